//! The robot's own map for localisation: every horizontal scan taken at a well-localised pose
//! is drawn into a grid (the outline between neighbouring returns, one outline point with its
//! normal per cell), and each new scan is matched against that outline: point-to-line ICP in
//! which each point's partner is looked up in the grid instead of in the previous scan.
//!
//! Matching a scan against the map of everything seen so far, instead of against the previous
//! key scan only, keeps the frame of an area fixed: a robot driving back along a link it
//! drove half an hour ago localises against the walls as it drew them then, so the link's
//! recorded path and the node coordinates stay where it believes they are. Scan-to-scan
//! matching hands every key scan's small heading error on to the next one, and a heading
//! error of 0.01 rad becomes 0.2 m across track after 20 m of corridor.
//!
//! Pose ξ = (x, y, θ); a scan point b (robot frame) lies at q = R(θ)·b + (x, y). With m the
//! outline point nearest q and n̂ its normal, the match minimises by Gauss–Newton, with a
//! Huber weight w on the residual and an odometry prior of weight λ on the position,
//!
//!   E(ξ) = Σᵢ w·rᵢ² + λ·|(x, y) − (x, y)_odometry|²,   rᵢ = n̂ᵢ · (qᵢ − mᵢ),
//!   ∂rᵢ/∂ξ = (n̂ₓ, n̂ᵧ, −n̂ₓ·(qᵧ − y) + n̂ᵧ·(qₓ − x)),
//!
//! over the pairs whose point lies near its partner both along and across the outline.

use usar_world::{Point2, Pose2, normalize_angle};

/// Neighbouring returns closer than this are on one surface: the outline is drawn between them.
const OUTLINE_GAP_M: f64 = 0.3;
/// Returns farther than this are not drawn: a heading error displaces far points most, and a
/// robot pitched by less than the obstacle threshold (3°) on the foot of a ramp sees the
/// floor ahead as a wall that moves with it, from 0.3 m / tan 3° ≈ 5.7 m on.
const DRAW_RANGE_M: f64 = 5.0;
/// Margin added around the points when the grid grows, metres.
const GROW_MARGIN_M: f64 = 10.0;
/// Gauss–Newton iterations, and the largest step per iteration.
const ITERATIONS: usize = 15;
const MAX_STEP_M: f64 = 0.05;
const MAX_STEP_RAD: f64 = 0.02;
/// Huber threshold of the weight, metres.
const HUBER_M: f64 = 0.05;
/// A pair counts only when the point lies within this of its partner along the outline (a
/// partner found past the drawn end of a wall, or on the wall round a corner, would pull the
/// robot along the corridor) ...
const ALONG_GATE_M: f64 = 0.15;
/// ... and within this across it (the first iterations, then [`ACROSS_GATE_FINE_M`]).
const ACROSS_GATE_M: f64 = 0.3;
const ACROSS_GATE_FINE_M: f64 = 0.1;
const COARSE_ITERATIONS: usize = 5;
/// Weight of the odometry prior on the position, per point used: along a corridor, where
/// the walls say nothing, odometry decides. Odometry moves the robot by a few millimetres
/// of error per step, so the prior is strong (0.3: a well-seen wall still corrects most of
/// an error within a few steps); at 0.02, a few pairs on door jambs slid the estimate 2 m
/// along the Willow Garage corridors.
const PRIOR_WEIGHT: f64 = 0.3;
/// At least this many points must lie within [`CLOSE_M`] of the outline after the match.
const MIN_CLOSE_POINTS: usize = 40;
const CLOSE_M: f64 = 0.08;
/// A correction farther than this from odometry is a false match.
const MAX_JUMP_M: f64 = 0.3;
const MAX_TURN_RAD: f64 = 0.15;
/// No outline point within reach of a cell.
const NONE: u32 = u32::MAX;

/// An outline point and its unit normal.
#[derive(Clone, Copy, Debug)]
struct Mark {
    at: Point2,
    normal: Point2,
}

/// A growable grid: per cell, the outline point nearest its centre (within reach).
#[derive(Clone, Debug)]
pub struct ScanMap {
    resolution_m: f64,
    reach_m: f64,
    /// World coordinates of the lower-left corner of cell (0, 0).
    origin: Point2,
    width: usize,
    height: usize,
    /// Whether an outline point lies in the cell.
    drawn: Vec<bool>,
    /// Index into `marks` of the outline point nearest the cell centre, or [`NONE`].
    nearest: Vec<u32>,
    /// Its distance from the cell centre.
    distance: Vec<f32>,
    marks: Vec<Mark>,
}

impl ScanMap {
    /// An empty map of `resolution_m` cells whose partner search reaches `reach_m`.
    pub fn new(resolution_m: f64, reach_m: f64) -> Self {
        Self {
            resolution_m,
            reach_m,
            origin: Point2::default(),
            width: 0,
            height: 0,
            drawn: Vec::new(),
            nearest: Vec::new(),
            distance: Vec::new(),
            marks: Vec::new(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.marks.is_empty()
    }

    /// Outline points drawn (one per cell).
    pub fn len(&self) -> usize {
        self.marks.len()
    }

    /// Draws a scan taken at `pose`: `beams` in beam order (robot frame, `None` = no return).
    pub fn insert(&mut self, pose: Pose2, beams: &[Option<Point2>]) {
        let near = |b: &Option<Point2>| {
            b.filter(|p| p.x.hypot(p.y) <= DRAW_RANGE_M)
                .map(|p| pose.to_world(p))
        };
        let world: Vec<Option<Point2>> = beams.iter().map(near).collect();
        let (mut lo, mut hi) = (pose.position(), pose.position());
        for p in world.iter().flatten() {
            lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        self.ensure(lo, hi);
        let n = world.len();
        let here = pose.position();
        // The return of beam `j` when it is another beam's neighbour on one surface with `a`.
        let neighbour = |j: usize, i: usize, a: Point2| {
            (j % n != i)
                .then_some(world[j % n])
                .flatten()
                .filter(|b| a.distance(*b) < OUTLINE_GAP_M)
        };
        for (i, a) in world.iter().enumerate() {
            let Some(a) = *a else { continue };
            let next = neighbour(i + 1, i, a);
            let prev = neighbour(i + n - 1, i, a);
            // The normal: across the outline through the neighbours, or towards the robot
            // for a lone return.
            let tangent = match (prev, next) {
                (Some(p), Some(q)) => Point2::new(q.x - p.x, q.y - p.y),
                (Some(p), None) => Point2::new(a.x - p.x, a.y - p.y),
                (None, Some(q)) => Point2::new(q.x - a.x, q.y - a.y),
                (None, None) => Point2::new(a.y - here.y, here.x - a.x),
            };
            self.draw(a, tangent);
            if let Some(b) = next {
                let gap = a.distance(b);
                let steps = (gap / (self.resolution_m / 2.0)).ceil() as usize;
                let t = Point2::new(b.x - a.x, b.y - a.y);
                for k in 1..steps {
                    let f = k as f64 / steps as f64;
                    self.draw(Point2::new(a.x + t.x * f, a.y + t.y * f), t);
                }
            }
        }
    }

    /// The outline point nearest `p` (looked up at p's cell) and its normal.
    fn partner(&self, p: Point2) -> Option<Mark> {
        let r = self.resolution_m;
        let cx = ((p.x - self.origin.x) / r).floor();
        let cy = ((p.y - self.origin.y) / r).floor();
        if cx < 0.0 || cy < 0.0 || cx >= self.width as f64 || cy >= self.height as f64 {
            return None;
        }
        let i = self.nearest[cy as usize * self.width + cx as usize];
        (i != NONE).then(|| self.marks[i as usize])
    }

    /// Distance from `p` to the outline point found as its partner, or `None`.
    pub fn distance_at(&self, p: Point2) -> Option<f64> {
        self.partner(p).map(|m| m.at.distance(p))
    }

    /// The pose at which `points` (robot frame) fit the map best, starting from `guess`;
    /// `None` when too few points lie on the map afterwards or the fit is far from the guess.
    pub fn match_scan(&self, points: &[Point2], guess: Pose2) -> Option<Pose2> {
        if self.is_empty() {
            return None;
        }
        let mut t = guess;
        for iteration in 0..ITERATIONS {
            let across_gate = if iteration < COARSE_ITERATIONS {
                ACROSS_GATE_M
            } else {
                ACROSS_GATE_FINE_M
            };
            let mut h = [[0.0f64; 3]; 3];
            let mut g = [0.0f64; 3];
            let mut used = 0usize;
            let frame = t.body_to_world();
            for &b in points {
                let q = frame.apply(b);
                let Some(m) = self.partner(q) else { continue };
                let n = m.normal;
                let (dx, dy) = (q.x - m.at.x, q.y - m.at.y);
                let r = n.x * dx + n.y * dy;
                let along = -n.y * dx + n.x * dy;
                if along.abs() > ALONG_GATE_M || r.abs() > across_gate {
                    continue;
                }
                let d = r.abs();
                let w = if d <= HUBER_M { 1.0 } else { HUBER_M / d };
                let jac = [n.x, n.y, -n.x * (q.y - t.y) + n.y * (q.x - t.x)];
                for a in 0..3 {
                    g[a] += w * jac[a] * r;
                    for c in 0..3 {
                        h[a][c] += w * jac[a] * jac[c];
                    }
                }
                used += 1;
            }
            if used < MIN_CLOSE_POINTS {
                return None;
            }
            // The odometry prior on the position (E += λ·|p − p_odometry|²) and a little
            // Levenberg damping on the heading.
            let prior = PRIOR_WEIGHT * used as f64;
            h[0][0] += prior;
            h[1][1] += prior;
            g[0] += prior * (t.x - guess.x);
            g[1] += prior * (t.y - guess.y);
            h[2][2] += 1e-3 * used as f64;
            let delta = solve3(h, [-g[0], -g[1], -g[2]])?;
            let step = delta[0].hypot(delta[1]);
            let scale = if step > MAX_STEP_M {
                MAX_STEP_M / step
            } else {
                1.0
            };
            let turn = delta[2].clamp(-MAX_STEP_RAD, MAX_STEP_RAD);
            t = Pose2::new(
                t.x + delta[0] * scale,
                t.y + delta[1] * scale,
                normalize_angle(t.theta + turn),
            );
            if step < 1e-4 && delta[2].abs() < 1e-5 {
                break;
            }
        }
        let frame = t.body_to_world();
        let close = points
            .iter()
            .filter(|&&b| {
                self.distance_at(frame.apply(b))
                    .is_some_and(|d| d < CLOSE_M)
            })
            .count();
        let jump = t.position().distance(guess.position());
        let turn = normalize_angle(t.theta - guess.theta).abs();
        (close >= MIN_CLOSE_POINTS && jump < MAX_JUMP_M && turn < MAX_TURN_RAD).then_some(t)
    }

    /// Grows the grid (keeping what is drawn) so that it covers `lo`–`hi` with the reach.
    fn ensure(&mut self, lo: Point2, hi: Point2) {
        let r = self.resolution_m;
        let inside = self.width > 0
            && lo.x >= self.origin.x + self.reach_m
            && lo.y >= self.origin.y + self.reach_m
            && hi.x < self.origin.x + self.width as f64 * r - self.reach_m
            && hi.y < self.origin.y + self.height as f64 * r - self.reach_m;
        if inside {
            return;
        }
        let (old_lo, old_hi) = if self.width > 0 {
            (
                self.origin,
                Point2::new(
                    self.origin.x + self.width as f64 * r,
                    self.origin.y + self.height as f64 * r,
                ),
            )
        } else {
            (lo, hi)
        };
        // Whole cells from the old origin, so that old cells keep their centres.
        let cells_below = |old: f64, new: f64| ((old - new) / r).ceil().max(0.0);
        let shift_x = cells_below(old_lo.x, lo.x - GROW_MARGIN_M);
        let shift_y = cells_below(old_lo.y, lo.y - GROW_MARGIN_M);
        let origin = Point2::new(old_lo.x - shift_x * r, old_lo.y - shift_y * r);
        let top = Point2::new(
            old_hi.x.max(hi.x + GROW_MARGIN_M),
            old_hi.y.max(hi.y + GROW_MARGIN_M),
        );
        let width = ((top.x - origin.x) / r).ceil() as usize;
        let height = ((top.y - origin.y) / r).ceil() as usize;
        let mut drawn = vec![false; width * height];
        let mut nearest = vec![NONE; width * height];
        let mut distance = vec![f32::INFINITY; width * height];
        let (sx, sy) = (shift_x as usize, shift_y as usize);
        for y in 0..self.height {
            let from = y * self.width..(y + 1) * self.width;
            let to = (y + sy) * width + sx..(y + sy) * width + sx + self.width;
            drawn[to.clone()].copy_from_slice(&self.drawn[from.clone()]);
            nearest[to.clone()].copy_from_slice(&self.nearest[from.clone()]);
            distance[to].copy_from_slice(&self.distance[from]);
        }
        self.origin = origin;
        self.width = width;
        self.height = height;
        self.drawn = drawn;
        self.nearest = nearest;
        self.distance = distance;
    }

    /// Draws the outline point `p` (tangent `tangent`) unless its cell has one already, and
    /// makes it the partner of the cells within reach that it is nearest to.
    fn draw(&mut self, p: Point2, tangent: Point2) {
        let r = self.resolution_m;
        let cx = ((p.x - self.origin.x) / r).floor();
        let cy = ((p.y - self.origin.y) / r).floor();
        if cx < 0.0 || cy < 0.0 || cx >= self.width as f64 || cy >= self.height as f64 {
            return;
        }
        let (cx, cy) = (cx as usize, cy as usize);
        let i = cy * self.width + cx;
        let len = tangent.x.hypot(tangent.y);
        if self.drawn[i] || len < 1e-9 {
            return;
        }
        self.drawn[i] = true;
        let index = self.marks.len() as u32;
        self.marks.push(Mark {
            at: p,
            normal: Point2::new(-tangent.y / len, tangent.x / len),
        });
        let k = (self.reach_m / r).ceil() as usize;
        for y in cy.saturating_sub(k)..(cy + k + 1).min(self.height) {
            let centre_y = self.origin.y + (y as f64 + 0.5) * r;
            for x in cx.saturating_sub(k)..(cx + k + 1).min(self.width) {
                let centre_x = self.origin.x + (x as f64 + 0.5) * r;
                let d = (centre_x - p.x).hypot(centre_y - p.y);
                let cell = y * self.width + x;
                if d <= self.reach_m && (d as f32) < self.distance[cell] {
                    self.distance[cell] = d as f32;
                    self.nearest[cell] = index;
                }
            }
        }
    }
}

/// Solves the 3 × 3 system `a·x = b` by Cramer's rule; `None` when singular.
pub(crate) fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if d.abs() < 1e-12 {
        return None;
    }
    let mut x = [0.0; 3];
    for (i, xi) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][i] = b[r];
        }
        *xi = det(m) / d;
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The outline of an L-shaped room seen from `pose`, one point every 2 cm, robot frame.
    fn room(pose: Pose2) -> Vec<Option<Point2>> {
        let corners = [
            (0.0, 0.0),
            (8.0, 0.0),
            (8.0, 3.0),
            (3.0, 3.0),
            (3.0, 7.0),
            (0.0, 7.0),
            (0.0, 0.0),
        ];
        let mut pts = Vec::new();
        for w in corners.windows(2) {
            let (a, b) = (Point2::new(w[0].0, w[0].1), Point2::new(w[1].0, w[1].1));
            let n = (a.distance(b) / 0.02) as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                let p = Point2::new(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t);
                pts.push(Some(pose.to_body(p)));
            }
        }
        pts
    }

    #[test]
    fn a_scan_is_matched_back_onto_the_map_it_drew() {
        let mut map = ScanMap::new(0.1, 0.5);
        let first = Pose2::new(1.5, 1.5, 0.3);
        map.insert(first, &room(first));
        let truth = Pose2::new(2.0, 1.8, 0.5);
        let scan: Vec<Point2> = room(truth).into_iter().flatten().step_by(5).collect();
        // Odometry is 0.15 m and 0.05 rad off. The odometry prior lets one scan correct part
        // of that; the scans that follow while the robot stands still correct the rest.
        let guess = Pose2::new(2.1, 1.7, 0.45);
        let mut fit = map.match_scan(&scan, guess).expect("a match");
        let error = |p: Pose2| p.position().distance(truth.position());
        assert!(error(fit) < 0.7 * error(guess), "{fit:?}");
        for _ in 0..20 {
            fit = map.match_scan(&scan, fit).expect("a match");
        }
        assert!(error(fit) < 0.01, "{fit:?}");
        assert!(
            normalize_angle(fit.theta - truth.theta).abs() < 0.005,
            "{fit:?}"
        );
        // Far outside the map nothing matches.
        assert_eq!(map.match_scan(&scan, Pose2::new(60.0, 60.0, 0.0)), None);
    }

    #[test]
    fn the_grid_grows_and_keeps_what_was_drawn() {
        let mut map = ScanMap::new(0.1, 0.3);
        let (a, b) = (Point2::new(1.02, 0.03), Point2::new(41.02, -29.97));
        map.insert(Pose2::new(0.0, 0.0, 0.0), &[Some(a)]);
        map.insert(
            Pose2::new(40.0, -30.0, 0.0),
            &[Some(Point2::new(1.02, 0.03))],
        );
        assert_eq!(map.len(), 2);
        assert!(map.distance_at(a).is_some_and(|d| d < 1e-9));
        assert!(map.distance_at(b).is_some_and(|d| d < 1e-9));
        assert!(
            map.distance_at(Point2::new(1.22, 0.03))
                .is_some_and(|d| (d - 0.2).abs() < 1e-9)
        );
        assert_eq!(map.distance_at(Point2::new(20.0, -15.0)), None);
    }
}

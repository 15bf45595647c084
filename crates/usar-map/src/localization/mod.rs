//! Where a robot thinks it is: its odometry, corrected by scan matching. Each horizontal laser
//! scan is matched by point-to-line ICP (Censi's PL-ICP without the closed form: Gauss–Newton
//! on the distances of the scan's points to the lines through their partners' neighbours)
//! either against a key scan taken earlier, or — with [`Localizer::with_map`] — against the
//! robot's own map of all the scans it took before ([`ScanMap`]). Only odometry and the
//! ranges are read: the pose stored in a [`LaserScan`](usar_readings::LaserScan) is never
//! used. The BTM builder (`usar-btm`) takes its node coordinates in this estimate, and the
//! exploration team (`usar-team`) can use it in place of the localization oracle.
//!
//! Odometry alone drifts by several degrees of heading over a course (the simulator's
//! rotation noise is 0.02 rad per √rad turned), which would put far nodes metres away.
//! While the robot is on an obstacle the horizontal laser sees the rising floor ahead (or
//! behind) as a wall that moves with the robot, and ICP would hold the robot back: odometry
//! alone carries it across. Back on level floor, the heading is corrected from the direction
//! of the straight walls to its sides, compared with the last key scan before the obstacle.
//!
//! - [`Localizer`]: [`new`](Localizer::new), [`with_map`](Localizer::with_map),
//!   [`predict`](Localizer::predict) with each odometry reading,
//!   [`correct`](Localizer::correct) with each scan, [`pose`](Localizer::pose);
//! - [`ScanView`]: a [`LaserScan`](usar_readings::LaserScan) as points in the robot frame
//!   ([`ScanView::from_scan`]), and the clearances measured on it ([`SideClearance`]);
//! - [`ScanMap`]: the robot's own map of scan outlines, matched against;
//! - [`compose`] and [`relative`]: poses in each other's frames.
//!
//! # Example
//!
//! A robot in a 6 m × 4 m room: its odometry under-reports a move by 5 cm and 0.05 rad, and
//! the scan it takes there pulls the estimate back onto the truth.
//!
//! ```
//! use std::f64::consts::{PI, TAU};
//! use usar_map::localization::{Localizer, ScanView, compose, relative};
//! use usar_readings::LaserScan;
//! use usar_world::{Pose2, normalize_angle};
//!
//! // The room's walls, as segments (x₀, y₀) – (x₁, y₁).
//! const WALLS: [((f64, f64), (f64, f64)); 4] = [
//!     ((0.0, 0.0), (6.0, 0.0)),
//!     ((6.0, 0.0), (6.0, 4.0)),
//!     ((6.0, 4.0), (0.0, 4.0)),
//!     ((0.0, 4.0), (0.0, 0.0)),
//! ];
//!
//! /// The scan a robot really at `truth` takes: 360 beams, one per degree from behind it,
//! /// cast against the walls. `stamped` is the pose it stamps the scan with (its odometry).
//! fn scan(truth: Pose2, stamped: Pose2) -> LaserScan {
//!     let increment = TAU / 360.0;
//!     let ranges_m = (0..360)
//!         .map(|i| {
//!             let (s, c) = (truth.theta - PI + f64::from(i) * increment).sin_cos();
//!             let mut nearest = f64::INFINITY;
//!             for ((ax, ay), (bx, by)) in WALLS {
//!                 // truth + t·(c, s) = a + u·(b − a), with t > 0 and 0 ≤ u ≤ 1.
//!                 let (ex, ey) = (bx - ax, by - ay);
//!                 let (wx, wy) = (ax - truth.x, ay - truth.y);
//!                 let det = ex * s - ey * c;
//!                 if det.abs() < 1e-12 {
//!                     continue;
//!                 }
//!                 let t = (ex * wy - ey * wx) / det;
//!                 let u = (c * wy - s * wx) / det;
//!                 if t > 0.0 && (0.0..=1.0).contains(&u) {
//!                     nearest = nearest.min(t);
//!                 }
//!             }
//!             nearest as f32
//!         })
//!         .collect();
//!     LaserScan {
//!         pose: stamped,
//!         angle_min_rad: -PI,
//!         angle_increment_rad: increment,
//!         max_range_m: 20.0,
//!         ranges_m,
//!     }
//! }
//!
//! // Start: the estimate and the odometry agree, and the first scan is the key scan.
//! let start = Pose2::new(2.0, 2.0, 0.1);
//! let mut localizer = Localizer::new(start, start, true, 1.0, 0.5);
//! localizer.correct(&ScanView::from_scan(&scan(start, start)), false);
//!
//! // The robot drives to `truth`; odometry reports 5 cm less travel and 0.05 rad less turn.
//! let truth = Pose2::new(2.5, 2.1, 0.2);
//! let odometry = Pose2::new(2.45, 2.1, 0.15);
//! localizer.predict(odometry);
//! let predicted = localizer.pose();
//! localizer.correct(&ScanView::from_scan(&scan(truth, odometry)), false);
//! let corrected = localizer.pose();
//!
//! let off = |p: Pose2| p.position().distance(truth.position());
//! let turned_off = |p: Pose2| normalize_angle(p.theta - truth.theta).abs();
//! assert!(off(predicted) > 0.04 && turned_off(predicted) > 0.04);
//! assert!(off(corrected) < 0.2 * off(predicted), "{corrected:?}");
//! assert!(turned_off(corrected) < 0.2 * turned_off(predicted), "{corrected:?}");
//! assert_eq!(localizer.matched, 1);
//!
//! // The move since the start, in the start's frame, and back.
//! let moved = relative(start, corrected);
//! assert!(compose(start, moved).position().distance(corrected.position()) < 1e-12);
//! ```

pub mod scan;
pub mod scan_map;

pub use self::scan::{ScanView, SideClearance};
pub use self::scan_map::ScanMap;

use self::scan_map::solve3;
use usar_world::{Point2, Pose2, normalize_angle};

/// a ⊕ b: pose `b` given in the frame of `a`, expressed in the frame `a` is given in.
pub fn compose(a: Pose2, b: Pose2) -> Pose2 {
    let (s, c) = a.theta.sin_cos();
    Pose2::new(
        a.x + c * b.x - s * b.y,
        a.y + s * b.x + c * b.y,
        normalize_angle(a.theta + b.theta),
    )
}

/// a⁻¹ ⊕ b: pose `b` in the frame of `a`.
pub fn relative(a: Pose2, b: Pose2) -> Pose2 {
    let p = a.to_body(b.position());
    Pose2::new(p.x, p.y, normalize_angle(b.theta - a.theta))
}

struct KeyScan {
    pose: Pose2,
    beams: Vec<Option<Point2>>,
    angle_min_rad: f64,
    angle_increment_rad: f64,
}

/// Cell size of the robot's map, metres (the residual is point to line: the cell size only
/// bounds how far the partner found may be from the nearest one).
pub const MAP_RESOLUTION_M: f64 = 0.1;
/// How far from a cell its partner outline point is looked for, metres: larger than any
/// correction accepted.
pub const MAP_REACH_M: f64 = 0.5;
/// The scan is drawn into the map after this distance driven or this turn since it was last
/// drawn: a new corridor is in the map before the robot has driven far into it.
pub const MAP_DRAW_DISTANCE_M: f64 = 0.25;
pub const MAP_DRAW_ANGLE_RAD: f64 = 0.25;

/// Odometry with scan-matching corrections.
pub struct Localizer {
    pose: Pose2,
    last_odometry: Pose2,
    /// The robot's map (drawn on level floor only) and the pose it was last drawn from, when
    /// matching against the map instead of the key scan.
    map: Option<ScanMap>,
    drawn_at: Option<Pose2>,
    /// Always taken on level floor.
    key: Option<KeyScan>,
    /// Whether the last scan was taken on an obstacle.
    on_obstacle: bool,
    /// The last scan taken on level floor before an obstacle, with its pose.
    last_level: Option<KeyScan>,
    /// Where the robot came back onto level floor, while the heading is not corrected yet.
    level_again_at: Option<Point2>,
    scan_matching: bool,
    keyframe_distance_m: f64,
    keyframe_angle_rad: f64,
    /// Scans matched and scans whose match was rejected.
    pub matched: u64,
    pub rejected: u64,
}

impl Localizer {
    pub fn new(
        start: Pose2,
        odometry: Pose2,
        scan_matching: bool,
        keyframe_distance_m: f64,
        keyframe_angle_rad: f64,
    ) -> Self {
        Self {
            pose: start,
            last_odometry: odometry,
            map: None,
            drawn_at: None,
            key: None,
            on_obstacle: false,
            last_level: None,
            level_again_at: None,
            scan_matching,
            keyframe_distance_m,
            keyframe_angle_rad,
            matched: 0,
            rejected: 0,
        }
    }

    /// Matches against the robot's own map instead of the last key scan.
    pub fn with_map(mut self) -> Self {
        self.map = Some(ScanMap::new(MAP_RESOLUTION_M, MAP_REACH_M));
        self
    }

    /// The current estimate.
    pub fn pose(&self) -> Pose2 {
        self.pose
    }

    /// Applies the motion odometry measured since the last call.
    pub fn predict(&mut self, odometry: Pose2) {
        let delta = relative(self.last_odometry, odometry);
        self.pose = compose(self.pose, delta);
        self.last_odometry = odometry;
    }

    /// Corrects the estimate with `scan`, taken on an obstacle or on level floor.
    pub fn correct(&mut self, scan: &ScanView, on_obstacle: bool) {
        if !self.scan_matching {
            return;
        }
        if on_obstacle {
            // Odometry alone: rising floor seen at a slant spoils even the side walls.
            self.on_obstacle = true;
            return;
        }
        if std::mem::take(&mut self.on_obstacle) {
            self.level_again_at = Some(self.pose.position());
        }
        if let Some(since) = self.level_again_at {
            // Back on level floor: once the obstacle is far enough behind not to show in the
            // side sectors, the heading from the side walls as they were in the last level
            // scan before it (walls' directions do not depend on where they are seen from),
            // then a fresh key scan. Odometry until then.
            if self.pose.position().distance(since) < BRIDGE_DELAY_M {
                return;
            }
            let corrected = self
                .last_level
                .as_ref()
                .and_then(|before| match_heading(before, scan, self.pose.theta));
            match corrected {
                Some(theta) => {
                    self.pose.theta = theta;
                    self.matched += 1;
                }
                // Tried again on the next scans, up to a limit.
                None if self.pose.position().distance(since) < BRIDGE_DELAY_M + BRIDGE_TRIES_M => {
                    self.rejected += 1;
                    return;
                }
                None => self.rejected += 1,
            }
            self.level_again_at = None;
            self.take_key(scan);
            self.remember_level(scan);
            return;
        }
        if self.map.is_some() {
            self.correct_on_map(scan);
            self.remember_level(scan);
            return;
        }
        let Some(key) = &self.key else {
            self.take_key(scan);
            return;
        };
        let guess = relative(key.pose, self.pose);
        match match_scan(key, scan, guess) {
            Some(t) => {
                self.pose = compose(key.pose, t);
                self.matched += 1;
            }
            None => self.rejected += 1,
        }
        let moved = self.pose.position().distance(key.pose.position());
        let turned = normalize_angle(self.pose.theta - key.pose.theta).abs();
        if moved > self.keyframe_distance_m || turned > self.keyframe_angle_rad {
            self.take_key(scan);
        }
        self.remember_level(scan);
    }

    fn snapshot(&self, scan: &ScanView) -> KeyScan {
        KeyScan {
            pose: self.pose,
            beams: scan.beams.clone(),
            angle_min_rad: scan.angle_min_rad,
            angle_increment_rad: scan.angle_increment_rad,
        }
    }

    /// Keeps `scan` as the last one on level floor, reusing the buffer of the one before.
    fn remember_level(&mut self, scan: &ScanView) {
        match &mut self.last_level {
            Some(k) => {
                k.pose = self.pose;
                k.beams.clone_from(&scan.beams);
                k.angle_min_rad = scan.angle_min_rad;
                k.angle_increment_rad = scan.angle_increment_rad;
            }
            None => self.last_level = Some(self.snapshot(scan)),
        }
    }

    fn take_key(&mut self, scan: &ScanView) {
        self.key = Some(self.snapshot(scan));
    }

    /// Matches `scan` against the map, then draws it when the robot has moved on enough.
    fn correct_on_map(&mut self, scan: &ScanView) {
        let Some(map) = &mut self.map else { return };
        if !map.is_empty() {
            match map.match_scan(&scan.points, self.pose) {
                Some(pose) => {
                    self.pose = pose;
                    self.matched += 1;
                }
                None => self.rejected += 1,
            }
        }
        let due = self.drawn_at.is_none_or(|at| {
            self.pose.position().distance(at.position()) > MAP_DRAW_DISTANCE_M
                || normalize_angle(self.pose.theta - at.theta).abs() > MAP_DRAW_ANGLE_RAD
        });
        if due {
            map.insert(self.pose, &scan.beams);
            self.drawn_at = Some(self.pose);
        }
    }
}
/// Beams searched either side of the projected one.
const SEARCH_BEAMS: i64 = 3;
const ITERATIONS: usize = 12;
const MIN_PAIRS: usize = 40;
/// Level distance driven after an obstacle before its heading is corrected, metres.
const BRIDGE_DELAY_M: f64 = 0.6;
/// Distance over which the heading correction is tried again, metres.
const BRIDGE_TRIES_M: f64 = 1.5;
/// A key point farther than this from the line through its neighbours is on a corner.
const COLLINEAR_M: f64 = 0.02;
/// tan 50°: "to the side" is within 40° of ±90°.
const SIDE_TAN: f64 = 1.192;
/// Side walls are used for the heading only when straight to within this, metres ...
const WALL_RESIDUAL_M: f64 = 0.03;
/// ... and seen by at least this many beams, within this lateral distance.
const WALL_MIN_POINTS: usize = 15;
const WALL_MAX_DISTANCE_M: f64 = 3.0;
/// The headings given by the left and the right wall must agree within this, radians.
const WALL_AGREEMENT_RAD: f64 = 0.008;
/// Side-wall returns are kept within this of their median lateral distance, metres.
const WALL_BAND_M: f64 = 0.1;

/// Direction (robot frame, modulo π) of the straight wall on one side, if there is one.
fn side_wall_direction(points: impl Iterator<Item = Point2>, left: bool) -> Option<f64> {
    let pts: Vec<Point2> = points
        .filter(|p| {
            (p.y > 0.0) == left
                && p.y.abs() > p.x.abs() * SIDE_TAN
                && p.y.abs() < WALL_MAX_DISTANCE_M
        })
        .collect();
    // Keep the wall: returns much nearer than the median lateral distance are the rising
    // floor of an obstacle seen at a slant.
    let mut lateral: Vec<f64> = pts.iter().map(|p| p.y.abs()).collect();
    lateral.sort_by(f64::total_cmp);
    let median = *lateral.get(lateral.len() / 2)?;
    let pts: Vec<Point2> = pts
        .into_iter()
        .filter(|p| (p.y.abs() - median).abs() < WALL_BAND_M)
        .collect();
    if pts.len() < WALL_MIN_POINTS {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.x / n, a.1 + p.y / n));
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for p in &pts {
        let (dx, dy) = (p.x - mx, p.y - my);
        sxx += dx * dx;
        syy += dy * dy;
        sxy += dx * dy;
    }
    // Principal direction and the spread across it (the smaller eigenvalue).
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let mean = (sxx + syy) / 2.0;
    let diff = ((sxx - syy) / 2.0).hypot(sxy);
    let across = ((mean - diff) / n).max(0.0).sqrt();
    (across < WALL_RESIDUAL_M).then_some(angle)
}

/// The heading at which the straight side walls of `scan` have the directions they had in
/// `key`; the candidate nearest `predicted` (walls are directions modulo π).
fn match_heading(key: &KeyScan, scan: &ScanView, predicted: f64) -> Option<f64> {
    let mut corrections = Vec::new();
    for left in [true, false] {
        let now = side_wall_direction(scan.points.iter().copied(), left);
        let then = side_wall_direction(key.beams.iter().flatten().copied(), left);
        if let (Some(now), Some(then)) = (now, then) {
            let theta = key.pose.theta + then - now;
            // Nearest to the prediction modulo π.
            let d = normalize_angle(2.0 * (theta - predicted)) / 2.0;
            corrections.push(d);
        }
    }
    // Both walls, agreeing: a wall fit spoilt by the rising floor seen at a slant disagrees.
    if corrections.len() < 2 || (corrections[0] - corrections[1]).abs() > WALL_AGREEMENT_RAD {
        return None;
    }
    let mean = corrections.iter().sum::<f64>() / corrections.len() as f64;
    (mean.abs() < 0.1).then(|| normalize_angle(predicted + mean))
}

/// Pose of `scan` in the frame of `key`, starting from `guess`; `None` when too few points
/// correspond.
fn match_scan(key: &KeyScan, scan: &ScanView, guess: Pose2) -> Option<Pose2> {
    let n = key.beams.len() as i64;
    if n == 0 || key.angle_increment_rad <= 0.0 {
        return None;
    }
    let mut t = guess;
    let mut pairs = 0;
    for iteration in 0..ITERATIONS {
        let max_d = if iteration < 4 { 0.3 } else { 0.1 };
        let mut h = [[0.0f64; 3]; 3];
        let mut g = [0.0f64; 3];
        pairs = 0;
        for p in scan.points.iter().step_by(2) {
            let q = t.to_world(*p);
            let bearing = normalize_angle(q.y.atan2(q.x) - key.angle_min_rad);
            let j = (bearing.rem_euclid(std::f64::consts::TAU) / key.angle_increment_rad).round()
                as i64;
            let mut best: Option<(f64, i64, Point2)> = None;
            for k in j - SEARCH_BEAMS..=j + SEARCH_BEAMS {
                if let Some(m) = key.beams[k.rem_euclid(n) as usize] {
                    let d = m.distance_squared(q);
                    if best.is_none_or(|b| d < b.0) {
                        best = Some((d, k, m));
                    }
                }
            }
            let Some((d2, k, m)) = best else { continue };
            if d2 > max_d * max_d {
                continue;
            }
            // The line through the key point's two neighbours, used only where the three are
            // collinear: at a corner a one-sided neighbour would tilt the normal and bias the
            // heading.
            let (Some(a), Some(b)) = (
                key.beams[(k - 1).rem_euclid(n) as usize],
                key.beams[(k + 1).rem_euclid(n) as usize],
            ) else {
                continue;
            };
            let len = a.distance(b);
            if !(1e-6..0.4).contains(&len) {
                continue;
            }
            let normal = ((a.y - b.y) / len, (b.x - a.x) / len);
            if (normal.0 * (m.x - a.x) + normal.1 * (m.y - a.y)).abs() > COLLINEAR_M {
                continue;
            }
            let r = normal.0 * (q.x - m.x) + normal.1 * (q.y - m.y);
            let jac = [normal.0, normal.1, normal.0 * -q.y + normal.1 * q.x];
            for a in 0..3 {
                g[a] += jac[a] * r;
                for b in 0..3 {
                    h[a][b] += jac[a] * jac[b];
                }
            }
            pairs += 1;
        }
        if pairs < MIN_PAIRS {
            return None;
        }
        let damping = 0.01 * pairs as f64;
        for (a, row) in h.iter_mut().enumerate() {
            row[a] += damping;
        }
        let delta = solve3(h, [-g[0], -g[1], -g[2]])?;
        let (s, c) = delta[2].sin_cos();
        t = Pose2::new(
            c * t.x - s * t.y + delta[0],
            s * t.x + c * t.y + delta[1],
            normalize_angle(t.theta + delta[2]),
        );
        if delta[0].abs() + delta[1].abs() < 1e-5 && delta[2].abs() < 1e-6 {
            break;
        }
    }
    // A correction far from odometry is a false match.
    let jump = t.position().distance(guess.position());
    let turn = normalize_angle(t.theta - guess.theta).abs();
    (pairs >= MIN_PAIRS && jump < 0.3 && turn < 0.15).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_readings::LaserScan;

    /// A scan of a 6 × 4 m box seen from `pose` (box corners (0,0)–(6,4)).
    fn box_scan(pose: Pose2) -> ScanView {
        let n = 360;
        let inc = std::f64::consts::TAU / n as f64;
        let ranges = (0..n)
            .map(|i| {
                let a = pose.theta - std::f64::consts::PI + i as f64 * inc;
                let (s, c) = a.sin_cos();
                let mut best = f64::INFINITY;
                for (wall, dir, pos) in [(6.0, c, pose.x), (0.0, c, pose.x)] {
                    if dir.abs() > 1e-9 {
                        let t = (wall - pos) / dir;
                        if t > 0.0 {
                            best = best.min(t);
                        }
                    }
                }
                for (wall, dir, pos) in [(4.0, s, pose.y), (0.0, s, pose.y)] {
                    if dir.abs() > 1e-9 {
                        let t = (wall - pos) / dir;
                        if t > 0.0 {
                            best = best.min(t);
                        }
                    }
                }
                best as f32
            })
            .collect();
        ScanView::from_scan(&LaserScan {
            pose,
            angle_min_rad: -std::f64::consts::PI,
            angle_increment_rad: inc,
            max_range_m: 20.0,
            ranges_m: ranges,
        })
    }

    #[test]
    fn scan_matching_recovers_a_heading_error() {
        let start = Pose2::new(2.0, 2.0, 0.1);
        let truth = Pose2::new(2.5, 2.1, 0.2);
        let mut loc = Localizer::new(start, start, true, 1.0, 0.5);
        loc.correct(&box_scan(start), false);
        // Odometry says 0.05 rad less turn and 5 cm less travel than the truth.
        loc.predict(Pose2::new(2.45, 2.1, 0.15));
        loc.correct(&box_scan(truth), false);
        let p = loc.pose();
        assert!(p.position().distance(truth.position()) < 0.01, "{p:?}");
        assert!((p.theta - truth.theta).abs() < 0.002, "{p:?}");
    }

    #[test]
    fn matching_against_the_map_recovers_a_heading_error() {
        let start = Pose2::new(2.0, 2.0, 0.1);
        let truth = Pose2::new(2.5, 2.1, 0.2);
        let mut loc = Localizer::new(start, start, true, 1.0, 0.5).with_map();
        loc.correct(&box_scan(start), false);
        // Ten steps; odometry reports 80 % of each step's travel and turn.
        for k in 1..=10 {
            let f = f64::from(k) / 10.0;
            let at = |scale: f64| {
                Pose2::new(
                    start.x + (truth.x - start.x) * f * scale,
                    start.y + (truth.y - start.y) * f * scale,
                    start.theta + (truth.theta - start.theta) * f * scale,
                )
            };
            loc.predict(at(0.8));
            loc.correct(&box_scan(at(1.0)), false);
        }
        // Standing still, the scans that follow correct what the odometry prior held back.
        for _ in 0..10 {
            loc.correct(&box_scan(truth), false);
        }
        let p = loc.pose();
        assert!(p.position().distance(truth.position()) < 0.01, "{p:?}");
        assert!((p.theta - truth.theta).abs() < 0.002, "{p:?}");
    }

    #[test]
    fn compose_and_relative_are_inverse() {
        let a = Pose2::new(1.0, -2.0, 0.7);
        let b = Pose2::new(3.0, 0.5, -2.0);
        let r = compose(a, relative(a, b));
        assert!((r.x - b.x).abs() < 1e-12 && (r.y - b.y).abs() < 1e-12);
        assert!(normalize_angle(r.theta - b.theta).abs() < 1e-12);
    }
}

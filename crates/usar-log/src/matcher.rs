//! Correlative scan matching (E. Olson, "Real-Time Correlative Scan Matching", ICRA 2009): a
//! scan is placed where its points score best on a likelihood grid of everything drawn before,
//! searched exhaustively over a window of poses around the odometry prediction — not from a
//! guess that must be close, as ICP needs.
//!
//! - The likelihood of a point at cell c is p(c) ∝ exp(−d(c)² / 2σ²), d the distance to the
//!   nearest point drawn, kept as a byte 0–255 ([`MatcherParams::sigma_m`], out to 3σ).
//! - The score of a pose ξ is Σᵢ p(cell(R(θ)·bᵢ + t)) over the scan's points bᵢ.
//! - The search is Olson's multi-resolution one: the headings step by δθ = resolution /
//!   farthest point's range (the farthest point moves at most one cell), the translations by
//!   one cell. A low-resolution grid holds at each cell the largest value of the block of
//!   `block × block` cells from it, so its score of a block of translations bounds every score
//!   within the block from above; blocks are searched best-first and the search stops when no
//!   block's bound beats the best full-resolution score found: the result is the exhaustive
//!   search's.

use usar_world::{Point2, Pose2, normalize_angle};

/// Parameters of the matcher.
#[derive(Clone, Debug, PartialEq)]
pub struct MatcherParams {
    /// Cell size of the likelihood grid, metres.
    pub resolution_m: f64,
    /// σ of the likelihood kernel (range noise and cell size), metres.
    pub sigma_m: f64,
    /// Half-width of the translation window around the prediction, metres.
    pub window_m: f64,
    /// Half-width of the heading window, radians.
    pub window_rad: f64,
    /// Side of the low-resolution blocks, in cells.
    pub block: usize,
    /// A match is kept only when its score is at least this share of the best possible
    /// (every point on a drawn point).
    pub min_score_share: f64,
}

impl Default for MatcherParams {
    /// A 0.05 m grid; σ 0.1 m (a SICK's centimetres of range noise plus half a cell and the
    /// wall's roughness); a window of ±0.5 m and ±0.25 rad (14°), wider than odometry errs
    /// between scans half a metre apart; blocks of 4 × 4 cells.
    fn default() -> Self {
        Self {
            resolution_m: 0.05,
            sigma_m: 0.1,
            window_m: 0.5,
            window_rad: 0.25,
            block: 4,
            min_score_share: 0.2,
        }
    }
}

/// A byte grid that grows to hold what is drawn, cells keeping their place.
#[derive(Clone, Debug, Default)]
struct GrowGrid {
    /// Cell (0, 0)'s indices in the unbounded grid.
    col0: i64,
    row0: i64,
    width: usize,
    height: usize,
    values: Vec<u8>,
}

impl GrowGrid {
    #[inline]
    fn get(&self, col: i64, row: i64) -> u8 {
        let (c, r) = (col - self.col0, row - self.row0);
        if c < 0 || r < 0 || c >= self.width as i64 || r >= self.height as i64 {
            return 0;
        }
        self.values[r as usize * self.width + c as usize]
    }

    /// Makes the grid cover cells `lo..=hi` (with a margin when it grows).
    fn ensure(&mut self, lo: (i64, i64), hi: (i64, i64), margin: i64) {
        let inside = self.width > 0
            && lo.0 >= self.col0
            && lo.1 >= self.row0
            && hi.0 < self.col0 + self.width as i64
            && hi.1 < self.row0 + self.height as i64;
        if inside {
            return;
        }
        let (c0, r0) = if self.width > 0 {
            (self.col0.min(lo.0 - margin), self.row0.min(lo.1 - margin))
        } else {
            (lo.0 - margin, lo.1 - margin)
        };
        let (c1, r1) = if self.width > 0 {
            (
                (self.col0 + self.width as i64).max(hi.0 + margin + 1),
                (self.row0 + self.height as i64).max(hi.1 + margin + 1),
            )
        } else {
            (hi.0 + margin + 1, hi.1 + margin + 1)
        };
        let (width, height) = ((c1 - c0) as usize, (r1 - r0) as usize);
        let mut values = vec![0u8; width * height];
        for r in 0..self.height {
            let to = (r as i64 + self.row0 - r0) as usize * width + (self.col0 - c0) as usize;
            values[to..to + self.width]
                .copy_from_slice(&self.values[r * self.width..(r + 1) * self.width]);
        }
        *self = Self {
            col0: c0,
            row0: r0,
            width,
            height,
            values,
        };
    }

    /// Raises cell (col, row) to `v`; whether it rose.
    #[inline]
    fn raise(&mut self, col: i64, row: i64, v: u8) -> bool {
        let i = (row - self.row0) as usize * self.width + (col - self.col0) as usize;
        let rose = self.values[i] < v;
        if rose {
            self.values[i] = v;
        }
        rose
    }
}

/// The likelihood grid and its search.
#[derive(Clone, Debug)]
pub struct CorrelativeMatcher {
    params: MatcherParams,
    fine: GrowGrid,
    /// At each cell, the largest fine value over the `block × block` cells from it.
    coarse: GrowGrid,
    /// The kernel: (d_col, d_row, value) out to 3σ.
    kernel: Vec<(i64, i64, u8)>,
    /// Kept between scans: the scan's points in cells relative to the predicted position, one
    /// run of points per candidate heading, and the blocks of translations with their bounds.
    rotated: Vec<(i64, i64)>,
    blocks: Vec<(u64, usize, i64, i64)>,
}

impl CorrelativeMatcher {
    pub fn new(params: MatcherParams) -> Self {
        let r = params.resolution_m;
        let reach = (3.0 * params.sigma_m / r).ceil() as i64;
        let mut kernel = Vec::new();
        for dr in -reach..=reach {
            for dc in -reach..=reach {
                let d = (dc as f64).hypot(dr as f64) * r;
                let v = (255.0 * (-d * d / (2.0 * params.sigma_m * params.sigma_m)).exp()).round();
                if v >= 1.0 {
                    kernel.push((dc, dr, v as u8));
                }
            }
        }
        Self {
            params,
            fine: GrowGrid::default(),
            coarse: GrowGrid::default(),
            kernel,
            rotated: Vec::new(),
            blocks: Vec::new(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.fine.width == 0
    }

    fn cell(&self, p: Point2) -> (i64, i64) {
        let r = self.params.resolution_m;
        ((p.x / r).floor() as i64, (p.y / r).floor() as i64)
    }

    /// Draws `points` (laser frame) seen from `pose`.
    pub fn insert(&mut self, pose: Pose2, points: &[Point2]) {
        let frame = pose.body_to_world();
        let cells: Vec<(i64, i64)> = points.iter().map(|&b| self.cell(frame.apply(b))).collect();
        let Some(&first) = cells.first() else { return };
        let reach = self.kernel.iter().map(|k| k.0.abs()).max().unwrap_or(0);
        let block = self.params.block as i64;
        let (mut lo, mut hi) = (first, first);
        for &(c, r) in &cells {
            lo = (lo.0.min(c), lo.1.min(r));
            hi = (hi.0.max(c), hi.1.max(r));
        }
        let (lo, hi) = (
            (lo.0 - reach - block, lo.1 - reach - block),
            (hi.0 + reach, hi.1 + reach),
        );
        let margin = (10.0 / self.params.resolution_m) as i64;
        self.fine.ensure(lo, hi, margin);
        self.coarse.ensure(lo, hi, margin);
        for &(c, r) in &cells {
            for &(dc, dr, v) in &self.kernel {
                let (col, row) = (c + dc, r + dr);
                if self.fine.raise(col, row, v) {
                    // The coarse cells whose block holds this one.
                    for br in 0..block {
                        for bc in 0..block {
                            self.coarse.raise(col - bc, row - br, v);
                        }
                    }
                }
            }
        }
    }

    /// The pose near `predicted` at which `points` (laser frame) score best, with its score
    /// as a share of the best possible; `None` when the grid is empty or no pose reaches
    /// [`MatcherParams::min_score_share`].
    pub fn match_scan(&mut self, points: &[Point2], predicted: Pose2) -> Option<(Pose2, f64)> {
        if self.is_empty() || points.is_empty() {
            return None;
        }
        let (mut rotated, mut blocks) = (
            std::mem::take(&mut self.rotated),
            std::mem::take(&mut self.blocks),
        );
        let found = self.search(points, predicted, &mut rotated, &mut blocks);
        (self.rotated, self.blocks) = (rotated, blocks);
        found
    }

    fn search(
        &self,
        points: &[Point2],
        predicted: Pose2,
        rotated: &mut Vec<(i64, i64)>,
        blocks: &mut Vec<(u64, usize, i64, i64)>,
    ) -> Option<(Pose2, f64)> {
        let p = &self.params;
        let r = p.resolution_m;
        let n = points.len();
        let farthest = points.iter().map(|b| b.x.hypot(b.y)).fold(r, f64::max);
        let step = (r / farthest).clamp(1e-4, 0.05);
        let headings = (p.window_rad / step).ceil() as i64;
        let window = (p.window_m / r).ceil() as i64;
        let block = p.block as i64;
        let origin = self.cell(predicted.position());
        let theta =
            |k: usize| normalize_angle(predicted.theta + (k as i64 - headings) as f64 * step);
        rotated.clear();
        for k in 0..(2 * headings + 1) as usize {
            let frame = Pose2::new(predicted.x, predicted.y, theta(k)).body_to_world();
            rotated.extend(points.iter().map(|&b| {
                let c = self.cell(frame.apply(b));
                (c.0 - origin.0, c.1 - origin.1)
            }));
        }
        let score = |grid: &GrowGrid, k: usize, dc: i64, dr: i64| -> u64 {
            rotated[k * n..(k + 1) * n]
                .iter()
                .map(|&(c, r)| u64::from(grid.get(origin.0 + c + dc, origin.1 + r + dr)))
                .sum()
        };
        // Every block of translations at every heading, with its bound.
        blocks.clear();
        for k in 0..(2 * headings + 1) as usize {
            let mut dr = -window;
            while dr <= window {
                let mut dc = -window;
                while dc <= window {
                    blocks.push((score(&self.coarse, k, dc, dr), k, dc, dr));
                    dc += block;
                }
                dr += block;
            }
        }
        blocks.sort_unstable_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        let mut best: Option<(u64, usize, i64, i64)> = None;
        for &(bound, k, dc0, dr0) in blocks.iter() {
            if best.is_some_and(|b| bound <= b.0) {
                break;
            }
            for dr in dr0..(dr0 + block).min(window + 1) {
                for dc in dc0..(dc0 + block).min(window + 1) {
                    let s = score(&self.fine, k, dc, dr);
                    if best.is_none_or(|b| s > b.0) {
                        best = Some((s, k, dc, dr));
                    }
                }
            }
        }
        let (s, k, dc, dr) = best?;
        let share = s as f64 / (255.0 * n as f64);
        (share >= p.min_score_share).then(|| {
            (
                Pose2::new(
                    predicted.x + dc as f64 * r,
                    predicted.y + dr as f64 * r,
                    theta(k),
                ),
                share,
            )
        })
    }
}

/// A pose tracked scan by scan: odometry predicts, the matcher corrects, the scan is drawn.
#[derive(Clone, Debug)]
pub struct Tracker {
    matcher: Option<CorrelativeMatcher>,
    pose: Option<Pose2>,
    last_odometry: Pose2,
    /// Scans matched, and scans whose match was rejected (odometry kept).
    pub matched: u64,
    pub rejected: u64,
}

impl Tracker {
    /// A tracker that matches with `params`, or follows odometry alone (`None`).
    pub fn new(params: Option<MatcherParams>) -> Self {
        Self {
            matcher: params.map(CorrelativeMatcher::new),
            pose: None,
            last_odometry: Pose2::default(),
            matched: 0,
            rejected: 0,
        }
    }

    /// The pose of a scan whose `points` (sensor frame) were taken at `odometry`; the first
    /// scan is at its odometry.
    pub fn update(&mut self, odometry: Pose2, points: &[Point2]) -> Pose2 {
        let predicted = match self.pose {
            Some(p) => usar_map::localization::compose(
                p,
                usar_map::localization::relative(self.last_odometry, odometry),
            ),
            None => odometry,
        };
        self.last_odometry = odometry;
        let pose = match &mut self.matcher {
            None => predicted,
            Some(m) => {
                let pose = match m.match_scan(points, predicted) {
                    Some((found, _)) => {
                        self.matched += 1;
                        found
                    }
                    None => {
                        self.rejected += u64::from(!m.is_empty());
                        predicted
                    }
                };
                m.insert(pose, points);
                pose
            }
        };
        self.pose = Some(pose);
        pose
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An L of walls seen from the origin; the same points seen from a pose 0.3 m and 0.1 rad
    /// off are put back where they were.
    #[test]
    fn a_displaced_scan_is_found_within_the_window() {
        let mut wall = Vec::new();
        for k in 0..60 {
            wall.push(Point2::new(4.0, -3.0 + 0.1 * f64::from(k)));
            wall.push(Point2::new(-2.0 + 0.1 * f64::from(k), 3.0));
        }
        let mut m = CorrelativeMatcher::new(MatcherParams::default());
        let truth = Pose2::new(1.0, 2.0, 0.3);
        m.insert(truth, &wall);
        let predicted = Pose2::new(1.3, 1.9, 0.4);
        let (found, share) = m.match_scan(&wall, predicted).unwrap();
        assert!(
            found.position().distance(truth.position()) < 0.06,
            "{found:?}"
        );
        assert!((found.theta - truth.theta).abs() < 0.01, "{found:?}");
        assert!(share > 0.9, "{share}");
        // Far outside the window: nothing scores enough.
        assert!(m.match_scan(&wall, Pose2::new(6.0, -5.0, 2.0)).is_none());
    }
}

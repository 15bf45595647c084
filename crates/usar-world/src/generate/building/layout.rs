//! The corridor skeleton of a floor, in whole grid cells: east–west corridors, the north–south
//! corridor pieces that join them, the rows of rooms between them, and the junctions.
//!
//! Seen from the south, a floor with `n` east–west corridors is the stack
//!
//! ```text
//! exterior wall | row | wall | C0 | wall | row | wall | row | wall | C1 | … | C(n-1) | wall | row | exterior wall
//! ```
//!
//! Every east–west corridor runs the whole interior width. Between two neighbouring corridors lie
//! two rows of rooms back to back (each opening onto its own corridor); along the north and south
//! exterior walls lies one row. North–south corridor pieces cross a band between two corridors
//! on "lines" (fixed x positions), so that pieces on the same line in neighbouring bands meet the
//! corridor between them in a crossing, and a lone piece meets it in a T junction. Optional ring
//! pieces along the east or west end wall turn the corridor ends into corners and T junctions;
//! otherwise the corridors end at the end walls in dead ends. Optional stubs run from the
//! outermost corridors to the north or south exterior wall (exits: dead ends).

use super::params::BuildingParams;
use crate::scene::JunctionKind;
use rand::Rng;
use rand_pcg::Pcg64Mcg;

/// A half-open rectangle of grid cells: columns `x0..x1`, rows `y0..y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct CellRect {
    pub x0: i32,
    pub y0: i32,
    pub x1: i32,
    pub y1: i32,
}

impl CellRect {
    pub fn new(x0: i32, y0: i32, x1: i32, y1: i32) -> Self {
        Self { x0, y0, x1, y1 }
    }

    pub fn width(&self) -> i32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> i32 {
        self.y1 - self.y0
    }

    pub fn area(&self) -> i64 {
        i64::from(self.width().max(0)) * i64::from(self.height().max(0))
    }

    pub fn contains(&self, col: i32, row: i32) -> bool {
        col >= self.x0 && col < self.x1 && row >= self.y0 && row < self.y1
    }

    pub fn intersects(&self, o: &CellRect) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    /// The rectangle grown by `k` cells on every side.
    pub fn expanded(&self, k: i32) -> CellRect {
        CellRect::new(self.x0 - k, self.y0 - k, self.x1 + k, self.y1 + k)
    }

    /// The part of the rectangle inside `0..width × 0..height`.
    pub fn clipped(&self, width: i32, height: i32) -> CellRect {
        CellRect::new(
            self.x0.max(0),
            self.y0.max(0),
            self.x1.min(width),
            self.y1.min(height),
        )
    }

    /// Centre, in cell units (cell (c, r) spans [c, c + 1) × [r, r + 1)).
    pub fn centre(&self) -> (f64, f64) {
        (
            f64::from(self.x0 + self.x1) / 2.0,
            f64::from(self.y0 + self.y1) / 2.0,
        )
    }
}

/// A side of a rectangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Side {
    North,
    South,
    West,
    East,
}

/// A straight corridor (one corridor room of the semantic layer).
#[derive(Clone, Debug)]
pub(super) struct CorridorPlan {
    pub rect: CellRect,
    /// Indices of the corridors this one meets.
    pub meets: Vec<usize>,
}

/// A stretch of a row of rooms between two cross corridors (or a cross corridor and an end
/// wall); all its rooms open onto `front_corridor` through the wall on side `front`.
#[derive(Clone, Debug)]
pub(super) struct Segment {
    pub rect: CellRect,
    pub front: Side,
    pub front_corridor: usize,
    /// The segment of the other row of the same band with the same x extent (back to back).
    pub twin: Option<usize>,
    /// The north–south corridor just west (east) of the segment, across one wall.
    pub west_corridor: Option<usize>,
    pub east_corridor: Option<usize>,
}

/// A junction of the corridor network; its position is in cell units.
#[derive(Clone, Copy, Debug)]
pub(super) struct JunctionPlan {
    pub kind: JunctionKind,
    pub x: f64,
    pub y: f64,
}

/// The corridor skeleton of a floor.
#[derive(Clone, Debug)]
pub(super) struct Skeleton {
    pub width: i32,
    pub height: i32,
    pub wall: i32,
    pub corridor_width: i32,
    /// East–west corridors first (south to north), then the north–south pieces (by band, west
    /// to east).
    pub corridors: Vec<CorridorPlan>,
    pub east_west_count: usize,
    pub segments: Vec<Segment>,
    pub junctions: Vec<JunctionPlan>,
}

impl Skeleton {
    pub fn corridor_area_cells(&self) -> i64 {
        self.corridors.iter().map(|c| c.rect.area()).sum()
    }
}

/// The random choices of a floor plan that do not depend on the corridor width, so that the
/// width can be tuned without redrawing them.
struct Topology {
    east_west: usize,
    depth_weights: Vec<f64>,
    line_fractions: Vec<f64>,
    /// `present[band][line]`: band 0 is south of C0, band `east_west` north of the last one.
    present: Vec<Vec<bool>>,
    ring_west: bool,
    ring_east: bool,
}

/// Grid dimensions and cell counts derived from the parameters.
pub(super) struct CellScale {
    pub width: i32,
    pub height: i32,
    pub wall: i32,
    pub resolution_m: f64,
}

impl CellScale {
    pub fn new(p: &BuildingParams) -> Self {
        let r = p.resolution_m;
        Self {
            width: (p.width_m / r).round().max(1.0) as i32,
            height: (p.height_m / r).round().max(1.0) as i32,
            wall: (p.wall_thickness_m / r).round().max(1.0) as i32,
            resolution_m: r,
        }
    }

    /// A length in metres as a whole number of cells (at least 1).
    pub fn cells(&self, metres: f64) -> i32 {
        (metres / self.resolution_m).round().max(1.0) as i32
    }

    pub fn cell_area_m2(&self) -> f64 {
        self.resolution_m * self.resolution_m
    }
}

/// Topologies drawn per floor; the one whose best corridor width comes closest to the corridor
/// share wins (when the width range alone cannot reach the share, e.g. a mall with many cross
/// galleries and a 4 m minimum gallery width).
const TOPOLOGY_DRAWS: usize = 4;

/// Draws the skeleton: [`TOPOLOGY_DRAWS`] topologies, then for each the corridor widths (in
/// whole cells, inside `corridor_width_m`); the pair whose predicted corridor share is closest to
/// `label_shares.corridor` wins.
/// `predict_share` maps a candidate skeleton to its predicted corridor share.
pub(super) fn plan_skeleton(
    p: &BuildingParams,
    scale: &CellScale,
    rng: &mut Pcg64Mcg,
    predict_share: impl Fn(&Skeleton) -> f64,
) -> Skeleton {
    let c_lo = scale.cells(p.corridor_width_m.min_m);
    let c_hi = scale.cells(p.corridor_width_m.max_m).max(c_lo);
    let c_nominal = (c_lo + c_hi) / 2;
    let interior_h = scale.height - 2 * scale.wall;
    let per_corridor = c_nominal + 2 * scale.cells(p.row_depth_m) + 3 * scale.wall;
    let mut east_west =
        ((f64::from(interior_h + scale.wall) / f64::from(per_corridor)).round() as usize).max(1);
    loop {
        let topologies: Vec<Topology> = (0..TOPOLOGY_DRAWS)
            .map(|_| Topology::draw(p, scale, east_west, rng))
            .collect();
        let best = topologies
            .iter()
            .flat_map(|t| (c_lo..=c_hi).filter_map(move |c| realize(t, p, scale, c)))
            .map(|s| ((predict_share(&s) - p.label_shares.corridor).abs(), s))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, skeleton)) = best {
            return skeleton;
        }
        let topology = &topologies[0];
        if east_west == 1 {
            // Nothing fits even one corridor with the configured depths: fall back to the
            // narrowest corridor and no depth limit (only reachable with extreme parameters).
            let relaxed = BuildingParams {
                min_row_depth_m: p.min_room_side_m,
                ..p.clone()
            };
            if let Some(s) = realize(topology, &relaxed, scale, c_lo) {
                return s;
            }
            let tiny = BuildingParams {
                min_row_depth_m: p.resolution_m,
                min_room_side_m: p.resolution_m,
                ..p.clone()
            };
            let c = c_lo.min((interior_h - 2 * scale.wall) / 3).max(1);
            if let Some(s) = realize(topology, &tiny, scale, c) {
                return s;
            }
            return single_corridor(scale, c);
        }
        east_west -= 1;
    }
}

/// A last-resort floor: one corridor along the middle and nothing else.
fn single_corridor(scale: &CellScale, c: i32) -> Skeleton {
    let y0 = (scale.height - c) / 2;
    let rect = CellRect::new(scale.wall, y0, scale.width - scale.wall, y0 + c);
    Skeleton {
        width: scale.width,
        height: scale.height,
        wall: scale.wall,
        corridor_width: c,
        corridors: vec![CorridorPlan {
            rect,
            meets: Vec::new(),
        }],
        east_west_count: 1,
        segments: Vec::new(),
        junctions: Vec::new(),
    }
}

impl Topology {
    fn draw(p: &BuildingParams, scale: &CellScale, east_west: usize, rng: &mut Pcg64Mcg) -> Self {
        let interior_w = f64::from(scale.width - 2 * scale.wall) * scale.resolution_m;
        let lines = ((interior_w / p.block_length_m).round() as usize).saturating_sub(1);
        let line_fractions: Vec<f64> = (0..lines)
            .map(|j| (j as f64 + 1.0 + rng.random_range(-0.2..=0.2)) / (lines as f64 + 1.0))
            .collect();
        let depth_weights = (0..2 * east_west)
            .map(|_| rng.random_range(0.85..=1.15))
            .collect();
        let ring = east_west >= 2;
        let ring_west = ring && rng.random_bool(p.ring_probability);
        let ring_east = ring && rng.random_bool(p.ring_probability);
        let mut present = vec![vec![false; lines]; east_west + 1];
        for band in present.iter_mut().take(east_west).skip(1) {
            for slot in band.iter_mut() {
                *slot = rng.random_bool(p.cross_corridor_probability);
            }
        }
        for band in [0, east_west] {
            if lines > 0 && rng.random_bool(p.stub_probability) {
                present[band][rng.random_range(0..lines)] = true;
            }
        }
        let mut t = Topology {
            east_west,
            depth_weights,
            line_fractions,
            present,
            ring_west,
            ring_east,
        };
        t.connect_every_band(rng);
        t.ensure_crossing(rng);
        t
    }

    /// Every band between two east–west corridors needs a cross corridor, or the corridor
    /// network falls apart.
    fn connect_every_band(&mut self, rng: &mut Pcg64Mcg) {
        let lines = self.line_fractions.len();
        for band in 1..self.east_west {
            if self.ring_west || self.ring_east || self.present[band].iter().any(|&x| x) {
                continue;
            }
            if lines > 0 {
                self.present[band][rng.random_range(0..lines)] = true;
            } else {
                self.ring_west = true;
            }
        }
    }

    /// The floor gets at least one crossing when it has a cross-corridor line at all: two pieces
    /// on one line on both sides of an east–west corridor.
    fn ensure_crossing(&mut self, rng: &mut Pcg64Mcg) {
        let lines = self.line_fractions.len();
        if lines == 0 {
            return;
        }
        let has = (0..self.east_west)
            .any(|k| (0..lines).any(|j| self.present[k][j] && self.present[k + 1][j]));
        if !has {
            let k = rng.random_range(0..self.east_west);
            let j = rng.random_range(0..lines);
            self.present[k][j] = true;
            self.present[k + 1][j] = true;
        }
    }
}

/// A cut through a band: the x extent of a north–south corridor piece.
#[derive(Clone, Copy)]
struct Cut {
    x0: i32,
    x1: i32,
}

/// Builds the skeleton for corridor width `c` (cells), or `None` when rows or segments would be
/// shallower or shorter than the parameters allow.
fn realize(t: &Topology, p: &BuildingParams, scale: &CellScale, c: i32) -> Option<Skeleton> {
    let (w, h, tw) = (scale.width, scale.height, scale.wall);
    let n = t.east_west as i32;
    let rows_total = h - 2 * tw - n * c - (3 * n - 1) * tw;
    let d_min = scale.cells(p.min_row_depth_m);
    if rows_total < 2 * n * d_min {
        return None;
    }
    let depths = distribute(rows_total, &t.depth_weights);
    if depths.iter().any(|&d| d < d_min) {
        return None;
    }
    // y structure, south to north.
    let mut y = tw;
    let mut rows: Vec<(i32, i32, usize, Side)> = Vec::new(); // (y0, y1, band, front)
    let mut east_west: Vec<(i32, i32)> = Vec::new();
    let mut depth = depths.iter().copied();
    let mut next_depth = || depth.next().unwrap_or(d_min);
    let d = next_depth();
    rows.push((y, y + d, 0, Side::North));
    y += d + tw;
    for k in 0..t.east_west {
        east_west.push((y, y + c));
        y += c + tw;
        if k + 1 < t.east_west {
            let d = next_depth();
            rows.push((y, y + d, k + 1, Side::South));
            y += d + tw;
            let d = next_depth();
            rows.push((y, y + d, k + 1, Side::North));
            y += d + tw;
        } else {
            let d = next_depth();
            rows.push((y, y + d, k + 1, Side::South));
            y += d + tw;
        }
    }
    debug_assert_eq!(y, h, "the y stack fills the floor");

    // x structure: lines between the ring pieces (if any).
    let lo = tw + if t.ring_west { c + tw } else { 0 };
    let hi = w - tw - if t.ring_east { c + tw } else { 0 };
    let lines: Vec<Cut> = t
        .line_fractions
        .iter()
        .map(|f| {
            let centre = lo + (f * f64::from(hi - lo)).round() as i32;
            let x0 = (centre - c / 2).clamp(lo, (hi - c).max(lo));
            Cut { x0, x1: x0 + c }
        })
        .collect();
    let ring_west = Cut { x0: tw, x1: tw + c };
    let ring_east = Cut {
        x0: w - tw - c,
        x1: w - tw,
    };
    let min_segment = 2 * scale.cells(p.min_room_side_m) + tw;

    let mut corridors: Vec<CorridorPlan> = east_west
        .iter()
        .map(|&(y0, y1)| CorridorPlan {
            rect: CellRect::new(tw, y0, w - tw, y1),
            meets: Vec::new(),
        })
        .collect();
    // Pieces per band: (cut, corridor index), sorted west to east.
    let bands = t.east_west + 1;
    let mut pieces: Vec<Vec<(Cut, usize)>> = vec![Vec::new(); bands];
    for (band, band_pieces) in pieces.iter_mut().enumerate() {
        let interior = band > 0 && band < t.east_west;
        let (y0, y1) = if band == 0 {
            (tw, east_west[0].0)
        } else if band == t.east_west {
            (east_west[band - 1].1, h - tw)
        } else {
            (east_west[band - 1].1, east_west[band].0)
        };
        let mut cuts: Vec<Cut> = Vec::new();
        if interior && t.ring_west {
            cuts.push(ring_west);
        }
        for (j, cut) in lines.iter().enumerate() {
            if t.present[band][j] {
                cuts.push(*cut);
            }
        }
        if interior && t.ring_east {
            cuts.push(ring_east);
        }
        for cut in cuts {
            let index = corridors.len();
            let mut meets = Vec::new();
            if band > 0 {
                meets.push(band - 1);
                corridors[band - 1].meets.push(index);
            }
            if band < t.east_west {
                meets.push(band);
                corridors[band].meets.push(index);
            }
            corridors.push(CorridorPlan {
                rect: CellRect::new(cut.x0, y0, cut.x1, y1),
                meets,
            });
            band_pieces.push((cut, index));
        }
    }

    // Segments: each row cut by its band's pieces.
    let mut segments: Vec<Segment> = Vec::new();
    let mut first_of_band_row: Vec<(usize, usize, usize)> = Vec::new(); // (band, start, count)
    for &(y0, y1, band, front) in &rows {
        let front_corridor = match front {
            Side::North => band,
            _ => band - 1,
        };
        let start = segments.len();
        let mut x = tw;
        let mut west: Option<usize> = None;
        let band_pieces = &pieces[band];
        for i in 0..=band_pieces.len() {
            let (end, east) = match band_pieces.get(i) {
                Some(&(cut, index)) => (cut.x0 - tw, Some(index)),
                None => (w - tw, None),
            };
            // A ring piece along an end wall leaves exactly one wall (-tw) between the end
            // wall and itself: no segment there. Anything else shorter than a segment means
            // the cross corridors are too close for this corridor width.
            if end - x >= min_segment {
                segments.push(Segment {
                    rect: CellRect::new(x, y0, end, y1),
                    front,
                    front_corridor,
                    twin: None,
                    west_corridor: west,
                    east_corridor: east,
                });
            } else if end - x != -tw {
                return None;
            }
            if let Some(&(cut, index)) = band_pieces.get(i) {
                x = cut.x1 + tw;
                west = Some(index);
            }
        }
        first_of_band_row.push((band, start, segments.len() - start));
    }
    // Twins: the two rows of an interior band have identical cuts.
    for pair in first_of_band_row.windows(2) {
        let ((b0, s0, n0), (b1, s1, n1)) = (pair[0], pair[1]);
        if b0 == b1 && n0 == n1 {
            for i in 0..n0 {
                segments[s0 + i].twin = Some(s1 + i);
                segments[s1 + i].twin = Some(s0 + i);
            }
        }
    }

    let junctions = junctions(t, &east_west, &pieces, scale, c);
    Some(Skeleton {
        width: w,
        height: h,
        wall: tw,
        corridor_width: c,
        corridors,
        east_west_count: t.east_west,
        segments,
        junctions,
    })
}

/// Classifies every place where corridors meet, turn or end. Junction squares belong to the
/// east–west corridor; the position is the centre of the square (or of the last corridor-wide
/// square of a dead end).
fn junctions(
    t: &Topology,
    east_west: &[(i32, i32)],
    pieces: &[Vec<(Cut, usize)>],
    scale: &CellScale,
    c: i32,
) -> Vec<JunctionPlan> {
    let (w, h, tw) = (scale.width, scale.height, scale.wall);
    let half = f64::from(c) / 2.0;
    let mut out = Vec::new();
    for (k, &(y0, y1)) in east_west.iter().enumerate() {
        let yc = f64::from(y0 + y1) / 2.0;
        let below = &pieces[k];
        let above = &pieces[k + 1];
        let mut xs: Vec<(i32, i32)> = below
            .iter()
            .chain(above.iter())
            .map(|(cut, _)| (cut.x0, cut.x1))
            .collect();
        xs.sort_unstable();
        xs.dedup();
        let mut west_joined = false;
        let mut east_joined = false;
        for (x0, x1) in xs {
            let down = below.iter().any(|(cut, _)| cut.x0 == x0);
            let up = above.iter().any(|(cut, _)| cut.x0 == x0);
            let west_arm = x0 > tw;
            let east_arm = x1 < w - tw;
            west_joined |= !west_arm;
            east_joined |= !east_arm;
            let arms = [down, up, west_arm, east_arm]
                .iter()
                .filter(|&&a| a)
                .count();
            let kind = match arms {
                4 => JunctionKind::Crossing,
                3 => JunctionKind::TJunction,
                _ => JunctionKind::Corner,
            };
            out.push(JunctionPlan {
                kind,
                x: f64::from(x0 + x1) / 2.0,
                y: yc,
            });
        }
        if !west_joined {
            out.push(JunctionPlan {
                kind: JunctionKind::DeadEnd,
                x: f64::from(tw) + half,
                y: yc,
            });
        }
        if !east_joined {
            out.push(JunctionPlan {
                kind: JunctionKind::DeadEnd,
                x: f64::from(w - tw) - half,
                y: yc,
            });
        }
    }
    // Stubs to the north and south exterior walls end in dead ends.
    for (band, y) in [
        (0, f64::from(tw) + half),
        (t.east_west, f64::from(h - tw) - half),
    ] {
        for (cut, _) in &pieces[band] {
            out.push(JunctionPlan {
                kind: JunctionKind::DeadEnd,
                x: f64::from(cut.x0 + cut.x1) / 2.0,
                y,
            });
        }
    }
    out
}

/// Splits `total` cells into parts proportional to `weights` (whole cells, summing to `total`).
fn distribute(total: i32, weights: &[f64]) -> Vec<i32> {
    let sum: f64 = weights.iter().sum();
    let mut parts: Vec<i32> = weights
        .iter()
        .map(|w| (f64::from(total) * w / sum).floor() as i32)
        .collect();
    let mut rest = total - parts.iter().sum::<i32>();
    let n = parts.len().max(1);
    let mut i = 0;
    while rest > 0 {
        parts[i % n] += 1;
        rest -= 1;
        i += 1;
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn distribute_sums_to_total() {
        assert_eq!(distribute(10, &[1.0, 1.0, 1.0]), vec![4, 3, 3]);
        assert_eq!(distribute(100, &[0.9, 1.1]).iter().sum::<i32>(), 100);
    }

    #[test]
    fn skeleton_tiles_the_floor_without_overlaps() {
        let p = BuildingParams::office();
        let scale = CellScale::new(&p);
        for seed in 0..8 {
            let mut rng = Pcg64Mcg::seed_from_u64(seed);
            let s = plan_skeleton(&p, &scale, &mut rng, |s| {
                let c = s.corridor_area_cells() as f64;
                c / (c + s.segments.iter().map(|g| g.rect.area()).sum::<i64>() as f64)
            });
            let rects: Vec<CellRect> = s
                .corridors
                .iter()
                .map(|c| c.rect)
                .chain(s.segments.iter().map(|g| g.rect))
                .collect();
            for (i, a) in rects.iter().enumerate() {
                assert!(a.area() > 0);
                assert!(a.x0 >= s.wall && a.y0 >= s.wall);
                assert!(a.x1 <= s.width - s.wall && a.y1 <= s.height - s.wall);
                for b in &rects[i + 1..] {
                    assert!(!a.intersects(b), "{a:?} overlaps {b:?}");
                }
            }
            for g in &s.segments {
                if let Some(t) = g.twin {
                    let o = &s.segments[t];
                    assert_eq!((o.rect.x0, o.rect.x1), (g.rect.x0, g.rect.x1));
                    assert_eq!(
                        o.twin,
                        Some(s.segments.iter().position(|x| x.rect == g.rect).unwrap())
                    );
                }
            }
        }
    }
}

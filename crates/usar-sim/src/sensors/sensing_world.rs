//! The ground truth as the sensors see it: one flat grid of "blocking heights" — the floor height
//! of each cell, or +∞ where a wall or furniture stands. A beam at height z is stopped by the
//! first cell whose blocking height reaches z.
//!
//! A beam above 0 m can only be stopped by a cell that rises above 0 m (walls, furniture, raised
//! floor). Per cell, a layer holds its Chebyshev distance (in cells, up to 255) to the nearest
//! rising cell — 0 on a rising cell — so the walk reads one byte per cell, a bitmap of the
//! obstacles on rising cells and the height itself only on raised floor. A beam above 0 m in a cell at distance c ≥
//! [`MIN_SKIP_CLEARANCE`] crosses nothing that could stop it before it leaves the square of
//! half-side c − 1 around that cell, so it jumps to that square's edge in one step
//! ([`GridRay::walk_skipping`]); the beam ends on the same cell at the same distance as a walk
//! through every cell.

use std::cmp::Ordering;
use usar_world::{CellRect, GridGeometry, GridRay, Point2, RayVisitor, Scene, Visit};

/// Clearance (cells) from which a beam jumps rather than steps: a jump costs about as much as
/// walking a few cells.
const MIN_SKIP_CLEARANCE: u8 = 8;

/// Blocking heights of a scene, built once and shared by every robot's sensors.
#[derive(Clone, Debug)]
pub struct SensingWorld {
    geometry: GridGeometry,
    blocking_height_m: Vec<f32>,
    /// Set when cell i's blocking height is +∞ (an obstacle).
    blocks_all: Vec<u64>,
    /// Per cell: Chebyshev distance in cells to the nearest rising cell (0 on one), at most
    /// 255; cells outside the grid do not count.
    clearance: Vec<u8>,
}

/// A beam above 0 m walking the grid: it stops on a rising cell at least as high as the beam
/// and jumps over the empty space around cells at least [`MIN_SKIP_CLEARANCE`] from any rising
/// cell.
struct BeamAbove<'a> {
    clearance: &'a [u8],
    blocks_all: &'a [u64],
    heights: &'a [f32],
    z_m: f32,
}

impl RayVisitor for BeamAbove<'_> {
    #[inline(always)]
    fn visit(&mut self, i: usize) -> Visit {
        match self.clearance[i] {
            0 => {
                if (self.blocks_all[i / 64] >> (i % 64)) & 1 != 0 || self.heights[i] >= self.z_m {
                    Visit::Stop
                } else {
                    Visit::Next
                }
            }
            c if c >= MIN_SKIP_CLEARANCE => Visit::MaySkip,
            _ => Visit::Next,
        }
    }

    #[inline(always)]
    fn skip(&mut self, i: usize, col: i32, row: i32) -> Option<CellRect> {
        let r = i32::from(self.clearance[i]) - 1;
        Some(CellRect {
            col_min: col - r,
            col_max: col + r,
            row_min: row - r,
            row_max: row + r,
        })
    }
}

/// Chebyshev distance from each cell to the nearest marked one (0 on a marked cell, 255 at
/// most, and 255 everywhere when none is): the two-pass chamfer transform with unit weights on
/// all eight neighbours, which is exact for this metric.
fn chebyshev_clearance(width: usize, height: usize, marked: impl Fn(usize) -> bool) -> Vec<u8> {
    /// Neighbours visited before a cell: west and south going forward, east and north back.
    const FORWARD: [(isize, isize); 4] = [(-1, 0), (-1, -1), (0, -1), (1, -1)];
    const BACKWARD: [(isize, isize); 4] = [(1, 0), (1, 1), (0, 1), (-1, 1)];
    let mut d: Vec<u8> = (0..width * height)
        .map(|i| if marked(i) { 0 } else { u8::MAX })
        .collect();
    let mut relax = |col: usize, row: usize, neighbours: &[(isize, isize); 4]| {
        let i = row * width + col;
        for &(dc, dr) in neighbours {
            let (c, r) = (col.wrapping_add_signed(dc), row.wrapping_add_signed(dr));
            if c < width && r < height {
                d[i] = d[i].min(d[r * width + c].saturating_add(1));
            }
        }
    };
    for row in 0..height {
        for col in 0..width {
            relax(col, row, &FORWARD);
        }
    }
    for row in (0..height).rev() {
        for col in (0..width).rev() {
            relax(col, row, &BACKWARD);
        }
    }
    d
}

impl SensingWorld {
    pub fn new(scene: &Scene) -> Self {
        let blocking_height_m = scene
            .obstacle
            .as_slice()
            .iter()
            .zip(scene.floor_height_m.as_slice())
            .map(|(&o, &h)| {
                if o != usar_world::obstacle::NONE {
                    f32::INFINITY
                } else {
                    h
                }
            })
            .collect::<Vec<f32>>();
        let bitmap = |mark: fn(f32) -> bool| -> Vec<u64> {
            blocking_height_m
                .chunks(64)
                .map(|heights| {
                    heights
                        .iter()
                        .enumerate()
                        .fold(0u64, |bits, (k, &h)| bits | (u64::from(mark(h)) << k))
                })
                .collect()
        };
        // Not ≤ 0, NaN included (its height then decides, as it would without the bitmap).
        let rises = |h: f32| !matches!(h.partial_cmp(&0.0), Some(Ordering::Less | Ordering::Equal));
        let g = *scene.geometry();
        let clearance = chebyshev_clearance(g.width as usize, g.height as usize, |i| {
            rises(blocking_height_m[i])
        });
        Self {
            geometry: g,
            clearance,
            blocks_all: bitmap(|h| h == f32::INFINITY),
            blocking_height_m,
        }
    }

    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// Floor height under a point (+∞ on an obstacle, `None` outside the grid).
    #[inline]
    pub fn height_at(&self, p: Point2) -> Option<f32> {
        self.geometry
            .checked_index(self.geometry.world_to_cell(p))
            .map(|i| self.blocking_height_m[i])
    }

    /// Distance (m) along a horizontal beam at height `z_m` from `origin` in direction
    /// (`cos`, `sin`) to the first cell that blocks it, or `None` if nothing does within
    /// `max_range_m`. A beam that leaves the grid returns `None`.
    #[inline]
    pub fn cast_horizontal(
        &self,
        origin: Point2,
        cos: f64,
        sin: f64,
        z_m: f32,
        max_range_m: f64,
    ) -> Option<f64> {
        let heights = self.blocking_height_m.as_slice();
        if z_m > 0.0 {
            // A cell at a clearance above 0 has a height ≤ 0 < z_m: skip its height.
            let mut beam = BeamAbove {
                clearance: &self.clearance,
                blocks_all: &self.blocks_all,
                heights,
                z_m,
            };
            let g = &self.geometry;
            let max_t = max_range_m / g.resolution_m;
            // As in `first_blocking`, with the empty space around the beam skipped.
            let (i, t_entry) = GridRay::new(g, origin, cos, sin).walk_skipping(
                g.width,
                g.height,
                max_t.next_up(),
                &mut beam,
            )?;
            (beam.visit(i) == Visit::Stop).then_some(t_entry * g.resolution_m)
        } else {
            self.first_blocking(origin, cos, sin, max_range_m, |i| heights[i] >= z_m)
        }
    }

    /// Distance (m) from `origin` in direction (`cos`, `sin`) to the entry of the first cell
    /// (by index) that `blocks`, or `None` if none does within `max_range_m` or before the beam
    /// leaves the grid.
    #[inline(always)]
    fn first_blocking(
        &self,
        origin: Point2,
        cos: f64,
        sin: f64,
        max_range_m: f64,
        blocks: impl Fn(usize) -> bool,
    ) -> Option<f64> {
        let g = &self.geometry;
        let max_t = max_range_m / g.resolution_m;
        // Cells entered at or before `max_t`: those left before the next float, plus the one in
        // which the beam reaches it.
        let (i, t_entry) = GridRay::new(g, origin, cos, sin).walk_to(
            g.width,
            g.height,
            max_t.next_up(),
            &blocks,
        )?;
        blocks(i).then_some(t_entry * g.resolution_m)
    }

    /// Distance (m, along the 3-D beam) from a sensor at (`origin`, `z0_m`) looking in horizontal
    /// direction (`cos`, `sin`) and pitched down by `pitch_down_rad` (negative: up) to the first
    /// surface it meets — a cell's side or its floor — or `None` within `max_range_m`.
    pub fn cast_3d(
        &self,
        origin: Point2,
        z0_m: f64,
        cos: f64,
        sin: f64,
        pitch_down_rad: f64,
        max_range_m: f64,
    ) -> Option<f64> {
        let g = &self.geometry;
        let (sp, cp) = pitch_down_rad.sin_cos();
        if cp <= 1e-9 {
            // Straight down (or up): the floor under the sensor, if it is below.
            let h = f64::from(self.height_at(origin)?);
            return (sp > 0.0 && z0_m - h <= max_range_m && h.is_finite()).then_some(z0_m - h);
        }
        let tan_p = sp / cp;
        let max_s = max_range_m * cp;
        let res = g.resolution_m;
        let mut ray = GridRay::new(g, origin, cos, sin);
        loop {
            let i = ray.index_in(g.width, g.height)?;
            let top = f64::from(self.blocking_height_m[i]);
            let s_in = ray.t_entry * res;
            if s_in > max_s {
                return None;
            }
            let z_in = z0_m - s_in * tan_p;
            if top >= z_in {
                return Some(s_in / cp);
            }
            if tan_p > 0.0 {
                let s_out = ray.t_exit() * res;
                let z_out = z0_m - s_out * tan_p;
                if top >= z_out {
                    let s_hit = (z0_m - top) / tan_p;
                    return (s_hit <= max_s).then_some(s_hit / cp);
                }
            }
            ray.advance();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::{Cell, Grid, obstacle};

    fn corridor() -> Scene {
        let g = GridGeometry::new(100, 20, 0.1, Point2::new(0.0, 0.0));
        let mut s = Scene::empty("t", g);
        for row in 0..20 {
            s.obstacle[Cell::new(80, row)] = obstacle::WALL;
        }
        // A 0.2 m step from column 50 on.
        s.floor_height_m = Grid::from_vec(
            g,
            (0..g.len())
                .map(|i| if i % 100 >= 50 { 0.2 } else { 0.0 })
                .collect(),
        )
        .unwrap();
        s
    }

    #[test]
    fn horizontal_beam_stops_at_wall_or_higher_floor() {
        let w = SensingWorld::new(&corridor());
        let d = w
            .cast_horizontal(Point2::new(1.05, 1.0), 1.0, 0.0, 0.3, 20.0)
            .unwrap();
        assert!((d - (8.0 - 1.05)).abs() < 1e-9, "{d}");
        // A beam at 0.1 m is stopped by the 0.2 m step at x = 5.0.
        let d = w
            .cast_horizontal(Point2::new(1.05, 1.0), 1.0, 0.0, 0.1, 20.0)
            .unwrap();
        assert!((d - (5.0 - 1.05)).abs() < 1e-9, "{d}");
        assert!(
            w.cast_horizontal(Point2::new(1.05, 1.0), -1.0, 0.0, 0.3, 0.5)
                .is_none()
        );
    }

    #[test]
    fn clearance_is_the_chebyshev_distance_to_the_nearest_rising_cell() {
        let (w, h) = (23usize, 17usize);
        let marked: Vec<bool> = (0..w * h).map(|i| (i * 7919) % 61 == 0).collect();
        let d = chebyshev_clearance(w, h, |i| marked[i]);
        for (i, &clearance) in d.iter().enumerate() {
            let (c, r) = ((i % w) as i32, (i / w) as i32);
            let brute = (0..w * h)
                .filter(|&j| marked[j])
                .map(|j| {
                    let (cj, rj) = ((j % w) as i32, (j / w) as i32);
                    (c - cj).abs().max((r - rj).abs())
                })
                .min()
                .map_or(255, |v| v.min(255) as u8);
            assert_eq!(clearance, brute, "cell {i}");
        }
        assert!(
            chebyshev_clearance(3, 2, |_| false)
                .iter()
                .all(|&v| v == 255)
        );
    }

    /// The beam that skips empty space ends exactly (same cell, same distance) where the walk
    /// through every cell ends, in a room with furniture-like blocks and raised floor.
    #[test]
    fn skipping_empty_space_changes_no_range() {
        let g = GridGeometry::new(300, 200, 0.1, Point2::new(0.0, 0.0));
        let mut s = Scene::empty("t", g);
        let mut heights = vec![0.0f32; g.len()];
        for k in 0..400usize {
            let (c, r) = ((k * 7919) % 300, (k * 104_729 / 7) % 200);
            if k % 3 == 0 {
                s.obstacle[Cell::new(c as i32, r as i32)] = obstacle::WALL;
            } else {
                heights[r * 300 + c] = if k % 2 == 0 { 0.2 } else { 0.5 };
            }
        }
        s.floor_height_m = Grid::from_vec(g, heights).unwrap();
        let w = SensingWorld::new(&s);
        let heights = w.blocking_height_m.clone();
        for k in 0..2000usize {
            let origin = Point2::new(0.05 + (k % 97) as f64 * 0.31, 0.05 + (k % 89) as f64 * 0.22);
            let (sn, cs) = (k as f64 * 0.0137).sin_cos();
            let z = 0.3f32;
            let skipped = w.cast_horizontal(origin, cs, sn, z, 20.0);
            let walked = w.first_blocking(origin, cs, sn, 20.0, |i| heights[i] >= z);
            assert_eq!(skipped, walked, "beam {k}");
        }
    }

    #[test]
    fn tilted_beam_meets_the_floor_at_the_expected_range() {
        let w = SensingWorld::new(&corridor());
        // Sensor 0.5 m above a flat floor, pitched down 30°: meets the floor after 1.0 m.
        let d = w
            .cast_3d(
                Point2::new(1.05, 1.0),
                0.5,
                1.0,
                0.0,
                30f64.to_radians(),
                4.0,
            )
            .unwrap();
        assert!((d - 1.0).abs() < 1e-9, "{d}");
        // 0.5 m before the wall at x = 8.0 the beam is still 0.21 m high: it hits the wall's face.
        let d = w
            .cast_3d(
                Point2::new(7.5, 1.0),
                0.5,
                1.0,
                0.0,
                30f64.to_radians(),
                4.0,
            )
            .unwrap();
        assert!((d - 0.5 / 30f64.to_radians().cos()).abs() < 1e-9, "{d}");
        // Near the 0.2 m step the beam clears its edge (z = 0.211 m at x = 5.0) and meets its
        // top where z = 0.2 m, i.e. 0.3 / tan 30° ahead.
        let d = w
            .cast_3d(
                Point2::new(4.5, 1.0),
                0.5,
                1.0,
                0.0,
                30f64.to_radians(),
                4.0,
            )
            .unwrap();
        let expected_horizontal = 0.3 / 30f64.to_radians().tan();
        // Heights are f32: 0.2 is stored as 0.200000003.
        assert!(
            (d * 30f64.to_radians().cos() - expected_horizontal).abs() < 1e-6,
            "{d}"
        );
    }
}

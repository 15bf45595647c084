//! The log-odds occupancy grid a robot builds from its laser scans, and its merging at a base
//! station.
//!
//! Each cell stores l = 10·ln(p / (1 − p)) as an `i8`, clamped to ±[`LOGODDS_LIMIT`], or
//! [`NEVER_OBSERVED`] until a beam first reaches it: "unknown" means never observed, so a cell
//! that sees contradictory evidence (a wall surface grazed by noisy beams) stays known and does
//! not reappear as a frontier. A scan updates every cell at most once: cells a beam crosses before its return get the miss
//! increment, the cell of the return gets the hit increment (applied after all misses, so a wall
//! grazed by one beam and hit by another ends up occupied). Class changes are logged for
//! incremental consumers (frontiers, inflation) and updated 32×32 tiles are marked dirty for
//! merging.

use usar_sim::sensors::LaserScan;
use usar_world::{Cell, Grid, GridGeometry, GridRay};

/// Largest |l| stored (p ≈ 0.018 … 0.982).
pub const LOGODDS_LIMIT: i8 = 40;
/// The value of a cell no beam has reached yet.
pub const NEVER_OBSERVED: i8 = i8::MIN;
const TILE_SHIFT: u32 = 5;

/// What a robot believes about a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CellClass {
    Unknown,
    Free,
    Occupied,
}

/// Sensor model of the occupancy update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OccupancyParams {
    /// Increment for the cell of a return: +9 ≈ p(occ | hit) = 0.71.
    pub hit: i8,
    /// Increment for a cell a beam crossed: −4 ≈ p(occ | miss) = 0.40.
    pub miss: i8,
    /// An observed cell is occupied when l > this, free otherwise. With the defaults one hit
    /// makes a cell occupied and it takes three misses to free it again.
    pub occupied_above: i8,
}

impl Default for OccupancyParams {
    fn default() -> Self {
        Self {
            hit: 9,
            miss: -4,
            occupied_above: 0,
        }
    }
}

impl OccupancyParams {
    #[inline]
    pub fn class(&self, logodds: i8) -> CellClass {
        if logodds == NEVER_OBSERVED {
            CellClass::Unknown
        } else if logodds > self.occupied_above {
            CellClass::Occupied
        } else {
            CellClass::Free
        }
    }
}

/// A log-odds occupancy grid.
#[derive(Clone, Debug)]
pub struct OccupancyGrid {
    geometry: GridGeometry,
    params: OccupancyParams,
    logodds: Vec<i8>,
    /// Scan number that last updated each cell (dedupes updates within one scan).
    stamp: Vec<u32>,
    scan_number: u32,
    hits: Vec<u32>,
    /// Cells whose class changed since the log was last drained.
    changed: Vec<u32>,
    tiles_x: usize,
    dirty_tiles: Vec<bool>,
    known_cells: usize,
}

impl OccupancyGrid {
    pub fn new(geometry: GridGeometry, params: OccupancyParams) -> Self {
        let n = geometry.len();
        let tiles_x = (geometry.width as usize).div_ceil(1 << TILE_SHIFT);
        let tiles_y = (geometry.height as usize).div_ceil(1 << TILE_SHIFT);
        Self {
            geometry,
            params,
            logodds: vec![NEVER_OBSERVED; n],
            stamp: vec![0; n],
            scan_number: 0,
            hits: Vec::new(),
            changed: Vec::new(),
            tiles_x,
            dirty_tiles: vec![false; tiles_x * tiles_y],
            known_cells: 0,
        }
    }

    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    pub fn params(&self) -> &OccupancyParams {
        &self.params
    }

    pub fn logodds(&self) -> &[i8] {
        &self.logodds
    }

    #[inline]
    pub fn class_at_index(&self, i: usize) -> CellClass {
        self.params.class(self.logodds[i])
    }

    /// Class of a cell; `Unknown` outside the grid.
    #[inline]
    pub fn class(&self, cell: Cell) -> CellClass {
        self.geometry
            .checked_index(cell)
            .map_or(CellClass::Unknown, |i| self.class_at_index(i))
    }

    /// Number of cells currently free or occupied.
    pub fn known_cells(&self) -> usize {
        self.known_cells
    }

    /// Known (free or occupied) area, m².
    pub fn known_area_m2(&self) -> f64 {
        self.known_cells as f64 * self.geometry.cell_area_m2()
    }

    /// Takes the log of cells whose class changed since the last call.
    pub fn drain_changed(&mut self, into: &mut Vec<u32>) {
        into.append(&mut self.changed);
    }

    #[inline(always)]
    fn apply(&mut self, i: usize, delta: i8) {
        let old = self.logodds[i];
        let base = if old == NEVER_OBSERVED { 0 } else { old };
        self.set(
            i,
            base.saturating_add(delta)
                .clamp(-LOGODDS_LIMIT, LOGODDS_LIMIT),
        );
    }

    /// Sets a cell's value, logging a class change and marking its tile dirty.
    #[inline(always)]
    fn set(&mut self, i: usize, new: i8) {
        let old = self.logodds[i];
        if new != old {
            self.logodds[i] = new;
            let (co, cn) = (self.params.class(old), self.params.class(new));
            if co != cn {
                self.changed.push(i as u32);
                self.known_cells = self.known_cells + usize::from(co == CellClass::Unknown)
                    - usize::from(cn == CellClass::Unknown);
            }
            let w = self.geometry.width as usize;
            let tile = ((i / w) >> TILE_SHIFT) * self.tiles_x + ((i % w) >> TILE_SHIFT);
            self.dirty_tiles[tile] = true;
        }
    }

    /// Integrates one laser scan taken at `scan.pose` (the pose is trusted: localisation is
    /// given, as in paper 002's simulations).
    pub fn integrate_scan(&mut self, scan: &LaserScan) {
        self.scan_number = self.scan_number.wrapping_add(1);
        if self.scan_number == 0 {
            self.stamp.fill(0);
            self.scan_number = 1;
        }
        let stamp_now = self.scan_number;
        let g = self.geometry;
        let inv_res = 1.0 / g.resolution_m;
        let (w, h) = (g.width, g.height);
        let (s, c) = scan.pose.theta.sin_cos();
        let (s0, c0) = scan.angle_min_rad.sin_cos();
        let (si, ci) = scan.angle_increment_rad.sin_cos();
        // Beam direction relative to the heading, advanced by rotation (no sin_cos per beam).
        let (mut bc, mut bs) = (c0, s0);
        let origin = scan.pose.position();
        let miss = self.params.miss;
        self.hits.clear();
        for &range in &scan.ranges_m {
            let (dc, ds) = (c * bc - s * bs, s * bc + c * bs);
            let hit = range.is_finite();
            let reach_t = if hit {
                f64::from(range)
            } else {
                scan.max_range_m
            } * inv_res;
            let mut ray = GridRay::new(&g, origin, dc, ds);
            while let Some(i) = ray.index_in(w, h) {
                let end_here = ray.t_exit() >= reach_t;
                if end_here && hit {
                    self.hits.push(i as u32);
                    break;
                }
                if self.stamp[i] != stamp_now {
                    self.stamp[i] = stamp_now;
                    self.apply(i, miss);
                }
                if end_here {
                    break;
                }
                ray.advance();
            }
            (bc, bs) = (bc * ci - bs * si, bs * ci + bc * si);
        }
        let hit_delta = self.params.hit;
        let mut hits = std::mem::take(&mut self.hits);
        hits.sort_unstable();
        hits.dedup();
        for &i in &hits {
            self.apply(i as usize, hit_delta);
        }
        self.hits = hits;
    }

    /// A mask of cells whose class is `class`.
    pub fn mask(&self, class: CellClass) -> Grid<bool> {
        Grid::from_vec(
            self.geometry,
            self.logodds
                .iter()
                .map(|&l| self.params.class(l) == class)
                .collect(),
        )
        .expect("same geometry")
    }

    /// Replaces this grid's values with the clamped sum of `sources` on every tile that any
    /// source changed since its last merge (log-odds of independent observers add up; a cell is
    /// unknown only if every source has never observed it), then clears the sources' dirty
    /// marks. All grids must share one geometry.
    pub fn merge_from(&mut self, sources: &mut [&mut OccupancyGrid]) {
        let n_tiles = self.dirty_tiles.len();
        let w = self.geometry.width as usize;
        let h = self.geometry.height as usize;
        let side = 1usize << TILE_SHIFT;
        let mut sum = vec![0i16; side];
        let mut observed = vec![false; side];
        for tile in 0..n_tiles {
            if !sources.iter().any(|s| s.dirty_tiles[tile]) {
                continue;
            }
            let (tx, ty) = (tile % self.tiles_x, tile / self.tiles_x);
            let (x0, y0) = (tx * side, ty * side);
            let (x1, y1) = ((x0 + side).min(w), (y0 + side).min(h));
            for row in y0..y1 {
                let span = row * w + x0..row * w + x1;
                let sum = &mut sum[..x1 - x0];
                let observed = &mut observed[..x1 - x0];
                sum.fill(0);
                observed.fill(false);
                for s in sources.iter() {
                    for ((acc, seen), &l) in sum
                        .iter_mut()
                        .zip(observed.iter_mut())
                        .zip(&s.logodds[span.clone()])
                    {
                        if l != NEVER_OBSERVED {
                            *acc += i16::from(l);
                            *seen = true;
                        }
                    }
                }
                for (k, (&total, &seen)) in sum.iter().zip(observed.iter()).enumerate() {
                    let target = if seen {
                        total.clamp(-i16::from(LOGODDS_LIMIT), i16::from(LOGODDS_LIMIT)) as i8
                    } else {
                        NEVER_OBSERVED
                    };
                    self.set(span.start + k, target);
                }
            }
        }
        for s in sources.iter_mut() {
            s.dirty_tiles.fill(false);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::{Point2, Pose2};

    fn scan_towards_east(range: f32) -> LaserScan {
        LaserScan {
            pose: Pose2::new(0.55, 0.55, 0.0),
            angle_min_rad: 0.0,
            angle_increment_rad: 0.0,
            max_range_m: 5.0,
            ranges_m: vec![range],
        }
    }

    #[test]
    fn a_beam_frees_the_cells_before_its_return_and_occupies_the_return() {
        let g = GridGeometry::new(30, 10, 0.1, Point2::new(0.0, 0.0));
        let mut grid = OccupancyGrid::new(g, OccupancyParams::default());
        grid.integrate_scan(&scan_towards_east(1.0));
        for col in 5..15 {
            assert_eq!(grid.class(Cell::new(col, 5)), CellClass::Free, "col {col}");
        }
        assert_eq!(grid.class(Cell::new(15, 5)), CellClass::Occupied);
        assert_eq!(grid.class(Cell::new(16, 5)), CellClass::Unknown);
        assert_eq!(grid.known_cells(), 11);
        let mut changed = Vec::new();
        grid.drain_changed(&mut changed);
        assert_eq!(changed.len(), 11);
    }

    #[test]
    fn a_beam_without_return_frees_up_to_the_maximum_range() {
        let g = GridGeometry::new(100, 10, 0.1, Point2::new(0.0, 0.0));
        let mut grid = OccupancyGrid::new(g, OccupancyParams::default());
        grid.integrate_scan(&scan_towards_east(f32::INFINITY));
        assert_eq!(grid.class(Cell::new(54, 5)), CellClass::Free);
        assert_eq!(grid.class(Cell::new(56, 5)), CellClass::Unknown);
        assert!(
            grid.mask(CellClass::Occupied)
                .as_slice()
                .iter()
                .all(|&o| !o)
        );
    }

    #[test]
    fn merging_sums_evidence_and_only_visits_dirty_tiles() {
        let g = GridGeometry::new(100, 100, 0.1, Point2::new(0.0, 0.0));
        let mut a = OccupancyGrid::new(g, OccupancyParams::default());
        let mut b = OccupancyGrid::new(g, OccupancyParams::default());
        a.integrate_scan(&scan_towards_east(1.0));
        let mut merged = OccupancyGrid::new(g, OccupancyParams::default());
        merged.merge_from(&mut [&mut a, &mut b]);
        assert_eq!(merged.logodds(), a.logodds());
        b.integrate_scan(&scan_towards_east(1.0));
        merged.merge_from(&mut [&mut a, &mut b]);
        assert_eq!(merged.logodds()[g.index(Cell::new(15, 5))], 18);
        assert_eq!(merged.logodds()[g.index(Cell::new(10, 5))], -8);
        assert_eq!(merged.known_cells(), 11);
    }
}

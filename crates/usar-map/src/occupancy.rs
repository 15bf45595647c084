//! The log-odds occupancy grid a robot builds from its laser scans, and its merging at a base
//! station.
//!
//! Each cell stores l = 10·ln(p / (1 − p)) as an `i8`, clamped to ±[`LOGODDS_LIMIT`], or
//! [`NEVER_OBSERVED`] until a beam first reaches it: "unknown" means never observed, so a cell
//! that sees contradictory evidence (a wall surface grazed by noisy beams) stays known and does
//! not reappear as a frontier. A scan updates every cell at most once: cells a beam crosses
//! before its return get the miss increment, the cell of the return gets the hit increment
//! (applied after all misses, so a wall grazed by one beam and hit by another ends up occupied).
//! Class changes are logged for incremental consumers (frontiers, inflation) and updated 32×32
//! tiles are marked dirty for merging.
//!
//! Speed: most cells a beam crosses are saturated free space, which a miss leaves unchanged; a
//! bitmap marks them, so such a cell costs one bit test (the bitmap of a 1000 × 1000 grid is
//! 125 kB and stays in cache) and needs no mark against a second miss in the scan, since every
//! later miss leaves it unchanged too. The other cells take the tabulated update and a bit in a
//! second bitmap, cleared at the end of the scan.

use usar_readings::LaserScan;
use usar_world::{Cell, Grid, GridGeometry, GridRay};

/// Largest |l| stored (p ≈ 0.018 … 0.982).
pub const LOGODDS_LIMIT: i8 = 40;
/// The value of a cell no beam has reached yet.
pub const NEVER_OBSERVED: i8 = i8::MIN;
const TILE_SHIFT: u32 = 5;
// A row of a tile is one `u32` of [`OccupancyGrid::merge_tracked`]'s bits.
const _: () = assert!(1 << TILE_SHIFT == u32::BITS);

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
    /// A cell's value after a miss, indexed by its value before (as `u8`): [`updated`]
    /// tabulated.
    after_miss: [i8; 256],
    /// A cell's value after a hit, indexed likewise.
    after_hit: [i8; 256],
    /// Bit `i % 64` of word `i / 64` is set when a miss leaves cell i unchanged
    /// (`after_miss[l] == l`): what a beam crossing saturated free space reads. While a scan is
    /// integrated it is also set on the cells a miss changed in that scan, which must take no
    /// second miss; it is made true again after the scan.
    unchanged_by_miss: Vec<u64>,
    /// Cells a miss changed in the scan being integrated.
    missed_cells: Vec<u32>,
    hits: Vec<u32>,
    log: ChangeLog,
}

/// What changed since consumers last looked: the class-change log, the dirty tiles and the count
/// of known cells.
#[derive(Clone, Debug)]
struct ChangeLog {
    /// Cells whose class changed since the log was last drained.
    changed: Vec<u32>,
    /// Row of a cell index, without a division.
    rows: RowOfIndex,
    tiles_x: usize,
    dirty_tiles: Vec<bool>,
    known_cells: usize,
}

impl ChangeLog {
    /// Records that cell `i` went from `old` to `new` (`new != old`).
    #[inline]
    fn record(&mut self, params: &OccupancyParams, i: usize, old: i8, new: i8) {
        let (co, cn) = (params.class(old), params.class(new));
        if co != cn {
            self.changed.push(i as u32);
            self.known_cells = self.known_cells + usize::from(co == CellClass::Unknown)
                - usize::from(cn == CellClass::Unknown);
        }
        let (row, col) = self.rows.row_and_col(i);
        self.dirty_tiles[(row >> TILE_SHIFT) * self.tiles_x + (col >> TILE_SHIFT)] = true;
    }
}

/// Row and column of a row-major cell index by a multiplication (Lemire, Kaser & Kurz 2019,
/// "Faster remainder by direct computation": for 32-bit n and d, ⌊n/d⌋ = ⌊c·n / 2⁶⁴⌋ with
/// c = ⌈2⁶⁴/d⌉); a division costs tens of cycles on every cell an update changes.
#[derive(Clone, Copy, Debug)]
struct RowOfIndex {
    width: usize,
    /// ⌈2⁶⁴/width⌉, or 0 where the identity does not hold (width 1, or indices beyond 32 bits).
    multiplier: u64,
}

impl RowOfIndex {
    fn new(width: usize, cells: usize) -> Self {
        let fits = width >= 2 && cells <= u32::MAX as usize;
        Self {
            width,
            multiplier: if fits { u64::MAX / width as u64 + 1 } else { 0 },
        }
    }

    #[inline]
    fn row_and_col(&self, i: usize) -> (usize, usize) {
        let row = if self.multiplier == 0 {
            i / self.width.max(1)
        } else {
            ((u128::from(self.multiplier) * i as u128) >> 64) as usize
        };
        (row, i - row * self.width)
    }
}

/// An occupancy grid's cells with what must change with them: its values, the bitmap of cells a
/// miss leaves unchanged, the marks of this scan's misses and the change log.
struct Cells<'a> {
    params: &'a OccupancyParams,
    after_miss: &'a [i8; 256],
    logodds: &'a mut [i8],
    unchanged_by_miss: &'a mut [u64],
    missed_cells: &'a mut Vec<u32>,
    log: &'a mut ChangeLog,
}

impl Cells<'_> {
    /// Sets a cell's value, logging a class change and marking its tile dirty.
    #[inline(always)]
    fn set(&mut self, i: usize, new: i8) {
        let old = self.logodds[i];
        if new != old {
            self.write(i, old, new);
        }
    }

    /// Writes `new` over `old` (`new != old`) in cell i, keeping the bitmap and the log.
    #[inline]
    fn write(&mut self, i: usize, old: i8, new: i8) {
        self.logodds[i] = new;
        self.refresh_unchanged_by_miss(i);
        self.log.record(self.params, i, old, new);
    }

    /// Sets cell i's bit in `unchanged_by_miss` from its value.
    #[inline]
    fn refresh_unchanged_by_miss(&mut self, i: usize) {
        let l = self.logodds[i];
        let unchanged = self.after_miss[usize::from(l as u8)] == l;
        let (word, bit) = (i / 64, i % 64);
        self.unchanged_by_miss[word] =
            (self.unchanged_by_miss[word] & !(1 << bit)) | (u64::from(unchanged) << bit);
    }

    /// A miss on cell i, at most once per scan: the common case, a cell that a miss leaves
    /// unchanged (saturated free), is one bit test.
    #[inline(always)]
    fn miss_at(&mut self, i: usize) {
        if (self.unchanged_by_miss[i / 64] >> (i % 64)) & 1 == 0 {
            self.change_by_miss(i);
        }
    }

    /// A miss on cell i, which it changes, and which then takes no other miss this scan: its
    /// bit is set until [`Cells::end_of_scan`]. (A cell that a miss leaves unchanged needs no
    /// such mark: every later miss in the scan leaves it unchanged too.)
    #[inline(never)]
    fn change_by_miss(&mut self, i: usize) {
        let old = self.logodds[i];
        let new = self.after_miss[usize::from(old as u8)];
        // `write` without its bitmap refresh: the bit is set regardless.
        self.logodds[i] = new;
        self.log.record(self.params, i, old, new);
        self.unchanged_by_miss[i / 64] |= 1 << (i % 64);
        self.missed_cells.push(i as u32);
    }

    /// Makes the bits of the cells missed this scan true again.
    fn end_of_scan(&mut self) {
        for k in 0..self.missed_cells.len() {
            self.refresh_unchanged_by_miss(self.missed_cells[k] as usize);
        }
        self.missed_cells.clear();
    }
}

/// `logodds` after evidence `delta`: a never-observed cell starts from 0 (p = 0.5); the sum
/// saturates and is clamped to ±[`LOGODDS_LIMIT`].
#[inline]
fn updated(logodds: i8, delta: i8) -> i8 {
    let base = if logodds == NEVER_OBSERVED {
        0
    } else {
        logodds
    };
    base.saturating_add(delta)
        .clamp(-LOGODDS_LIMIT, LOGODDS_LIMIT)
}

/// `updated(l, delta)` for every `l`, indexed by `l as u8`.
fn update_table(delta: i8) -> [i8; 256] {
    std::array::from_fn(|k| updated(k as u8 as i8, delta))
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
            after_miss: update_table(params.miss),
            after_hit: update_table(params.hit),
            // A miss always changes a never-observed cell: no bit is set.
            unchanged_by_miss: vec![0; n.div_ceil(64)],
            missed_cells: Vec::new(),
            hits: Vec::new(),
            log: ChangeLog {
                changed: Vec::new(),
                rows: RowOfIndex::new(geometry.width as usize, n),
                tiles_x,
                dirty_tiles: vec![false; tiles_x * tiles_y],
                known_cells: 0,
            },
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
        self.log.known_cells
    }

    /// Known (free or occupied) area, m².
    pub fn known_area_m2(&self) -> f64 {
        self.log.known_cells as f64 * self.geometry.cell_area_m2()
    }

    /// Takes the log of cells whose class changed since the last call.
    pub fn drain_changed(&mut self, into: &mut Vec<u32>) {
        into.append(&mut self.log.changed);
    }

    /// The cells and their bookkeeping, borrowed as slices so that a ray walk keeps their
    /// addresses in registers across the out-of-line slow path.
    fn cells(&mut self) -> Cells<'_> {
        Cells {
            params: &self.params,
            after_miss: &self.after_miss,
            logodds: &mut self.logodds,
            unchanged_by_miss: &mut self.unchanged_by_miss,
            missed_cells: &mut self.missed_cells,
            log: &mut self.log,
        }
    }

    /// Integrates one laser scan taken at `scan.pose` (the pose is trusted: localisation is
    /// given, as in paper 002's simulations). A finite range is a return (misses up to it, a
    /// hit where it ends), +∞ no return (misses up to `max_range_m`), NaN no reading at all.
    pub fn integrate_scan(&mut self, scan: &LaserScan) {
        let g = self.geometry;
        let inv_res = 1.0 / g.resolution_m;
        let (s, c) = scan.pose.theta.sin_cos();
        let (s0, c0) = scan.angle_min_rad.sin_cos();
        let (si, ci) = scan.angle_increment_rad.sin_cos();
        // Beam direction relative to the heading, advanced by rotation (no sin_cos per beam).
        let (mut bc, mut bs) = (c0, s0);
        let origin = scan.pose.position();
        let mut hits = std::mem::take(&mut self.hits);
        hits.clear();
        let after_hit = self.after_hit;
        let mut cells = self.cells();
        for &range in &scan.ranges_m {
            let (dc, ds) = (c * bc - s * bs, s * bc + c * bs);
            (bc, bs) = (bc * ci - bs * si, bs * ci + bc * si);
            if range.is_nan() {
                // No reading (a real log's invalid beam): neither a return nor free space.
                continue;
            }
            let hit = range.is_finite();
            let reach_t = if hit {
                f64::from(range)
            } else {
                scan.max_range_m
            } * inv_res;
            // Misses on the cells the beam leaves before its range; the cell where it ends
            // takes the hit (a return) or a miss (no return within the maximum range).
            let ray = GridRay::new(&g, origin, dc, ds);
            let end = ray.walk_to(g.width, g.height, reach_t, |i| {
                cells.miss_at(i);
                false
            });
            if let Some((i, _)) = end {
                if hit {
                    // Neighbouring beams often end in the same cell: a repeat is not kept.
                    if hits.last() != Some(&(i as u32)) {
                        hits.push(i as u32);
                    }
                } else {
                    cells.miss_at(i);
                }
            }
        }
        hits.sort_unstable();
        hits.dedup();
        for &i in &hits {
            let i = i as usize;
            let old = cells.logodds[i];
            let new = after_hit[usize::from(old as u8)];
            if new != old {
                cells.write(i, old, new);
            }
        }
        cells.end_of_scan();
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
        let n_tiles = self.log.dirty_tiles.len();
        let side = 1usize << TILE_SHIFT;
        let mut sum = vec![0i16; side];
        let mut observed = vec![false; side];
        for tile in 0..n_tiles {
            if !sources.iter().any(|s| s.log.dirty_tiles[tile]) {
                continue;
            }
            for span in self.tile_rows(tile) {
                let sum = &mut sum[..span.len()];
                let observed = &mut observed[..span.len()];
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
                    self.cells()
                        .set(span.start + k, merged_logodds(total, seen));
                }
            }
        }
        for s in sources.iter_mut() {
            s.log.dirty_tiles.fill(false);
        }
    }
}

impl OccupancyGrid {
    /// The cell-index spans of tile `tile`'s rows, south to north (tiles of the change log).
    fn tile_rows(&self, tile: usize) -> impl Iterator<Item = std::ops::Range<usize>> + use<> {
        let (w, h) = (self.geometry.width as usize, self.geometry.height as usize);
        let side = 1usize << TILE_SHIFT;
        let (x0, y0) = (
            (tile % self.log.tiles_x) * side,
            (tile / self.log.tiles_x) * side,
        );
        let x1 = (x0 + side).min(w);
        (y0..(y0 + side).min(h)).map(move |row| row * w + x0..row * w + x1)
    }
}

/// A merged cell: the clamped sum of its observers' log-odds, or never observed.
fn merged_logodds(sum: i16, observed: bool) -> i8 {
    if observed {
        sum.clamp(-i16::from(LOGODDS_LIMIT), i16::from(LOGODDS_LIMIT)) as i8
    } else {
        NEVER_OBSERVED
    }
}

/// Running sums of a fixed list of sources for [`OccupancyGrid::merge_tracked`]: per cell the
/// sum of the observed sources' log-odds and how many observed it, and each source's values as
/// last merged.
#[derive(Clone, Debug, Default)]
pub struct MergeSums {
    sum: Vec<i16>,
    observers: Vec<u16>,
    last: Vec<Vec<i8>>,
}

impl OccupancyGrid {
    /// The same result, cell for cell and in the same change-log order, as
    /// [`OccupancyGrid::merge_from`] when `sums` has followed every merge of this grid with the
    /// same list of `sources` (it starts empty and is reset when the list's length changes).
    /// Instead of adding up every source on every dirty tile, each source's dirty tiles update
    /// the running sums by the cells that changed since its last merge, and only those cells
    /// are merged again.
    pub fn merge_tracked(&mut self, sources: &mut [&mut OccupancyGrid], sums: &mut MergeSums) {
        let n = self.logodds.len();
        let reset = sums.last.len() != sources.len() || sums.sum.len() != n;
        if reset {
            // A new list: start from what the sources hold now, all of it.
            *sums = MergeSums {
                sum: vec![0; n],
                observers: vec![0; n],
                last: vec![vec![NEVER_OBSERVED; n]; sources.len()],
            };
            for s in sources.iter_mut() {
                s.log.dirty_tiles.fill(true);
            }
        }
        let n_tiles = self.log.dirty_tiles.len();
        for tile in 0..n_tiles {
            if !sources.iter().any(|s| s.log.dirty_tiles[tile]) {
                continue;
            }
            // Per row of the tile, a bit per column: the cells some source changed. The others
            // keep their merged value (it is the merge of the same sums); after a reset every
            // cell is computed again.
            let mut touched = [if reset { u32::MAX } else { 0 }; 1 << TILE_SHIFT];
            for (s, last) in sources.iter().zip(sums.last.iter_mut()) {
                if !s.log.dirty_tiles[tile] {
                    continue;
                }
                for (row_bits, span) in touched.iter_mut().zip(self.tile_rows(tile)) {
                    let now = &s.logodds[span.clone()];
                    let was = &mut last[span.clone()];
                    for_each_change(now, was, |k, now, was| {
                        let i = span.start + k;
                        if was != NEVER_OBSERVED {
                            sums.sum[i] -= i16::from(was);
                            sums.observers[i] -= 1;
                        }
                        if now != NEVER_OBSERVED {
                            sums.sum[i] += i16::from(now);
                            sums.observers[i] += 1;
                        }
                        *row_bits |= 1 << k;
                    });
                }
            }
            for (&row_bits, span) in touched.iter().zip(self.tile_rows(tile)) {
                // Columns in order, as a merge of every cell sets them.
                let mut bits = row_bits & (u32::MAX >> (32 - span.len()));
                while bits != 0 {
                    let i = span.start + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let target = merged_logodds(sums.sum[i], sums.observers[i] > 0);
                    self.cells().set(i, target);
                }
            }
        }
        for s in sources.iter_mut() {
            s.log.dirty_tiles.fill(false);
        }
    }
}

/// Calls `change(k, now[k], was[k])` for each k where the two differ, in order, and copies
/// `now` into `was`. Compares eight cells at a time: most are unchanged since the last merge.
#[inline]
fn for_each_change(now: &[i8], was: &mut [i8], mut change: impl FnMut(usize, i8, i8)) {
    // Cell by cell, from index `k0`.
    let mut cells = |k0: usize, now: &[i8], was: &mut [i8]| {
        for (j, (&n, w)) in now.iter().zip(was.iter_mut()).enumerate() {
            if n != *w {
                change(k0 + j, n, *w);
                *w = n;
            }
        }
    };
    let mut k = 0;
    for (now8, was8) in now.chunks_exact(8).zip(was.chunks_exact_mut(8)) {
        let (a, b): ([i8; 8], [i8; 8]) = (
            now8.try_into().expect("eight cells"),
            (&*was8).try_into().expect("eight cells"),
        );
        if a != b {
            cells(k, now8, was8);
        }
        k += 8;
    }
    cells(k, &now[k..], &mut was[k..]);
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

    #[test]
    fn tracked_merging_equals_merging_every_source_with_the_same_change_log() {
        use rand::SeedableRng;
        let g = GridGeometry::new(90, 70, 0.1, Point2::new(0.0, 0.0));
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let mut robots: Vec<OccupancyGrid> = (0..3)
            .map(|_| OccupancyGrid::new(g, OccupancyParams::default()))
            .collect();
        let mut copies = robots.clone();
        let mut full = OccupancyGrid::new(g, OccupancyParams::default());
        let mut tracked = full.clone();
        let mut sums = MergeSums::default();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for round in 0..12 {
            for (k, (r, c)) in robots.iter_mut().zip(copies.iter_mut()).enumerate() {
                if (round + k) % 3 != 0 {
                    let scan = random_scan(&mut rng, &g, 60);
                    r.integrate_scan(&scan);
                    c.integrate_scan(&scan);
                }
            }
            full.merge_from(&mut robots.iter_mut().collect::<Vec<_>>());
            tracked.merge_tracked(&mut copies.iter_mut().collect::<Vec<_>>(), &mut sums);
            assert_eq!(full.logodds(), tracked.logodds(), "round {round}");
            a.clear();
            b.clear();
            full.drain_changed(&mut a);
            tracked.drain_changed(&mut b);
            assert_eq!(a, b, "round {round}");
            assert_eq!(full.known_cells(), tracked.known_cells());
        }
    }

    #[test]
    fn row_of_index_by_multiplication_equals_division() {
        for width in [
            1usize,
            2,
            3,
            7,
            32,
            100,
            999,
            1000,
            1024,
            4095,
            65_537,
            1 << 20,
        ] {
            let rows = RowOfIndex::new(width, u32::MAX as usize);
            let near_ends = (0..2000).chain(u32::MAX as usize - 2000..=u32::MAX as usize);
            for i in near_ends.chain((0..4000).map(|k| k * 1_073_741 % u32::MAX as usize)) {
                assert_eq!(rows.row_and_col(i), (i / width, i % width), "{i} / {width}");
            }
        }
    }

    /// The update as first written, before its speed-ups (tabulated updates, the bitmap of
    /// cells a miss leaves unchanged, a bitmap of the scan's misses): the reference the fast one
    /// must match.
    struct ReferenceGrid {
        params: OccupancyParams,
        width: usize,
        tiles_x: usize,
        logodds: Vec<i8>,
        stamp: Vec<u32>,
        scan_number: u32,
        changed: Vec<u32>,
        dirty_tiles: Vec<bool>,
        known_cells: usize,
    }

    impl ReferenceGrid {
        fn new(grid: &OccupancyGrid) -> Self {
            Self {
                params: grid.params,
                width: grid.geometry.width as usize,
                tiles_x: grid.log.tiles_x,
                logodds: grid.logodds.clone(),
                stamp: vec![0; grid.logodds.len()],
                scan_number: 0,
                changed: Vec::new(),
                dirty_tiles: grid.log.dirty_tiles.clone(),
                known_cells: grid.log.known_cells,
            }
        }

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
                let (row, col) = (i / self.width, i % self.width);
                self.dirty_tiles[(row >> TILE_SHIFT) * self.tiles_x + (col >> TILE_SHIFT)] = true;
            }
        }

        fn apply(&mut self, i: usize, delta: i8) {
            let old = self.logodds[i];
            let base = if old == NEVER_OBSERVED { 0 } else { old };
            self.set(
                i,
                base.saturating_add(delta)
                    .clamp(-LOGODDS_LIMIT, LOGODDS_LIMIT),
            );
        }

        fn miss(&mut self, i: usize) {
            if self.stamp[i] != self.scan_number {
                self.stamp[i] = self.scan_number;
                self.apply(i, self.params.miss);
            }
        }

        fn integrate_scan(&mut self, g: &GridGeometry, scan: &LaserScan) {
            self.scan_number += 1;
            let mut hits = Vec::new();
            for (k, &range) in scan.ranges_m.iter().enumerate() {
                // Same beam directions as the grid (rotation by the increment).
                let (s, c) = scan.pose.theta.sin_cos();
                let (mut bs, mut bc) = scan.angle_min_rad.sin_cos();
                let (si, ci) = scan.angle_increment_rad.sin_cos();
                for _ in 0..k {
                    (bc, bs) = (bc * ci - bs * si, bs * ci + bc * si);
                }
                let (dc, ds) = (c * bc - s * bs, s * bc + c * bs);
                if range.is_nan() {
                    // No reading: nothing drawn (REP 117).
                    continue;
                }
                let hit = range.is_finite();
                let reach_t = if hit {
                    f64::from(range)
                } else {
                    scan.max_range_m
                } / g.resolution_m;
                let ray = GridRay::new(g, scan.pose.position(), dc, ds);
                let end = ray.walk_to(g.width, g.height, reach_t, |i| {
                    self.miss(i);
                    false
                });
                match end {
                    Some((i, _)) if hit => hits.push(i),
                    Some((i, _)) => self.miss(i),
                    None => {}
                }
            }
            hits.sort_unstable();
            hits.dedup();
            for i in hits {
                self.apply(i, self.params.hit);
            }
        }

        /// `merge_from` with a single source whose values and dirty tiles are given (tile by
        /// tile, row by row, as the change log records them).
        fn merge_from_one(&mut self, source: &[i8], source_dirty: &[bool]) {
            let side = 1 << TILE_SHIFT;
            let height = source.len() / self.width;
            for (tile, _) in source_dirty.iter().enumerate().filter(|(_, d)| **d) {
                let (x0, y0) = ((tile % self.tiles_x) * side, (tile / self.tiles_x) * side);
                for row in y0..(y0 + side).min(height) {
                    for col in x0..(x0 + side).min(self.width) {
                        let i = row * self.width + col;
                        self.set(i, source[i]);
                    }
                }
            }
        }
    }

    fn random_scan(rng: &mut impl rand::Rng, g: &GridGeometry, beams: usize) -> LaserScan {
        let size = Point2::new(
            g.width as f64 * g.resolution_m,
            g.height as f64 * g.resolution_m,
        );
        let max_range_m = rng.random_range(0.2..4.0);
        LaserScan {
            // Mostly inside the grid, sometimes beyond its border.
            pose: Pose2::new(
                rng.random_range(-0.3..size.x + 0.3),
                rng.random_range(-0.3..size.y + 0.3),
                rng.random_range(-3.2..3.2),
            ),
            angle_min_rad: -std::f64::consts::PI,
            angle_increment_rad: std::f64::consts::TAU / beams as f64,
            max_range_m,
            ranges_m: (0..beams)
                .map(|_| match rng.random_range(0..10) {
                    0 => f32::INFINITY,
                    1 => f32::NAN,
                    2 => -0.5,
                    _ => rng.random_range(0.0..max_range_m * 1.2) as f32,
                })
                .collect(),
        }
    }

    /// The fast update matches the reference on every value, the change log (in order), the
    /// count of known cells and the dirty tiles, through hundreds of scans, merges, and sensor
    /// models whose miss saturates, is zero or is positive.
    #[test]
    fn integration_matches_the_reference_update_exactly() {
        use rand::SeedableRng;
        let g = GridGeometry::new(70, 45, 0.1, Point2::new(0.0, 0.0));
        let models = [
            OccupancyParams::default(),
            OccupancyParams {
                hit: 40,
                miss: -40,
                occupied_above: 10,
            },
            OccupancyParams {
                hit: 3,
                miss: 0,
                occupied_above: 0,
            },
            OccupancyParams {
                hit: -5,
                miss: 7,
                occupied_above: -3,
            },
        ];
        for (m, params) in models.into_iter().enumerate() {
            let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(m as u64);
            let mut grid = OccupancyGrid::new(g, params);
            let mut other = OccupancyGrid::new(g, params);
            let mut reference = ReferenceGrid::new(&grid);
            let (mut changed, mut expected_changed) = (Vec::new(), Vec::new());
            for scan_index in 0..600 {
                let scan = random_scan(&mut rng, &g, 48);
                grid.integrate_scan(&scan);
                reference.integrate_scan(&g, &scan);
                if scan_index % 97 == 96 {
                    other.integrate_scan(&random_scan(&mut rng, &g, 48));
                    let (values, dirty) = (other.logodds.clone(), other.log.dirty_tiles.clone());
                    grid.merge_from(&mut [&mut other]);
                    reference.merge_from_one(&values, &dirty);
                }
                grid.drain_changed(&mut changed);
                expected_changed.append(&mut reference.changed);
                assert_eq!(
                    grid.logodds, reference.logodds,
                    "model {m}, scan {scan_index}"
                );
                assert_eq!(changed, expected_changed, "model {m}, scan {scan_index}");
                assert_eq!(grid.known_cells(), reference.known_cells);
                assert_eq!(grid.log.dirty_tiles, reference.dirty_tiles);
            }
        }
    }
}

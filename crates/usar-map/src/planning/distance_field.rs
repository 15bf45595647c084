//! A distance field: one multi-source search that prices every cell at once (the distance to the
//! nearest source, e.g. a robot, or a frontier), with the path back to that source.
//!
//! Both connectivities are *exact* Dijkstra searches in O(cells), with no priority queue.
//! [`Connectivity::Four`] is a breadth-first search (unit costs).
//!
//! [`Connectivity::Eight`] (straight moves 1, diagonal moves √2) keeps a bucket queue of width 1,
//! the least edge cost (Dial 1969; the Δ-stepping argument of Meyer & Sanders 2003 with Δ = the
//! least edge weight): bucket k holds the cells whose tentative distance lies in [k, k + 1). A
//! cell relaxed from a cell of bucket k gets a distance ≥ k + 1, so no cell of bucket k can lower
//! another one: once the buckets below k are done, every cell of bucket k is final, in whatever
//! order the bucket is scanned. Moves reach only buckets k + 1 and k + 2 (√2 < 2), so three
//! buckets are reused in turn. A queued entry holds no key, only the cell; one whose cell has
//! since dropped into an earlier bucket is stale and skipped.
//!
//! Each bucket keeps one list per move that queued the cell, and each list is scanned by code
//! specialised to that move, which tries only the moves of [`MOVES_TO_TRY`]: from a cell reached
//! by a straight move, five moves; by a diagonal one, three (the others provably cannot lower a
//! distance). Half the neighbour tests of a plain scan, each with fewer mispredicted branches.
//! A cell lowered again inside its bucket by another move is queued again under that move, so
//! the moves of its final one are always tried (a repeat scan lowers nothing).
//!
//! The distances are the same f64 sums of 1 and √2 that [`super::GridAStar`] computes, equal to
//! A*'s lengths up to the rounding of the summation order (< 1e-9 cells on any grid below 10⁶
//! cells a side). Diagonal moves follow the same rule as A*: only when both orthogonal cells are
//! passable.
//!
//! Only the distance (8 bytes) is kept per cell, with blocked cells marked by a negative value
//! and unreached ones by infinity, so the search reads one array: a neighbour is lowered exactly
//! when its new distance is below its stored one, which is never true of a blocked cell
//! (negative) nor of a final one. Paths back to a source are found by steepest descent: from a
//! cell of distance d, step to the first neighbour (in [`usar_world::NEIGHBORS8`] order) whose
//! distance plus the move's cost is d. The cell the search reached it from qualifies (its
//! distance was summed exactly so), so the descent always reaches a source along a shortest path.

use super::grid_astar::{Connectivity, DIAGONAL_COST, GridPath, MAX_CELLS};
use super::nav_grid::{NavGrid, PASSABLE};
use super::open_list::Fifo;

use usar_world::{Cell, Grid, GridGeometry, NEIGHBORS8, Point2};

/// Relative tolerance of the descent's test d(next) + cost = d(cell): the distances are exact
/// sums, so this only absorbs a different summation order.
const DESCENT_TOLERANCE: f64 = 1e-12;

/// Stored distance of a blocked cell (any negative value: no new distance is below it).
const BLOCKED_DISTANCE: f64 = -1.0;

/// The list of a bucket holding sources, from which every move is tried.
const SOURCE_MOVE: usize = 8;

/// The lists of one bucket: cells by the move that queued them (index in
/// [`usar_world::NEIGHBORS8`]), index [`SOURCE_MOVE`] for the sources.
type MoveLists = [Vec<u32>; 9];

/// The moves worth trying from a cell, as bit masks over the move indices of
/// [`usar_world::NEIGHBORS8`] (bits 0–3 east, north, west, south; 4–7 north-east, north-west,
/// south-west, south-east), by the move that gave the cell its distance (index 8: a source).
///
/// A neighbour v is left out when a cell with a smaller distance is bound to offer v a distance
/// below the one this cell would (by at least 2 − √2, far above rounding), so trying it could
/// never succeed. For a cell u reached from its parent p:
/// * by a straight move (east, say): p itself, and p's north and south neighbours, which p
///   reaches by one straight move (d(p) + 1 = d(u) < d(u) + √2);
/// * by a diagonal move (north-east, say): p; the west and south neighbours of u, which are p's
///   north and east neighbours (passable, or the diagonal move were not allowed) at
///   d(p) + 1 < d(p) + √2 + 1; and u's north-west and south-east neighbours, two straight moves
///   from p (d(p) + 2 < d(p) + 2√2).
///
/// The cells offering the bound have smaller distances, so they were scanned in an earlier
/// bucket (any move costs at least 1) and either tried the move or left it out for the same
/// reason, by induction on the distance. Only the moves ahead remain: five after a straight
/// move, three after a diagonal one.
const MOVES_TO_TRY: [u32; 9] = [
    0b1001_1011, // east: E, N, S, NE, SE
    0b0011_0111, // north: E, N, W, NE, NW
    0b0110_1110, // west: N, W, S, NW, SW
    0b1100_1101, // south: E, W, S, SW, SE
    0b0001_0011, // north-east: E, N, NE
    0b0010_0110, // north-west: N, W, NW
    0b0100_1100, // south-west: W, S, SW
    0b1000_1001, // south-east: E, S, SE
    0b1111_1111, // a source: all
];

/// The two straight moves beside each diagonal move (north-east: east and north, …), whose
/// cells must be passable for it.
const DIAGONAL_SIDES: [(usize, usize); 4] = [(0, 1), (2, 1), (2, 3), (0, 3)];

/// The neighbours whose distances a scan of the list of each move reads: the moves it tries and
/// the cells beside its diagonal ones.
const NEEDED: [u32; 9] = {
    let mut needed = [0; 9];
    let mut m = 0;
    while m < 9 {
        let moves = MOVES_TO_TRY[m];
        needed[m] = moves;
        let mut k = 4;
        while k < 8 {
            if moves & (1 << k) != 0 {
                let (a, b) = DIAGONAL_SIDES[k - 4];
                needed[m] |= (1 << a) | (1 << b);
            }
            k += 1;
        }
        m += 1;
    }
    needed
};

/// Distances from a set of source cells to every cell of a [`NavGrid`].
///
/// The buffers are kept between [`DistanceField::compute`] calls: recomputing on a grid of the
/// same size allocates nothing.
#[derive(Clone, Debug)]
pub struct DistanceField {
    geometry: GridGeometry,
    stride: usize,
    connectivity: Connectivity,
    /// Per padded cell: distance to the nearest source in cells once reached, `INFINITY` if
    /// passable and unreached, [`BLOCKED_DISTANCE`] if blocked. Empty when nothing was computed
    /// (or the grid was too large).
    distance: Vec<f64>,
    /// The passable sources, in the order given.
    sources: Vec<Cell>,
    /// Per padded cell, [`PASSABLE`] while not reached by the breadth-first search
    /// ([`Connectivity::Four`]); a dense copy of the grid that keeps its tests in cache.
    unvisited: Vec<u8>,
    /// Breadth-first queue ([`Connectivity::Four`]).
    frontier: Fifo<u32>,
    /// The three buckets in use ([`Connectivity::Eight`]): the one being scanned, the next one
    /// and the one after it.
    buckets: [MoveLists; 3],
    reached: usize,
    /// Padded indices of the cells a search may stop after settling (reused buffer).
    pending_targets: Vec<u32>,
}

impl Default for DistanceField {
    fn default() -> Self {
        Self::new()
    }
}

impl DistanceField {
    /// An empty field (no cell reachable) with no buffers yet.
    pub fn new() -> Self {
        Self {
            geometry: GridGeometry::new(0, 0, 1.0, Point2::new(0.0, 0.0)),
            stride: 2,
            connectivity: Connectivity::Four,
            distance: Vec::new(),
            unvisited: Vec::new(),
            frontier: Fifo::default(),
            sources: Vec::new(),
            buckets: Default::default(),
            reached: 0,
            pending_targets: Vec::new(),
        }
    }

    /// Prices every cell of `grid` by its distance to the nearest of `sources`.
    ///
    /// Sources that are blocked or outside the grid are ignored; with no usable source (or on a
    /// grid of more than 2³² − 1 padded cells) every cell is unreachable. Duplicate sources
    /// count once.
    pub fn compute(&mut self, grid: &NavGrid, sources: &[Cell], connectivity: Connectivity) {
        self.compute_until_settled(grid, sources, connectivity, &[]);
    }

    /// [`DistanceField::compute`] that may stop early, once every cell of `targets` is settled
    /// (an 8-connected search stops after the bucket that settles the last of them; a
    /// 4-connected one always runs to the end). The distances of the targets, and of every cell
    /// nearer to the sources than the farthest target, are then final, and so are the paths back
    /// from them ([`DistanceField::path_to_source`], [`DistanceField::descent_step`]): a path
    /// descends through nearer cells only. Farther cells may hold a larger, provisional distance
    /// or none. Targets that are blocked or outside the grid are ignored; one that is not
    /// reachable makes the search run to the end. With no targets this is `compute`.
    pub fn compute_until_settled(
        &mut self,
        grid: &NavGrid,
        sources: &[Cell],
        connectivity: Connectivity,
        targets: &[Cell],
    ) {
        let len = grid.cells().len();
        self.geometry = *grid.geometry();
        self.stride = grid.stride();
        self.connectivity = connectivity;
        self.sources.clear();
        self.reached = 0;
        if len > MAX_CELLS {
            // Nothing is reachable: `index` finds no distance for any cell.
            self.distance.clear();
            return;
        }
        // Every entry is written: the buffer is only resized (filled) when the size changes.
        // ∞ and −1 differ in their two top bits only: the start distances are bit operations,
        // which the compiler vectorises (a branch per cell costs five instructions a cell, on
        // every search).
        const FLIP: u64 = f64::INFINITY.to_bits() ^ BLOCKED_DISTANCE.to_bits();
        self.distance.resize(len, BLOCKED_DISTANCE);
        for (d, &c) in self.distance.iter_mut().zip(grid.cells()) {
            *d = f64::from_bits(BLOCKED_DISTANCE.to_bits() ^ (u64::from(c == PASSABLE) * FLIP));
        }
        for list in self.buckets.iter_mut().flatten() {
            list.clear();
        }
        for &s in sources {
            if !grid.is_passable(s) {
                continue;
            }
            let i = grid.padded_index(s);
            if self.distance[i] == 0.0 {
                continue;
            }
            self.distance[i] = 0.0;
            self.sources.push(s);
            self.buckets[0][SOURCE_MOVE].push(i as u32);
        }
        match connectivity {
            Connectivity::Four => self.breadth_first(grid),
            Connectivity::Eight => {
                let mut pending = std::mem::take(&mut self.pending_targets);
                pending.clear();
                pending.extend(
                    targets
                        .iter()
                        .filter(|&&t| grid.is_passable(t))
                        .map(|&t| grid.padded_index(t) as u32),
                );
                // With no target, the search runs until no bucket is left.
                if targets.is_empty() {
                    pending.push(u32::MAX);
                }
                self.bucket_dijkstra(&pending);
                self.pending_targets = pending;
            }
        }
    }

    /// Unit-cost breadth-first search: the first time a cell is reached is final. Visits are
    /// marked in a byte copy of the grid, denser in cache than the distances.
    fn breadth_first(&mut self, grid: &NavGrid) {
        let s = self.stride as isize;
        let offsets = [1isize, s, -1, -s];
        self.unvisited.clear();
        self.unvisited.extend_from_slice(grid.cells());
        // Locals, so that the compiler keeps the buffers in registers.
        let (unvisited, distance) = (&mut self.unvisited[..], &mut self.distance[..]);
        let frontier = &mut self.frontier;
        frontier.clear();
        for &source in &self.buckets[0][SOURCE_MOVE] {
            unvisited[source as usize] = 0;
            frontier.push(source);
        }
        let mut reached = 0;
        while let Some(cur) = frontier.pop() {
            let cur = cur as usize;
            reached += 1;
            let next_d = distance[cur] + 1.0;
            for &o in &offsets {
                let next = cur.wrapping_add_signed(o);
                if unvisited[next] == PASSABLE {
                    unvisited[next] = 0;
                    distance[next] = next_d;
                    frontier.push(next as u32);
                }
            }
        }
        self.reached = reached;
    }

    /// Exact Dijkstra with a bucket queue of width 1, one list per move (see the module
    /// documentation).
    /// Stops once the cells of `targets` (padded indices; `u32::MAX`: none, never settled) are
    /// settled.
    fn bucket_dijkstra(&mut self, targets: &[u32]) {
        let stride = self.stride;
        let distance = &mut self.distance[..];
        let [b0, b1, b2] = &mut self.buckets;
        // The bucket being scanned, the next one and the one after it.
        let (mut current, mut next, mut after) = (b0, b1, b2);
        let mut reached = current[SOURCE_MOVE].len();
        let mut level = 0.0;
        // Targets settled so far (a prefix of `targets`).
        let mut settled = 0;
        while [&*current, &*next, &*after]
            .iter()
            .any(|bucket| bucket.iter().any(|list| !list.is_empty()))
        {
            reached += scan_bucket(current, next, after, distance, stride, level);
            for list in current.iter_mut() {
                list.clear();
            }
            (current, next, after) = (next, after, current);
            level += 1.0;
            // Every distance below `level` is final now.
            while let Some(&t) = targets.get(settled) {
                if t == u32::MAX || distance[t as usize] >= level {
                    break;
                }
                settled += 1;
            }
            if settled == targets.len() {
                break;
            }
        }
        self.reached = reached;
    }

    /// Geometry of the grid of the last computation.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// Connectivity of the last computation.
    pub fn connectivity(&self) -> Connectivity {
        self.connectivity
    }

    /// The sources actually used (passable, in the order given, duplicates removed).
    pub fn sources(&self) -> &[Cell] {
        &self.sources
    }

    /// Number of cells reached (sources included).
    pub fn reached_count(&self) -> usize {
        self.reached
    }

    /// Padded index of a reached cell.
    fn index(&self, cell: Cell) -> Option<usize> {
        self.geometry
            .contains(cell)
            .then(|| (cell.row as usize + 1) * self.stride + cell.col as usize + 1)
            .filter(|&i| self.distance.get(i).is_some_and(|&d| reached(d)))
    }

    /// Distance in cells from `cell` to its nearest source; `None` when unreachable or outside.
    pub fn distance_cells(&self, cell: Cell) -> Option<f64> {
        self.index(cell).map(|i| self.distance[i])
    }

    /// Distance in metres (cells × the grid's resolution).
    pub fn distance_m(&self, cell: Cell) -> Option<f64> {
        self.distance_cells(cell)
            .map(|d| d * self.geometry.resolution_m)
    }

    /// A nearest source of `cell` (the end of [`DistanceField::path_to_source`]); `None` when
    /// unreachable. Costs one descent, O(path length).
    pub fn nearest_source(&self, cell: Cell) -> Option<Cell> {
        self.path_to_source(cell)
            .and_then(|p| p.cells.last().copied())
    }

    /// A shortest path from `cell` to a nearest source (first cell `cell`, last the source), by
    /// steepest descent over the distances.
    pub fn path_to_source(&self, cell: Cell) -> Option<GridPath> {
        let mut i = self.index(cell)?;
        let length_cells = self.distance[i];
        let mut cells = vec![self.cell_of_padded(i)];
        while self.distance[i] > 0.0 {
            // The cell the search reached `i` from always qualifies; stop rather than loop if
            // the buffers were ever inconsistent.
            i = self.descend(i)?;
            cells.push(self.cell_of_padded(i));
        }
        Some(GridPath {
            cells,
            length_cells,
        })
    }

    /// The step [`DistanceField::path_to_source`] takes from `cell`: the next cell towards its
    /// nearest source. `None` at a source, or when `cell` is unreachable or outside.
    pub fn descent_step(&self, cell: Cell) -> Option<Cell> {
        let i = self.index(cell)?;
        if self.distance[i] > 0.0 {
            self.descend_move(i).map(|(_, k)| {
                let (dc, dr) = NEIGHBORS8[k];
                Cell::new(cell.col + dc, cell.row + dr)
            })
        } else {
            None
        }
    }

    /// One step of the steepest descent from the reached, non-source padded cell `i`: the first
    /// neighbour (in [`usar_world::NEIGHBORS8`] order) whose distance plus the move's cost is
    /// `i`'s.
    fn descend(&self, i: usize) -> Option<usize> {
        self.descend_move(i).map(|(j, _)| j)
    }

    /// [`DistanceField::descend`] with the index of the move taken.
    #[inline]
    fn descend_move(&self, i: usize) -> Option<(usize, usize)> {
        let s = self.stride as isize;
        // Padded offsets of the moves in [`usar_world::NEIGHBORS8`] order.
        let offsets = [1, s, -1, -s, s + 1, s - 1, -s - 1, -s + 1];
        let distance = &self.distance[..];
        let d = distance[i];
        let tolerance = DESCENT_TOLERANCE * d.max(1.0);
        let moves = if self.connectivity == Connectivity::Eight {
            8
        } else {
            4
        };
        for (k, &offset) in offsets.iter().enumerate().take(moves) {
            let next = i.wrapping_add_signed(offset);
            let dn = distance[next];
            if !reached(dn) {
                continue;
            }
            let cost = if k < 4 {
                1.0
            } else {
                // Only when both orthogonal cells are passable.
                let (a, b) = DIAGONAL_SIDES[k - 4];
                if distance[i.wrapping_add_signed(offsets[a])] < 0.0
                    || distance[i.wrapping_add_signed(offsets[b])] < 0.0
                {
                    continue;
                }
                DIAGONAL_COST
            };
            if (dn + cost - d).abs() <= tolerance {
                return Some((next, k));
            }
        }
        None
    }

    /// Walks the steepest descent of [`DistanceField::path_to_source`] from `cell`: `go_on` is
    /// asked about each cell reached, `cell` first, and `moved(c, k)` told of each step, from
    /// `c` by move `k` of [`usar_world::NEIGHBORS8`]. Returns the cell where the walk ended (a
    /// source, or the first cell `go_on` refused); `None` when `cell` is unreachable or outside.
    pub fn descend_while(
        &self,
        cell: Cell,
        mut go_on: impl FnMut(Cell) -> bool,
        mut moved: impl FnMut(Cell, usize),
    ) -> Option<Cell> {
        let mut i = self.index(cell)?;
        let mut c = cell;
        while go_on(c) && self.distance[i] > 0.0 {
            let (next, k) = self.descend_move(i)?;
            moved(c, k);
            let (dc, dr) = NEIGHBORS8[k];
            c = Cell::new(c.col + dc, c.row + dr);
            i = next;
        }
        Some(c)
    }

    /// The whole field as a grid of distances in cells, `INFINITY` where unreachable.
    pub fn to_grid(&self) -> Grid<f64> {
        let g = self.geometry;
        let mut out = Grid::filled(g, f64::INFINITY);
        let w = g.width as usize;
        if w > 0 && !self.distance.is_empty() {
            for (row, dst) in out.as_mut_slice().chunks_exact_mut(w).enumerate() {
                let start = (row + 1) * self.stride + 1;
                for (d, &dist) in dst.iter_mut().zip(&self.distance[start..start + w]) {
                    if reached(dist) {
                        *d = dist;
                    }
                }
            }
        }
        out
    }

    fn cell_of_padded(&self, i: usize) -> Cell {
        Cell::new((i % self.stride) as i32 - 1, (i / self.stride) as i32 - 1)
    }
}

/// Scans every list of the current bucket (distances in [`level`, `level` + 1)); returns the
/// number of cells reached for the first time. Out of line: the lists' loops get the registers
/// to themselves.
#[inline(never)]
fn scan_bucket(
    current: &MoveLists,
    next: &mut MoveLists,
    after: &mut MoveLists,
    distance: &mut [f64],
    stride: usize,
    level: f64,
) -> usize {
    let (c, n, a) = (current, next, after);
    scan_list::<0>(&c[0], distance, stride, level, n, a)
        + scan_list::<1>(&c[1], distance, stride, level, n, a)
        + scan_list::<2>(&c[2], distance, stride, level, n, a)
        + scan_list::<3>(&c[3], distance, stride, level, n, a)
        + scan_list::<4>(&c[4], distance, stride, level, n, a)
        + scan_list::<5>(&c[5], distance, stride, level, n, a)
        + scan_list::<6>(&c[6], distance, stride, level, n, a)
        + scan_list::<7>(&c[7], distance, stride, level, n, a)
        + scan_list::<SOURCE_MOVE>(&c[SOURCE_MOVE], distance, stride, level, n, a)
}

/// Scans the cells of the current bucket (distances in [`level`, `level` + 1)) queued by move
/// `MOVE` (or the sources), trying the moves of `MOVES_TO_TRY[MOVE]`, and queues each neighbour
/// it lowers in the list of that move in `next` (bucket level + 1) or `after` (level + 2).
/// Returns the number of cells reached for the first time.
#[inline(always)]
fn scan_list<const MOVE: usize>(
    cells: &[u32],
    distance: &mut [f64],
    stride: usize,
    level: f64,
    next: &mut MoveLists,
    after: &mut MoveLists,
) -> usize {
    let moves = MOVES_TO_TRY[MOVE];
    let s = stride as isize;
    // Padded offsets of the moves in [`usar_world::NEIGHBORS8`] order.
    let offsets = [1, s, -1, -s, s + 1, s - 1, -s - 1, -s + 1];
    let after_level = level + 2.0;
    let mut reached = 0;
    for &cell in cells {
        let cur = cell as usize;
        let d = distance[cur];
        // Stale: the cell's distance dropped into an earlier bucket, scanned already.
        if d < level {
            continue;
        }
        // The neighbours' distances, in move order; only those the moves tried need are read
        // (the others count as blocked).
        let old: [f64; 8] = std::array::from_fn(|k| {
            if NEEDED[MOVE] & (1 << k) != 0 {
                distance[cur.wrapping_add_signed(offsets[k])]
            } else {
                BLOCKED_DISTANCE
            }
        });
        // Straight moves land in bucket level + 1. Blocked (negative) and final cells are
        // never lowered.
        let nd = d + 1.0;
        for k in 0..4 {
            if moves & (1 << k) != 0 && nd < old[k] {
                let i = cur.wrapping_add_signed(offsets[k]);
                distance[i] = nd;
                reached += usize::from(old[k] == f64::INFINITY);
                next[k].push(i as u32);
            }
        }
        // Diagonal moves, allowed when both orthogonal cells are passable (≥ 0), land in
        // bucket level + 1 or level + 2.
        let nd = d + DIAGONAL_COST;
        let target = if nd < after_level {
            &mut *next
        } else {
            &mut *after
        };
        let free = old.map(|v| v >= 0.0);
        for k in 4..8 {
            let (a, b) = DIAGONAL_SIDES[k - 4];
            if moves & (1 << k) != 0 && free[a] && free[b] && nd < old[k] {
                let i = cur.wrapping_add_signed(offsets[k]);
                distance[i] = nd;
                reached += usize::from(old[k] == f64::INFINITY);
                target[k].push(i as u32);
            }
        }
    }
    reached
}

/// True for the stored distance of a reached cell (not blocked, not infinite).
#[inline]
fn reached(distance: f64) -> bool {
    (0.0..f64::INFINITY).contains(&distance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_floor_distances_are_manhattan_and_octile() {
        let g = GridGeometry::new(9, 6, 0.5, Point2::new(0.0, 0.0));
        let grid = NavGrid::from_fn(g, |_| false);
        let mut field = DistanceField::new();
        let src = Cell::new(2, 1);
        field.compute(&grid, &[src], Connectivity::Four);
        assert_eq!(field.distance_cells(Cell::new(7, 4)), Some(8.0));
        assert_eq!(field.distance_m(Cell::new(7, 4)), Some(4.0));
        assert_eq!(field.reached_count(), 54);
        field.compute(&grid, &[src], Connectivity::Eight);
        let d = field.distance_cells(Cell::new(7, 4)).unwrap();
        assert!((d - (2.0 + 3.0 * DIAGONAL_COST)).abs() < 1e-12);
        let path = field.path_to_source(Cell::new(7, 4)).unwrap();
        assert_eq!(path.cells.first(), Some(&Cell::new(7, 4)));
        assert_eq!(path.cells.last(), Some(&src));
        assert_eq!(field.nearest_source(Cell::new(0, 0)), Some(src));
        assert_eq!(field.distance_cells(Cell::new(9, 0)), None);
    }
}

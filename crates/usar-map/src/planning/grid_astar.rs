//! A* on a [`NavGrid`]: 4- or 8-connected, octile costs, no corner cutting, reusable scratch
//! memory.
//!
//! Hart, Nilsson & Raphael 1968 ("A Formal Basis for the Heuristic Determination of Minimum Cost
//! Paths"): expand the open cell of least f = g + h. Costs follow the MovingAI benchmarks
//! (Sturtevant 2012): a straight move costs 1, a diagonal move √2 and is allowed only when both
//! orthogonal cells it passes are passable. The heuristics (Manhattan for 4-connected, octile
//! `max(dx, dy) + (√2 − 1)·min(dx, dy)` for 8-connected) are consistent, so a closed cell is never
//! reopened and the first time the goal is taken from the open list its g is optimal.

use super::nav_grid::{NavGrid, PASSABLE};
use serde::{Deserialize, Serialize};
use usar_world::Cell;

/// Cost of a diagonal move, cells.
pub const DIAGONAL_COST: f64 = std::f64::consts::SQRT_2;

/// Which neighbours a move may reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Connectivity {
    /// East, north, west, south; every move costs 1.
    Four,
    /// The four straight moves (cost 1) and the four diagonals (cost √2), a diagonal only when
    /// both orthogonal cells beside it are passable (no corner cutting).
    Eight,
}

impl Connectivity {
    /// The admissible, consistent heuristic for this connectivity, cells: Manhattan for
    /// [`Connectivity::Four`], octile for [`Connectivity::Eight`].
    #[inline]
    pub fn heuristic(self, from: Cell, to: Cell) -> f64 {
        let dx = (from.col - to.col).unsigned_abs() as f64;
        let dy = (from.row - to.row).unsigned_abs() as f64;
        match self {
            Connectivity::Four => dx + dy,
            Connectivity::Eight => octile(dx, dy),
        }
    }
}

/// Octile distance `max + (√2 − 1)·min`.
#[inline]
fn octile(dx: f64, dy: f64) -> f64 {
    let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
    hi + (DIAGONAL_COST - 1.0) * lo
}

/// A path of grid cells, first cell to last cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridPath {
    /// Every cell visited, both ends included; consecutive cells are neighbours.
    pub cells: Vec<Cell>,
    /// Length in cells: the sum of its steps (1 straight, √2 diagonal).
    pub length_cells: f64,
}

impl GridPath {
    /// Length in metres on a grid of `resolution_m`.
    pub fn length_m(&self, resolution_m: f64) -> f64 {
        self.length_cells * resolution_m
    }

    /// Number of moves (cells − 1).
    pub fn steps(&self) -> usize {
        self.cells.len().saturating_sub(1)
    }
}

/// Width of one bucket of the open list, in units of f (cells).
///
/// It must be smaller than the least positive change of f along one move, so that a cell opened
/// from the cell being expanded either has the same f (it lands on the current bucket) or lands
/// on a later bucket. Along a move f = g + h changes by 0 or by at least 2 − √2 ≈ 0.586 with the
/// octile heuristic (Δg ∈ {1, √2}, Δh ∈ {±1, ±(√2 − 1), ±√2, √2 − 2, 2 − √2, 0}), and by 0 or 2
/// with Manhattan.
const BUCKET_WIDTH: f64 = 0.5;

/// An open-list entry, 16 bytes.
#[derive(Clone, Copy, Debug)]
struct OpenEntry {
    /// f = g + h, cells.
    f: f64,
    /// h, cells, rounded to f32: among entries of equal f the smaller h has the larger g; the
    /// rounding can only reorder entries whose h differ by less than ~1e-3 cells.
    h: f32,
    /// Padded index of the cell.
    node: u32,
}

/// A sort key growing with urgency: least f first, then least h (= largest g, the cell deeper
/// along its path). f and h are non-negative, so the integer order of their bits is their float
/// order.
#[inline]
fn urgency_rank(e: &OpenEntry) -> u128 {
    (u128::from(!e.f.to_bits()) << 32) | u128::from(!e.h.to_bits())
}

/// ⌊f / BUCKET_WIDTH⌋ (f ≥ 0, so truncation is the floor).
#[inline(always)]
fn bucket_of(f: f64) -> i64 {
    (f * (1.0 / BUCKET_WIDTH)) as i64
}

/// The open list: a bucket queue over f (Dial 1969) whose current bucket is a stack.
///
/// While a bucket is current, every entry pushed into it has the f of the entry just popped
/// (see [`BUCKET_WIDTH`]) and a larger g than any entry left with that f (the popped entry had
/// the largest), so pushing it on top keeps the most urgent entry on top: ties in f go to the
/// larger g, at O(1) amortised cost instead of a binary heap's O(log n).
///
/// The entries a bucket received before it became current are ordered once, when it does:
/// - with `sort_buckets` (8-connected, where one bucket spans several f values), sorted by f,
///   then by h (the smaller h has the larger g), which is the order of a binary heap on (f, −g);
/// - without it (4-connected: f is an integer and a bucket holds one f value), they stay in
///   push order and come out last-in first-out. Sorting them by g as well cuts expansions by
///   ~5 % on a 1000×1000 building floor but costs ~30 % more time.
///
/// Pushes of one expansion must come in order of increasing g (straight moves before
/// diagonal ones) for the top of the stack to stay the most urgent.
#[derive(Clone, Debug, Default)]
struct BucketQueue {
    buckets: Vec<Vec<OpenEntry>>,
    /// ⌊f / BUCKET_WIDTH⌋ of bucket 0.
    base: i64,
    current: usize,
    /// Buckets `..used` may hold entries.
    used: usize,
    /// Sort a bucket when it becomes current (needed when a bucket spans several f values).
    sort_buckets: bool,
}

impl BucketQueue {
    fn reset(&mut self, f0: f64, sort_buckets: bool) {
        self.sort_buckets = sort_buckets;
        for bucket in &mut self.buckets[..self.used] {
            bucket.clear();
        }
        self.base = bucket_of(f0);
        self.current = 0;
        self.used = 0;
    }

    #[inline(always)]
    fn push(&mut self, entry: OpenEntry) {
        // Rounding may put an entry of the current f a hair below the current bucket: clamp.
        let index = (bucket_of(entry.f) - self.base).max(self.current as i64) as usize;
        if index >= self.buckets.len() {
            self.buckets.resize_with(index + 1, Vec::new);
        }
        self.used = self.used.max(index + 1);
        self.buckets[index].push(entry);
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<OpenEntry> {
        loop {
            if let Some(entry) = self.buckets.get_mut(self.current)?.pop() {
                return Some(entry);
            }
            self.current += 1;
            if self.current >= self.used {
                return None;
            }
            if self.sort_buckets {
                self.buckets[self.current].sort_unstable_by_key(urgency_rank);
            }
        }
    }
}

/// Grid A* with scratch memory kept between searches: after the first search on a grid of a
/// given size, planning allocates only the returned path.
#[derive(Clone, Debug, Default)]
pub struct GridAStar {
    /// Per padded cell: `2·search` while open, `2·search + 1` once closed, anything else:
    /// untouched by this search (so nothing is cleared between searches).
    stamp: Vec<u16>,
    /// Best cost found from the start, cells; valid where `stamp` is this search's.
    g: Vec<f64>,
    /// Padded index of the cell each one was reached from (`u32::MAX` for the start).
    parent: Vec<u32>,
    open: BucketQueue,
    search: u16,
    expanded: usize,
}

impl GridAStar {
    /// A planner with no scratch memory yet (it grows on the first search).
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of cells expanded (taken from the open list and closed) by the last search.
    pub fn expanded(&self) -> usize {
        self.expanded
    }

    /// A shortest path from `start` to `goal`, or `None` when either is blocked or outside the
    /// grid, or the goal cannot be reached.
    pub fn plan(
        &mut self,
        grid: &NavGrid,
        start: Cell,
        goal: Cell,
        connectivity: Connectivity,
    ) -> Option<GridPath> {
        self.expanded = 0;
        if !grid.is_passable(start) || !grid.is_passable(goal) {
            return None;
        }
        let h0 = connectivity.heuristic(start, goal);
        self.prepare(grid.cells().len(), h0, connectivity == Connectivity::Eight);
        let open_stamp = 2 * self.search;
        let closed_stamp = open_stamp + 1;

        let stride = grid.stride();
        let cells = grid.cells();
        let start_i = grid.padded_index(start);
        let goal_i = grid.padded_index(goal);
        let (goal_col, goal_row) = (goal.col + 1, goal.row + 1);
        let s = stride as isize;
        let straight: [(isize, i32, i32); 4] = [(1, 1, 0), (s, 0, 1), (-1, -1, 0), (-s, 0, -1)];
        let diagonal: [(isize, i32, i32); 4] =
            [(s + 1, 1, 1), (s - 1, -1, 1), (-s - 1, -1, -1), (-s + 1, 1, -1)];
        let eight = connectivity == Connectivity::Eight;

        // Locals, so that the compiler keeps the buffers in registers.
        let mut search = Search {
            stamp: &mut self.stamp[..],
            g: &mut self.g[..],
            parent: &mut self.parent[..],
            open: &mut self.open,
            open_stamp,
            closed_stamp,
        };
        search.stamp[start_i] = open_stamp;
        search.g[start_i] = 0.0;
        search.parent[start_i] = u32::MAX;
        search.open.push(OpenEntry { f: h0, h: h0 as f32, node: start_i as u32 });

        let mut expanded = 0;
        let mut found = false;
        while let Some(entry) = search.open.pop() {
            let cur = entry.node as usize;
            if search.stamp[cur] == closed_stamp {
                continue;
            }
            search.stamp[cur] = closed_stamp;
            expanded += 1;
            if cur == goal_i {
                found = true;
                break;
            }
            let g_cur = search.g[cur];
            // Padded coordinates of the current cell (the border shifts both by one).
            let col = (cur % stride) as i32;
            let row = (cur / stride) as i32;
            for &(offset, dc, dr) in &straight {
                let next = (cur as isize + offset) as usize;
                if cells[next] != PASSABLE {
                    continue;
                }
                let h = heuristic_padded(eight, col + dc - goal_col, row + dr - goal_row);
                search.relax(next, cur, g_cur + 1.0, h);
            }
            if eight {
                for &(offset, dc, dr) in &diagonal {
                    let next = (cur as isize + offset) as usize;
                    if cells[next] != PASSABLE
                        || cells[(cur as isize + dc as isize) as usize] != PASSABLE
                        || cells[(cur as isize + dr as isize * s) as usize] != PASSABLE
                    {
                        continue;
                    }
                    let h = heuristic_padded(true, col + dc - goal_col, row + dr - goal_row);
                    search.relax(next, cur, g_cur + DIAGONAL_COST, h);
                }
            }
        }
        self.expanded = expanded;
        found.then(|| self.reconstruct(grid, goal_i))
    }

    /// Grows the scratch buffers to `len` padded cells and starts a new search stamp.
    fn prepare(&mut self, len: usize, f0: f64, sort_buckets: bool) {
        if self.stamp.len() < len {
            self.stamp.resize(len, 0);
            self.g.resize(len, f64::INFINITY);
            self.parent.resize(len, u32::MAX);
        }
        self.open.reset(f0, sort_buckets);
        // Stamps 2·search and 2·search + 1 must not collide with older ones.
        if self.search >= u16::MAX / 2 - 1 {
            self.stamp.fill(0);
            self.search = 0;
        }
        self.search += 1;
    }

    fn reconstruct(&self, grid: &NavGrid, goal_i: usize) -> GridPath {
        let mut cells = Vec::new();
        let mut i = goal_i as u32;
        while i != u32::MAX {
            cells.push(grid.cell_of_padded(i as usize));
            i = self.parent[i as usize];
        }
        cells.reverse();
        GridPath { cells, length_cells: self.g[goal_i] }
    }
}

/// The buffers of one search, borrowed apart so that the hot loop keeps them in registers.
struct Search<'a> {
    stamp: &'a mut [u16],
    g: &'a mut [f64],
    parent: &'a mut [u32],
    open: &'a mut BucketQueue,
    open_stamp: u16,
    closed_stamp: u16,
}

impl Search<'_> {
    /// Opens `next`, reached from `cur` at cost `g_next`, unless it is closed or already open
    /// at a cost no higher.
    #[inline(always)]
    fn relax(&mut self, next: usize, cur: usize, g_next: f64, h: f64) {
        let st = self.stamp[next];
        if st == self.closed_stamp || (st == self.open_stamp && self.g[next] <= g_next) {
            return;
        }
        self.stamp[next] = self.open_stamp;
        self.g[next] = g_next;
        self.parent[next] = cur as u32;
        self.open.push(OpenEntry { f: g_next + h, h: h as f32, node: next as u32 });
    }
}

/// The heuristic from integer offsets to the goal.
#[inline(always)]
fn heuristic_padded(eight: bool, dcol: i32, drow: i32) -> f64 {
    let dx = dcol.unsigned_abs() as f64;
    let dy = drow.unsigned_abs() as f64;
    if eight { octile(dx, dy) } else { dx + dy }
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::{GridGeometry, Point2};

    fn open_grid(w: u32, h: u32) -> NavGrid {
        NavGrid::from_fn(GridGeometry::new(w, h, 1.0, Point2::new(0.0, 0.0)), |_| false)
    }

    #[test]
    fn open_floor_lengths_are_manhattan_and_octile() {
        let grid = open_grid(10, 7);
        let mut astar = GridAStar::new();
        let (a, b) = (Cell::new(1, 1), Cell::new(8, 5));
        let four = astar.plan(&grid, a, b, Connectivity::Four).unwrap();
        assert_eq!(four.length_cells, 11.0);
        assert_eq!(four.cells.len(), 12);
        // Tie-breaking toward larger g walks straight at the goal: no extra expansions.
        assert_eq!(astar.expanded(), 12);
        let eight = astar.plan(&grid, a, b, Connectivity::Eight).unwrap();
        assert!((eight.length_cells - (3.0 + 4.0 * DIAGONAL_COST)).abs() < 1e-12);
        assert_eq!(eight.cells.first(), Some(&a));
        assert_eq!(eight.cells.last(), Some(&b));
    }

    #[test]
    fn start_equal_to_goal_is_a_one_cell_path() {
        let grid = open_grid(3, 3);
        let p = GridAStar::new().plan(&grid, Cell::new(1, 1), Cell::new(1, 1), Connectivity::Eight);
        assert_eq!(p, Some(GridPath { cells: vec![Cell::new(1, 1)], length_cells: 0.0 }));
    }

    #[test]
    fn diagonal_between_two_blocked_corners_is_refused() {
        // . #
        // # .   the two free cells touch only at a corner.
        let g = GridGeometry::new(2, 2, 1.0, Point2::new(0.0, 0.0));
        let grid = NavGrid::from_fn(g, |c| c.col != c.row);
        let mut astar = GridAStar::new();
        assert_eq!(astar.plan(&grid, Cell::new(0, 0), Cell::new(1, 1), Connectivity::Eight), None);
    }
}

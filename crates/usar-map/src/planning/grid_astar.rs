//! A* on a [`NavGrid`]: 4- or 8-connected, octile costs, no corner cutting, reusable scratch
//! memory; 8-connected planning by jump point search (`jump_point.rs`) unless plain A* is asked
//! for ([`GridAlgorithm`]).
//!
//! Hart, Nilsson & Raphael 1968 ("A Formal Basis for the Heuristic Determination of Minimum Cost
//! Paths"): expand the open cell of least f = g + h. Costs follow the MovingAI benchmarks
//! (Sturtevant 2012): a straight move costs 1, a diagonal move √2 and is allowed only when both
//! orthogonal cells it passes are passable. The heuristics (Manhattan for 4-connected, octile
//! `max(dx, dy) + (√2 − 1)·min(dx, dy)` for 8-connected) are consistent, so a closed cell is never
//! reopened and the first time the goal is taken from the open list its g is optimal.
//!
//! g is summed in f64, so lengths match the MovingAI optima to rounding. The open list (see
//! `open_list.rs`) is exact and O(1) per operation: with these costs and heuristics f changes by
//! one of six values along a move, so one FIFO queue per value replaces the binary heap. Ties in f
//! go to the larger g (the cell just reached, deeper along its path), which on open floors walks
//! straight at the goal instead of fanning out over every cell of equal f.
//!
//! Grids are limited to 2³² − 1 cells including the border (cell indices are `u32`).

use super::jump_point::{JumpPointScratch, JumpPointSearch};
use super::nav_grid::NavGrid;
use super::open_list::{OpenEntry, OpenList};
use super::separation::Separation;
use serde::{Deserialize, Serialize};
use usar_world::Cell;

/// Most padded cells a planner handles (cell indices are `u32`).
pub(crate) const MAX_CELLS: usize = u32::MAX as usize - 1;

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
pub(crate) fn octile(dx: f64, dy: f64) -> f64 {
    let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
    hi + (DIAGONAL_COST - 1.0) * lo
}

/// The search algorithm of [`GridAStar::plan_with`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GridAlgorithm {
    /// Plain A*, expanding cell by cell (both connectivities).
    AStar,
    /// Jump point search (see `jump_point.rs`): A* over the cells where an optimal
    /// path may turn, same optimal lengths, far fewer expansions on open floors and in
    /// corridors. 8-connected only: with [`Connectivity::Four`] plain A* runs instead.
    JumpPoint,
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

/// Grid A* (and jump point search) with scratch memory kept between searches: after the first
/// search on a grid of a given size, planning allocates only the returned path.
#[derive(Clone, Debug, Default)]
pub struct GridAStar {
    /// Per padded cell: `2·search` while open, `2·search + 1` once closed, anything else:
    /// untouched by this search (so nothing is cleared between searches).
    stamp: Vec<u16>,
    /// Best cost found from the start, cells; valid where `stamp` is this search's.
    g: Vec<f64>,
    open: OpenList,
    /// Parent links and open list of jump point search.
    jump: JumpPointScratch,
    search: u16,
    expanded: usize,
    /// Cells stepped on by the jumps of the last search (0 for plain A*).
    scanned: usize,
    /// The floods that answer "no path" before a search would examine the start's whole part.
    separation: Separation,
}

impl GridAStar {
    /// A planner with no scratch memory yet (it grows on the first search).
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of cells expanded (taken from the open list and closed) by the last search: with
    /// jump point search, the jump points expanded; 0 when no search ran (a blocked end, or a
    /// goal found unreachable beforehand, see `separation.rs`).
    pub fn expanded(&self) -> usize {
        self.expanded
    }

    /// Cells the jumps of the last search stepped on (a cell scanned by several jumps counts
    /// each time): the work of jump point search besides its expansions; 0 for plain A*.
    pub fn scanned(&self) -> usize {
        self.scanned
    }

    /// Open-list pushes of the last search whose step of f matched none of the reduced-cost
    /// classes and went to the fallback heap: always 0 with the built-in heuristics (the tests
    /// check it); a diagnostic of the open list's invariant.
    pub fn fallback_pushes(&self) -> usize {
        self.open.fallback_pushes()
    }

    /// A shortest path from `start` to `goal`, or `None` when either is blocked or outside the
    /// grid, or the goal cannot be reached (or the grid has more than 2³² − 1 padded cells).
    ///
    /// 8-connected searches use jump point search, 4-connected ones plain A*
    /// ([`GridAStar::plan_with`] chooses); both return an optimal path.
    pub fn plan(
        &mut self,
        grid: &NavGrid,
        start: Cell,
        goal: Cell,
        connectivity: Connectivity,
    ) -> Option<GridPath> {
        self.plan_with(grid, start, goal, connectivity, GridAlgorithm::JumpPoint)
    }

    /// Like [`GridAStar::plan`], with the search algorithm chosen: the path's length is the
    /// same optimum either way (up to the rounding of its sum), the cells of the path may
    /// differ among equally short ones.
    pub fn plan_with(
        &mut self,
        grid: &NavGrid,
        start: Cell,
        goal: Cell,
        connectivity: Connectivity,
        algorithm: GridAlgorithm,
    ) -> Option<GridPath> {
        self.expanded = 0;
        self.scanned = 0;
        if !grid.is_passable(start) || !grid.is_passable(goal) || grid.cells().len() > MAX_CELLS {
            return None;
        }
        if self
            .separation
            .separated(grid, grid.padded_index(start), grid.padded_index(goal))
        {
            // The goal lies in another connected part: nothing is expanded.
            return None;
        }
        self.prepare(grid.cells().len());
        if algorithm == GridAlgorithm::JumpPoint && connectivity == Connectivity::Eight {
            let jps = JumpPointSearch::new(
                grid,
                grid.padded_index(goal),
                &mut self.stamp,
                &mut self.g,
                2 * self.search,
                &mut self.jump,
            );
            let (path, expanded) = jps.run(grid.padded_index(start));
            self.expanded = expanded;
            self.scanned = self.jump.scanned();
            return path;
        }
        self.plain_astar(grid, start, goal, connectivity)
    }

    /// Plain A* (the scratch buffers prepared).
    fn plain_astar(
        &mut self,
        grid: &NavGrid,
        start: Cell,
        goal: Cell,
        connectivity: Connectivity,
    ) -> Option<GridPath> {
        let h0 = connectivity.heuristic(start, goal);
        let open_stamp = 2 * self.search;
        let closed_stamp = open_stamp + 1;

        let stride = grid.stride();
        let start_i = grid.padded_index(start);
        let goal_i = grid.padded_index(goal);
        let (goal_col, goal_row) = (goal.col + 1, goal.row + 1);
        let move_table = grid.move_table();
        let eight = connectivity == Connectivity::Eight;

        // Locals, so that the compiler keeps the buffers in registers.
        let mut search = Search {
            stamp: &mut self.stamp[..],
            g: &mut self.g[..],
            open: &mut self.open,
            open_stamp,
            closed_stamp,
            f_expanded: h0,
        };
        search.stamp[start_i] = open_stamp;
        search.g[start_i] = 0.0;
        search.open.push(
            OpenEntry {
                f: h0,
                h: h0 as f32,
                node: start_i as u32,
            },
            h0,
        );

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
            search.f_expanded = entry.f;
            // Padded coordinates of the current cell (the border shifts both by one).
            let col = (cur % stride) as i32;
            let row = (cur / stride) as i32;
            // Straight moves come first (lower bits): on the stack of equal f, the diagonal
            // (larger g) then lies on top.
            let mut moves = grid.allowed_moves(cur, eight);
            while moves != 0 {
                let k = moves.trailing_zeros() as usize;
                moves &= moves - 1;
                let (offset, dc, dr, cost) = move_table[k];
                let next = (cur as isize + offset) as usize;
                search.relax(next, g_cur + cost, || {
                    heuristic_padded(eight, col + dc - goal_col, row + dr - goal_row)
                });
            }
        }
        self.expanded = expanded;
        found.then(|| self.reconstruct(grid, goal_i, eight))
    }

    /// Grows the scratch buffers to `len` padded cells and starts a new search stamp.
    fn prepare(&mut self, len: usize) {
        if self.stamp.len() < len {
            self.stamp.resize(len, 0);
            self.g.resize(len, f64::INFINITY);
        }
        self.open.clear();
        // Stamps 2·search and 2·search + 1 must not collide with older ones.
        if self.search >= u16::MAX / 2 - 1 {
            self.stamp.fill(0);
            self.search = 0;
        }
        self.search += 1;
    }

    /// The path from the start to `goal_i`, by steepest descent over g from the goal: step to
    /// the first closed neighbour (allowed move, in [`usar_world::NEIGHBORS8`] order) whose g plus
    /// the move's cost is this cell's g. Closed cells have optimal g (consistent heuristic), and
    /// the cell a cell was opened from always qualifies, so no parent array is needed.
    fn reconstruct(&self, grid: &NavGrid, goal_i: usize, eight: bool) -> GridPath {
        let closed_stamp = 2 * self.search + 1;
        let move_table = grid.move_table();
        let mut i = goal_i;
        let mut cells = vec![grid.cell_of_padded(i)];
        while self.g[i] > 0.0 {
            let g = self.g[i];
            let mut moves = grid.allowed_moves(i, eight);
            let mut step = None;
            while moves != 0 {
                let k = moves.trailing_zeros() as usize;
                moves &= moves - 1;
                let (offset, _, _, cost) = move_table[k];
                let next = (i as isize + offset) as usize;
                if self.stamp[next] == closed_stamp
                    && (self.g[next] + cost - g).abs() <= RECONSTRUCT_TOLERANCE * g
                {
                    step = Some(next);
                    break;
                }
            }
            // Some closed neighbour always qualifies; never loop if that were ever violated.
            let Some(next) = step else { break };
            i = next;
            cells.push(grid.cell_of_padded(i));
        }
        cells.reverse();
        GridPath {
            cells,
            length_cells: self.g[goal_i],
        }
    }
}

/// Relative tolerance of the reconstruction's test g(next) + cost = g(cell): g values are exact
/// sums, so this only absorbs a different summation order.
const RECONSTRUCT_TOLERANCE: f64 = 1e-12;

/// The buffers of one search, borrowed apart so that the hot loop keeps them in registers.
struct Search<'a> {
    stamp: &'a mut [u16],
    g: &'a mut [f64],
    open: &'a mut OpenList,
    open_stamp: u16,
    closed_stamp: u16,
    /// f of the cell being expanded.
    f_expanded: f64,
}

impl Search<'_> {
    /// Opens `next`, reached from `cur` at cost `g_next`, unless it is closed or already open
    /// at a cost no higher; `h` computes its heuristic, only when it is opened.
    #[inline(always)]
    fn relax(&mut self, next: usize, g_next: f64, h: impl FnOnce() -> f64) {
        let st = self.stamp[next];
        if st == self.closed_stamp || (st == self.open_stamp && self.g[next] <= g_next) {
            return;
        }
        let h = h();
        self.stamp[next] = self.open_stamp;
        self.g[next] = g_next;
        self.open.push(
            OpenEntry {
                f: g_next + h,
                h: h as f32,
                node: next as u32,
            },
            self.f_expanded,
        );
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
        NavGrid::from_fn(GridGeometry::new(w, h, 1.0, Point2::new(0.0, 0.0)), |_| {
            false
        })
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
        assert_eq!(
            p,
            Some(GridPath {
                cells: vec![Cell::new(1, 1)],
                length_cells: 0.0
            })
        );
    }

    #[test]
    fn diagonal_between_two_blocked_corners_is_refused() {
        // . #
        // # .   the two free cells touch only at a corner.
        let g = GridGeometry::new(2, 2, 1.0, Point2::new(0.0, 0.0));
        let grid = NavGrid::from_fn(g, |c| c.col != c.row);
        let mut astar = GridAStar::new();
        assert_eq!(
            astar.plan(&grid, Cell::new(0, 0), Cell::new(1, 1), Connectivity::Eight),
            None
        );
    }
}

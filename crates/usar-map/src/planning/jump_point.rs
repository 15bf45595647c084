//! Jump point search (JPS): optimal 8-connected grid planning that expands only the cells where
//! an optimal path may turn, without corner cutting.
//!
//! Harabor & Grastien 2011 ("Online Graph Pruning for Pathfinding on Grid Maps") observe that on
//! a uniform-cost grid most optimal paths are symmetric: they differ only in the order of the
//! same moves. JPS keeps one canonical path of each class, *diagonal moves first*, and jumps over
//! every cell where such a path cannot turn. This module uses the movement model of Harabor &
//! Grastien 2014 ("Improving Jump Point Search") and of the MovingAI benchmarks: straight
//! moves cost 1, diagonal moves √2 and are allowed only when both orthogonal cells beside them
//! are passable. Under that model the pruning rules are:
//!
//! * Arrived at x by a **diagonal** move (dc, dr): the natural neighbours are the straight moves
//!   (dc, 0), (0, dr) and the diagonal (dc, dr). There are no forced neighbours: the cells behind
//!   x on both sides were passable (the move into x needed them), so every other neighbour is
//!   reached at least as cheaply from the parent.
//! * Arrived at x by a **straight** move d (say east): the natural neighbour is x + d. A side
//!   neighbour n = x + s (s = north or south) is *forced* when it is passable and the cell behind
//!   it, n − d, is blocked: no path through the parent reaches n without passing x. Then n and
//!   the diagonal x + d + s (if that move is allowed) are successors too.
//! * A straight jump from x in direction d steps along d until it hits a blocked cell (no
//!   successor), the goal, or a cell with a forced neighbour (a jump point). A diagonal jump
//!   steps diagonally while the move is allowed; at every cell c on the way it runs the two
//!   straight jumps along its components, and c is a turning point if either finds a jump point.
//!
//! The diagonal turning points are not put on the open list (intermediate jump points pruned):
//! the jump points found from them are generated at once as successors of the jump's origin,
//! with the parent link "diagonal moves first, then straight moves" (the shape of every
//! segment), and the diagonal scan goes on. Each segment is expanded back into its cells when
//! the path is rebuilt, so the returned path lists every cell, consecutive cells neighbours.
//!
//! The jump points form a graph whose edge costs are the segments' octile lengths; A* over them
//! with the consistent octile heuristic returns an optimal path (Harabor & Grastien 2011,
//! Theorem 1). The open list is a binary heap (jump points are few and edge costs arbitrary),
//! ties in f broken toward the larger g.

use super::grid_astar::{DIAGONAL_COST, GridPath, octile};
use super::nav_grid::{NavGrid, PASSABLE, PackedCells};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Scratch memory of JPS kept between searches (the stamps and g values are shared with
/// [`super::GridAStar`]'s plain A*).
#[derive(Clone, Debug, Default)]
pub(crate) struct JumpPointScratch {
    /// Padded index of the jump point each open or closed jump point was generated from (the
    /// start: itself).
    parent: Vec<u32>,
    heap: BinaryHeap<HeapEntry>,
    /// Cells stepped on by the jumps of the last search (a measure of its work).
    scanned: usize,
}

impl JumpPointScratch {
    /// Cells stepped on by the jumps of the last search.
    pub fn scanned(&self) -> usize {
        self.scanned
    }
}

/// An open-list entry: the heap pops the least f, then the largest g.
#[derive(Clone, Copy, Debug)]
struct HeapEntry {
    f: f64,
    g: f64,
    node: u32,
}

impl PartialEq for HeapEntry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for HeapEntry {}
impl PartialOrd for HeapEntry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for HeapEntry {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .f
            .total_cmp(&self.f)
            .then(self.g.total_cmp(&other.g))
            .then(other.node.cmp(&self.node))
    }
}

/// The buffers and constants of one search.
pub(crate) struct JumpPointSearch<'a> {
    cells: &'a [u8],
    packed: &'a PackedCells,
    stride: usize,
    goal: usize,
    /// Padded column and row of the goal.
    goal_col: i32,
    goal_row: i32,
    stamp: &'a mut [u16],
    g: &'a mut [f64],
    open_stamp: u16,
    closed_stamp: u16,
    scratch: &'a mut JumpPointScratch,
    scanned: usize,
}

impl<'a> JumpPointSearch<'a> {
    /// A search on `grid` towards the padded index `goal`, over buffers of at least the grid's
    /// padded length whose stamps hold neither `open_stamp` nor `open_stamp + 1`.
    pub fn new(
        grid: &'a NavGrid,
        goal: usize,
        stamp: &'a mut [u16],
        g: &'a mut [f64],
        open_stamp: u16,
        scratch: &'a mut JumpPointScratch,
    ) -> Self {
        let len = grid.cells().len();
        if scratch.parent.len() < len {
            scratch.parent.resize(len, 0);
        }
        scratch.heap.clear();
        let stride = grid.stride();
        Self {
            cells: grid.cells(),
            packed: grid.bit_lines(),
            stride,
            goal,
            goal_col: (goal % stride) as i32,
            goal_row: (goal / stride) as i32,
            stamp,
            g,
            open_stamp,
            closed_stamp: open_stamp + 1,
            scratch,
            scanned: 0,
        }
    }

    /// Runs the search from the padded index `start`; returns the path and the number of jump
    /// points expanded, or `None` and that number when the goal is unreachable.
    pub fn run(mut self, start: usize) -> (Option<GridPath>, usize) {
        self.relax(start, 0.0, start);
        let mut expanded = 0;
        let mut found = false;
        while let Some(entry) = self.scratch.heap.pop() {
            let x = entry.node as usize;
            if self.stamp[x] == self.closed_stamp || entry.g > self.g[x] {
                continue;
            }
            self.stamp[x] = self.closed_stamp;
            expanded += 1;
            if x == self.goal {
                found = true;
                break;
            }
            self.expand(x);
        }
        self.scratch.scanned = self.scanned;
        let path = found.then(|| self.reconstruct(start));
        (path, expanded)
    }

    #[inline(always)]
    fn free(&self, i: usize) -> bool {
        self.cells[i] == PASSABLE
    }

    /// The other axis' unit offset: `stride` for a horizontal step, 1 for a vertical one.
    #[inline(always)]
    fn side_of(&self, step: isize) -> isize {
        if step.unsigned_abs() == 1 {
            self.stride as isize
        } else {
            1
        }
    }

    /// Generates the successors of the closed jump point `x` (see the module documentation).
    fn expand(&mut self, x: usize) {
        let s = self.stride as isize;
        let parent = self.scratch.parent[x] as usize;
        if parent == x {
            // The start: every allowed move.
            for step in [1, s, -1, -s] {
                self.explore_straight(x, step);
            }
            for (h, v) in [(1, s), (-1, s), (-1, -s), (1, -s)] {
                self.explore_diagonal(x, h, v);
            }
            return;
        }
        // The last move into x: segments are diagonal moves first, then straight moves.
        let stride = self.stride as i32;
        let dc = (x as i32 % stride) - (parent as i32 % stride);
        let dr = (x as i32 / stride) - (parent as i32 / stride);
        let (h, v) = (dc.signum() as isize, dr.signum() as isize * s);
        if dc.abs() == dr.abs() {
            self.explore_straight(x, h);
            self.explore_straight(x, v);
            self.explore_diagonal(x, h, v);
        } else {
            let step = if dc.abs() > dr.abs() { h } else { v };
            self.explore_straight(x, step);
            let side = self.side_of(step);
            for n in [side, -side] {
                let xi = x as isize;
                if self.free((xi + n) as usize) && !self.free((xi - step + n) as usize) {
                    self.explore_straight(x, n);
                    self.explore_diagonal(x, step, n);
                }
            }
        }
    }

    /// Jumps from `x` along the straight direction `step` and opens the jump point found.
    #[inline]
    fn explore_straight(&mut self, x: usize, step: isize) {
        if let Some((y, moves)) = self.jump_straight(x, step) {
            self.relax(y, self.g[x] + f64::from(moves), x);
        }
    }

    /// Steps diagonally from `x` along `h + v` while the move is allowed; opens the goal or the
    /// jump points the straight jumps find from each cell on the way.
    fn explore_diagonal(&mut self, x: usize, h: isize, v: isize) {
        let g_x = self.g[x];
        let mut cur = x as isize;
        let mut k = 0u32;
        while self.free((cur + h) as usize)
            && self.free((cur + v) as usize)
            && self.free((cur + h + v) as usize)
        {
            cur += h + v;
            k += 1;
            self.scanned += 1;
            let c = cur as usize;
            let g_c = g_x + f64::from(k) * DIAGONAL_COST;
            if c == self.goal {
                self.relax(c, g_c, x);
                return;
            }
            for step in [h, v] {
                if let Some((y, moves)) = self.jump_straight(c, step) {
                    self.relax(y, g_c + f64::from(moves), x);
                }
            }
        }
    }

    /// Steps from `origin` along `step` until a blocked cell (`None`), the goal, or a cell with
    /// a forced neighbour; returns that cell and the number of moves to it. Scans 64 cells a
    /// step on the packed bits (see `bit_lines.rs`).
    #[inline]
    fn jump_straight(&mut self, origin: usize, step: isize) -> Option<(usize, u32)> {
        let stride = self.stride;
        let (row, col) = (origin / stride, origin % stride);
        // The line scanned, the position on it of the origin and of the goal (if on the line),
        // and the padded index step of one position.
        let (lines, line, pos, goal_pos, unit) = if step.unsigned_abs() == 1 {
            let goal = (row as i32 == self.goal_row).then_some(self.goal_col as usize);
            (&self.packed.rows, row, col, goal, 1)
        } else {
            let goal = (col as i32 == self.goal_col).then_some(self.goal_row as usize);
            (&self.packed.cols, col, row, goal, stride)
        };
        let forward = step > 0;
        let stop = if forward {
            lines.scan_forward(line, pos)
        } else {
            lines.scan_backward(line, pos)
        };
        let (lo, hi) = if forward { (pos, stop) } else { (stop, pos) };
        self.scanned += hi - lo;
        let to_index = |p: usize| {
            if unit == 1 {
                row * stride + p
            } else {
                p * stride + col
            }
        };
        if let Some(gp) = goal_pos
            && gp != pos
            && (lo..=hi).contains(&gp)
        {
            return Some((to_index(gp), gp.abs_diff(pos) as u32));
        }
        lines
            .is_set(line, stop)
            .then(|| (to_index(stop), stop.abs_diff(pos) as u32))
    }

    /// Opens `node` at cost `g` from the jump point `parent`, unless it is closed or already
    /// open at a cost no higher.
    #[inline]
    fn relax(&mut self, node: usize, g: f64, parent: usize) {
        let st = self.stamp[node];
        if st == self.closed_stamp || (st == self.open_stamp && self.g[node] <= g) {
            return;
        }
        self.stamp[node] = self.open_stamp;
        self.g[node] = g;
        self.scratch.parent[node] = parent as u32;
        let stride = self.stride;
        let dx = ((node % stride) as i32 - self.goal_col).unsigned_abs() as f64;
        let dy = ((node / stride) as i32 - self.goal_row).unsigned_abs() as f64;
        self.scratch.heap.push(HeapEntry {
            f: g + octile(dx, dy),
            g,
            node: node as u32,
        });
    }

    /// The cells from `start` to the goal: every segment between a jump point and its parent is
    /// diagonal moves first, then straight moves; walked back from the goal.
    fn reconstruct(&self, start: usize) -> GridPath {
        let stride = self.stride as i32;
        let (mut col, mut row) = (self.goal_col, self.goal_row);
        let mut cells = vec![usar_world::Cell::new(col - 1, row - 1)];
        let (mut straight, mut diagonal) = (0u64, 0u64);
        let mut i = self.goal;
        while i != start {
            let p = self.scratch.parent[i] as usize;
            let (pc, pr) = (p as i32 % stride, p as i32 / stride);
            let (dc, dr) = (col - pc, row - pr);
            let n_diagonal = dc.abs().min(dr.abs());
            let n_straight = dc.abs().max(dr.abs()) - n_diagonal;
            let (sc, sr) = if dc.abs() > dr.abs() {
                (dc.signum(), 0)
            } else {
                (0, dr.signum())
            };
            for _ in 0..n_straight {
                col -= sc;
                row -= sr;
                cells.push(usar_world::Cell::new(col - 1, row - 1));
            }
            for _ in 0..n_diagonal {
                col -= dc.signum();
                row -= dr.signum();
                cells.push(usar_world::Cell::new(col - 1, row - 1));
            }
            straight += n_straight as u64;
            diagonal += n_diagonal as u64;
            i = p;
        }
        cells.reverse();
        GridPath {
            cells,
            length_cells: straight as f64 + diagonal as f64 * DIAGONAL_COST,
        }
    }
}

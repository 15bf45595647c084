//! A distance field: one multi-source search that prices every cell at once (the distance to the
//! nearest source, e.g. a robot, or a frontier), with the path back to that source.
//!
//! Both connectivities are *exact* Dijkstra searches in O(cells), with no priority queue:
//! every edge costs either 1 (straight) or √2 (diagonal), so the search keeps one FIFO queue per
//! edge cost. A cell settled at distance d pushes its neighbours with keys d + 1 and d + √2 onto
//! the two queues; since cells are settled in non-decreasing d, each queue receives
//! non-decreasing keys and is therefore sorted, and the least open key is the smaller of the two
//! queue heads. This is Dijkstra's algorithm with a monotone multi-queue (the "few distinct edge
//! lengths" case of Dial 1969 / Ahuja, Mehlhorn, Orlin & Tarjan 1990), so no fixed-point rounding
//! is needed: the distances are the same f64 sums of 1 and √2 that [`super::GridAStar`]
//! computes, equal to A*'s lengths up to the rounding of the summation order (< 1e-9 cells on
//! any grid below 10⁶ cells a side). With [`Connectivity::Four`] only one queue is used and the
//! search is a breadth-first search with unit costs.
//!
//! Diagonal moves follow the same rule as A*: only when both orthogonal cells are passable.
//!
//! Only the distance (8 bytes) and a state byte are kept per cell, so that the search touches
//! as little memory as possible; paths back to a source are found by steepest descent: from a
//! cell of distance d, step to the first neighbour (in [`usar_world::NEIGHBORS8`] order) whose
//! distance plus the move's cost is d. The cell the search reached it from qualifies (its
//! distance was summed exactly so), so the descent always reaches a source along a shortest path.

use super::grid_astar::{Connectivity, DIAGONAL_COST, GridPath, MAX_CELLS};
use super::nav_grid::{BLOCKED, NavGrid, PASSABLE};

use super::open_list::Fifo;
use usar_world::{Cell, Grid, GridGeometry, NEIGHBORS8, Point2};

/// Relative tolerance of the descent's test d(next) + cost = d(cell): the distances are exact
/// sums, so this only absorbs a different summation order.
const DESCENT_TOLERANCE: f64 = 1e-12;

/// Search state of a cell: passable and not reached yet. The state buffer starts as a copy of
/// the grid, so blocked cells hold 0 and free ones this value.
const UNREACHED: u8 = PASSABLE;
/// Search state of a cell: reached, its distance may still fall ([`Connectivity::Eight`]).
const OPEN: u8 = 2;
/// Search state of a cell: its distance is final.
const SETTLED: u8 = 3;

/// Distances from a set of source cells to every cell of a [`NavGrid`].
///
/// The buffers are kept between [`DistanceField::compute`] calls: recomputing on a grid of the
/// same size allocates nothing.
#[derive(Clone, Debug)]
pub struct DistanceField {
    geometry: GridGeometry,
    stride: usize,
    connectivity: Connectivity,
    /// Distance to the nearest source, cells, per padded cell; meaningful where `state` is
    /// [`SETTLED`] (or [`OPEN`] during the search).
    distance: Vec<f64>,
    /// 0 (blocked), [`UNREACHED`], [`OPEN`] or [`SETTLED`] per padded cell.
    state: Vec<u8>,
    /// The passable sources, in the order given.
    sources: Vec<Cell>,
    /// Breadth-first queue ([`Connectivity::Four`]).
    frontier: Fifo<u32>,
    /// Cells opened by a straight move, with their distance (sorted by it).
    straight_queue: Fifo<(f64, u32)>,
    /// Cells opened by a diagonal move, with their distance (sorted by it).
    diagonal_queue: Fifo<(f64, u32)>,
    reached: usize,
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
            state: Vec::new(),
            frontier: Fifo::default(),
            sources: Vec::new(),
            straight_queue: Fifo::default(),
            diagonal_queue: Fifo::default(),
            reached: 0,
        }
    }

    /// Prices every cell of `grid` by its distance to the nearest of `sources`.
    ///
    /// Sources that are blocked or outside the grid are ignored; with no usable source (or on a
    /// grid of more than 2³² − 1 padded cells) every cell is unreachable. Ties between sources at equal distance go to the one listed first among
    /// those reaching the cell first (deterministic).
    pub fn compute(&mut self, grid: &NavGrid, sources: &[Cell], connectivity: Connectivity) {
        let len = grid.cells().len();
        self.geometry = *grid.geometry();
        self.stride = grid.stride();
        self.connectivity = connectivity;
        self.state.clear();
        self.sources.clear();
        self.reached = 0;
        if len > MAX_CELLS {
            // Nothing is reachable: `index` finds no state for any cell.
            return;
        }
        self.state.extend_from_slice(grid.cells());
        if self.distance.len() < len {
            self.distance.resize(len, f64::INFINITY);
        }
        self.sources.clear();
        self.frontier.clear();
        self.straight_queue.clear();
        self.diagonal_queue.clear();
        self.reached = 0;

        for &s in sources {
            if !grid.is_passable(s) {
                continue;
            }
            let i = grid.padded_index(s);
            if self.state[i] != UNREACHED {
                continue;
            }
            self.state[i] = match connectivity {
                Connectivity::Four => SETTLED,
                Connectivity::Eight => OPEN,
            };
            self.distance[i] = 0.0;
            self.sources.push(s);
            match connectivity {
                Connectivity::Four => self.frontier.push(i as u32),
                Connectivity::Eight => self.straight_queue.push((0.0, i as u32)),
            }
        }
        match connectivity {
            Connectivity::Four => self.breadth_first(),
            Connectivity::Eight => self.two_queue_dijkstra(grid),
        }
    }

    /// Unit-cost breadth-first search: the first time a cell is reached is final.
    fn breadth_first(&mut self) {
        let s = self.stride as isize;
        let offsets = [1isize, s, -1, -s];
        // Locals, so that the compiler keeps the buffers in registers.
        let (state, distance) = (&mut self.state[..], &mut self.distance[..]);
        let frontier = &mut self.frontier;
        let mut reached = 0;
        while let Some(cur) = frontier.pop() {
            let cur = cur as usize;
            reached += 1;
            let next_d = distance[cur] + 1.0;
            for &o in &offsets {
                let next = (cur as isize + o) as usize;
                if state[next] == UNREACHED {
                    state[next] = SETTLED;
                    distance[next] = next_d;
                    frontier.push(next as u32);
                }
            }
        }
        self.reached = reached;
    }

    /// Exact Dijkstra with one sorted FIFO queue per edge cost (1 and √2).
    fn two_queue_dijkstra(&mut self, grid: &NavGrid) {
        let cells = grid.cells();
        let s = self.stride as isize;
        let straight = [1isize, s, -1, -s];
        // (offset, the two orthogonal cells the diagonal passes)
        let diagonal = [
            (s + 1, 1, s),
            (s - 1, -1, s),
            (-s - 1, -1, -s),
            (-s + 1, 1, -s),
        ];
        let (state, distance) = (&mut self.state[..], &mut self.distance[..]);
        let (straight_queue, diagonal_queue) = (&mut self.straight_queue, &mut self.diagonal_queue);
        let mut reached = 0;
        loop {
            let from_straight = match (straight_queue.front(), diagonal_queue.front()) {
                (None, None) => break,
                (Some(_), None) => true,
                (None, Some(_)) => false,
                (Some(a), Some(b)) => a.0 <= b.0,
            };
            let queue = if from_straight {
                &mut *straight_queue
            } else {
                &mut *diagonal_queue
            };
            let Some((d, cur)) = queue.pop() else { break };
            let cur = cur as usize;
            // A cell is queued again only with a strictly smaller distance, so exactly one of its
            // entries carries its final distance: the others are stale.
            if state[cur] != OPEN || d > distance[cur] {
                continue;
            }
            state[cur] = SETTLED;
            reached += 1;
            let next_d = d + 1.0;
            for &o in &straight {
                let next = (cur as isize + o) as usize;
                let st = state[next];
                if st == UNREACHED || (st == OPEN && next_d < distance[next]) {
                    state[next] = OPEN;
                    distance[next] = next_d;
                    straight_queue.push((next_d, next as u32));
                }
            }
            let next_d = d + DIAGONAL_COST;
            for &(o, a, b) in &diagonal {
                let next = (cur as isize + o) as usize;
                let st = state[next];
                if (st == UNREACHED || (st == OPEN && next_d < distance[next]))
                    && cells[(cur as isize + a) as usize] == PASSABLE
                    && cells[(cur as isize + b) as usize] == PASSABLE
                {
                    state[next] = OPEN;
                    distance[next] = next_d;
                    diagonal_queue.push((next_d, next as u32));
                }
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

    fn index(&self, cell: Cell) -> Option<usize> {
        self.geometry
            .contains(cell)
            .then(|| (cell.row as usize + 1) * self.stride + cell.col as usize + 1)
            .filter(|&i| self.state.get(i) == Some(&SETTLED))
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
        let s = self.stride as isize;
        let eight = self.connectivity == Connectivity::Eight;
        let passable = |j: isize| self.state[j as usize] != BLOCKED;
        let mut cells = vec![self.cell_of_padded(i)];
        while self.distance[i] > 0.0 {
            let d = self.distance[i];
            let here = i as isize;
            let mut step = None;
            for (dc, dr) in NEIGHBORS8 {
                let diagonal = dc != 0 && dr != 0;
                if diagonal && !eight {
                    break;
                }
                let next = here + dc as isize + dr as isize * s;
                if self.state[next as usize] != SETTLED
                    || (diagonal
                        && !(passable(here + dc as isize) && passable(here + dr as isize * s)))
                {
                    continue;
                }
                let cost = if diagonal { DIAGONAL_COST } else { 1.0 };
                if (self.distance[next as usize] + cost - d).abs() <= DESCENT_TOLERANCE * d.max(1.0)
                {
                    step = Some(next as usize);
                    break;
                }
            }
            // The cell the search reached `i` from always qualifies; stop rather than loop if
            // the buffers were ever inconsistent.
            let next = step?;
            i = next;
            cells.push(self.cell_of_padded(i));
        }
        Some(GridPath {
            cells,
            length_cells,
        })
    }

    /// The whole field as a grid of distances in cells, `INFINITY` where unreachable.
    pub fn to_grid(&self) -> Grid<f64> {
        let g = self.geometry;
        let mut out = Grid::filled(g, f64::INFINITY);
        let w = g.width as usize;
        if w > 0 && !self.state.is_empty() {
            for (row, dst) in out.as_mut_slice().chunks_exact_mut(w).enumerate() {
                let start = (row + 1) * self.stride + 1;
                let states = &self.state[start..start + w];
                let distances = &self.distance[start..start + w];
                for ((d, &st), &dist) in dst.iter_mut().zip(states).zip(distances) {
                    if st == SETTLED {
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

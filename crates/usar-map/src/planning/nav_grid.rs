//! The planners' view of a map: passability in one flat byte buffer with a blocked border.

use super::bit_lines::BitLines;
use std::sync::OnceLock;
use usar_world::{Cell, Grid, GridGeometry};

/// Byte value of a cell a robot may enter.
pub(crate) const PASSABLE: u8 = 1;
/// Byte value of a blocked cell (and of the border).
pub(crate) const BLOCKED: u8 = 0;

/// Passability of a grid, stored row-major in a `Vec<u8>` with a one-cell blocked border, so
/// that the planners' neighbour loops need no bounds checks: every in-grid cell has all eight
/// neighbours in the buffer, and the border ones are blocked.
///
/// Padded index of cell (col, row) is `(row + 1) * (width + 2) + col + 1`.
///
/// Jump point search also reads the cells packed in bits (by rows and by columns); that copy is
/// built on its first use and dropped when a cell changes.
#[derive(Clone)]
pub struct NavGrid {
    geometry: GridGeometry,
    /// Width of a padded row, `width + 2`.
    stride: usize,
    /// `(width + 2) * (height + 2)` bytes, [`PASSABLE`] or [`BLOCKED`].
    cells: Vec<u8>,
    /// `cells` as bits, built on demand (see [`NavGrid::bit_lines`]).
    bits: OnceLock<PackedCells>,
}

/// The padded cells as bits: by rows, and by columns (transposed).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PackedCells {
    /// Line = padded row, position = padded column.
    pub rows: BitLines,
    /// Line = padded column, position = padded row.
    pub cols: BitLines,
}

impl PartialEq for NavGrid {
    /// Equal geometry and passability (whether the bit copy was built does not matter).
    fn eq(&self, other: &Self) -> bool {
        self.geometry == other.geometry && self.cells == other.cells
    }
}

impl std::fmt::Debug for NavGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NavGrid")
            .field("geometry", &self.geometry)
            .field("stride", &self.stride)
            .field("cells", &self.cells)
            .finish_non_exhaustive()
    }
}

impl NavGrid {
    /// A grid of the given geometry with every cell blocked.
    pub fn all_blocked(geometry: GridGeometry) -> Self {
        let stride = geometry.width as usize + 2;
        let cells = vec![BLOCKED; stride * (geometry.height as usize + 2)];
        Self {
            geometry,
            stride,
            cells,
            bits: OnceLock::new(),
        }
    }

    /// From a blocked mask: `true` = blocked (an obstacle, or an inflated one).
    pub fn from_blocked(blocked: &Grid<bool>) -> Self {
        Self::from_values(blocked, |&b| !b)
    }

    /// From a passable mask: `true` = free (e.g. a MovingAI map's `passable`).
    pub fn from_passable(passable: &Grid<bool>) -> Self {
        Self::from_values(passable, |&p| p)
    }

    /// From any grid and a predicate saying which values are passable.
    pub fn from_values<T>(grid: &Grid<T>, mut is_passable: impl FnMut(&T) -> bool) -> Self {
        let mut nav = Self::all_blocked(*grid.geometry());
        let w = grid.width() as usize;
        if w == 0 {
            return nav;
        }
        for (row, values) in grid.as_slice().chunks_exact(w).enumerate() {
            let start = (row + 1) * nav.stride + 1;
            for (dst, v) in nav.cells[start..start + w].iter_mut().zip(values) {
                *dst = if is_passable(v) { PASSABLE } else { BLOCKED };
            }
        }
        nav
    }

    /// From a closure saying, for every cell of `geometry`, whether it is blocked.
    pub fn from_fn(geometry: GridGeometry, mut is_blocked: impl FnMut(Cell) -> bool) -> Self {
        let mut nav = Self::all_blocked(geometry);
        for row in 0..geometry.height as i32 {
            for col in 0..geometry.width as i32 {
                let cell = Cell::new(col, row);
                let i = nav.padded_index(cell);
                nav.cells[i] = if is_blocked(cell) { BLOCKED } else { PASSABLE };
            }
        }
        nav
    }

    /// Size, resolution and placement of the (unpadded) grid.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// True if `cell` is inside the grid and passable.
    #[inline]
    pub fn is_passable(&self, cell: Cell) -> bool {
        self.geometry.contains(cell) && self.cells[self.padded_index(cell)] == PASSABLE
    }

    /// Marks an in-grid cell passable or blocked; cells outside the grid are ignored. The bit
    /// copy, when built, is updated in place (two bits), so planners that open a start or goal
    /// cell for one query and close it again do not rebuild it.
    pub fn set_passable(&mut self, cell: Cell, passable: bool) {
        if self.geometry.contains(cell) {
            let i = self.padded_index(cell);
            let value = if passable { PASSABLE } else { BLOCKED };
            if self.cells[i] == value {
                return;
            }
            self.cells[i] = value;
            if let Some(bits) = self.bits.get_mut() {
                let (col, row) = (i % self.stride, i / self.stride);
                bits.rows.set(row, col, passable);
                bits.cols.set(col, row, passable);
            }
        }
    }

    /// Number of passable cells.
    pub fn passable_count(&self) -> usize {
        self.cells.iter().filter(|&&c| c == PASSABLE).count()
    }

    /// The blocked mask (`true` = blocked), unpadded.
    pub fn to_blocked(&self) -> Grid<bool> {
        let g = self.geometry;
        let mut out = Grid::filled(g, true);
        let w = g.width as usize;
        if w > 0 {
            for (row, dst) in out.as_mut_slice().chunks_exact_mut(w).enumerate() {
                let start = (row + 1) * self.stride + 1;
                for (d, &c) in dst.iter_mut().zip(&self.cells[start..start + w]) {
                    *d = c != PASSABLE;
                }
            }
        }
        out
    }

    /// The moves allowed from the cell at padded index `i` (which must not be on the border), as
    /// a bit mask in the order of [`usar_world::NEIGHBORS8`]: bits 0–3 east, north, west, south;
    /// bits 4–7 north-east, north-west, south-west, south-east. A move is allowed into a passable
    /// cell, a diagonal one only when both orthogonal cells beside it are passable too. Computed
    /// without branches, so that the planners' neighbour loops visit only allowed moves.
    #[inline(always)]
    pub(crate) fn allowed_moves(&self, i: usize, eight: bool) -> u32 {
        let c = &self.cells;
        let s = self.stride;
        let at = |j: usize| u32::from(c[j] == PASSABLE);
        let (e, n, w, so) = (at(i + 1), at(i + s), at(i - 1), at(i - s));
        let straight = e | (n << 1) | (w << 2) | (so << 3);
        if !eight {
            return straight;
        }
        let (ne, nw, sw, se) = (at(i + s + 1), at(i + s - 1), at(i - s - 1), at(i - s + 1));
        let diagonal =
            ((ne & e & n) << 4) | ((nw & w & n) << 5) | ((sw & w & so) << 6) | ((se & e & so) << 7);
        straight | diagonal
    }

    /// Padded index offset, column step, row step and cost of each move bit of
    /// [`NavGrid::allowed_moves`].
    pub(crate) fn move_table(&self) -> [(isize, i32, i32, f64); 8] {
        let s = self.stride as isize;
        let d = std::f64::consts::SQRT_2;
        [
            (1, 1, 0, 1.0),
            (s, 0, 1, 1.0),
            (-1, -1, 0, 1.0),
            (-s, 0, -1, 1.0),
            (s + 1, 1, 1, d),
            (s - 1, -1, 1, d),
            (-s - 1, -1, -1, d),
            (-s + 1, 1, -1, d),
        ]
    }

    /// Padded row width, `width + 2`.
    #[inline]
    pub(crate) fn stride(&self) -> usize {
        self.stride
    }

    /// The padded cells packed in bits by rows and by columns, built on the first call after
    /// the grid was made or changed (O(cells)).
    pub(crate) fn bit_lines(&self) -> &PackedCells {
        self.bits.get_or_init(|| PackedCells {
            rows: BitLines::from_cells(&self.cells, self.stride, false),
            cols: BitLines::from_cells(&self.cells, self.stride, true),
        })
    }

    /// The padded passability buffer.
    #[inline]
    pub(crate) fn cells(&self) -> &[u8] {
        &self.cells
    }

    /// Padded index of an in-grid cell.
    #[inline]
    pub(crate) fn padded_index(&self, cell: Cell) -> usize {
        debug_assert!(self.geometry.contains(cell));
        (cell.row as usize + 1) * self.stride + cell.col as usize + 1
    }

    /// The cell of a padded index (border indices give col or row -1 or width/height).
    #[inline]
    pub(crate) fn cell_of_padded(&self, index: usize) -> Cell {
        Cell::new(
            (index % self.stride) as i32 - 1,
            (index / self.stride) as i32 - 1,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::Point2;

    #[test]
    fn border_is_blocked_and_cells_round_trip() {
        let g = GridGeometry::new(3, 2, 0.1, Point2::new(0.0, 0.0));
        let nav = NavGrid::from_fn(g, |c| c == Cell::new(1, 0));
        assert_eq!(nav.cells().len(), 5 * 4);
        assert!(!nav.is_passable(Cell::new(1, 0)));
        assert!(nav.is_passable(Cell::new(2, 1)));
        assert!(!nav.is_passable(Cell::new(3, 1)));
        assert!(!nav.is_passable(Cell::new(-1, 0)));
        assert_eq!(nav.passable_count(), 5);
        for c in [Cell::new(0, 0), Cell::new(2, 1)] {
            assert_eq!(nav.cell_of_padded(nav.padded_index(c)), c);
        }
        let blocked = nav.to_blocked();
        assert_eq!(NavGrid::from_blocked(&blocked), nav);
    }

    #[test]
    fn changing_a_cell_keeps_the_bit_copy_equal_to_a_fresh_one() {
        let g = GridGeometry::new(70, 66, 0.1, Point2::new(0.0, 0.0));
        let mut nav = NavGrid::from_fn(g, |c| (c.col * 7 + c.row * 3) % 5 == 0);
        nav.bit_lines();
        for (k, c) in [
            Cell::new(0, 0),
            Cell::new(63, 64),
            Cell::new(64, 1),
            Cell::new(69, 65),
        ]
        .into_iter()
        .enumerate()
        {
            nav.set_passable(c, k % 2 == 0);
            nav.set_passable(Cell::new(c.col / 2, c.row), k % 2 == 1);
            let fresh = NavGrid::from_fn(g, |x| !nav.is_passable(x));
            assert_eq!(nav.bit_lines(), fresh.bit_lines());
        }
    }
}

/// Why a planner found no path between two cells of a [`NavGrid`] built for a robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NoPath {
    /// The start cell is not passable.
    #[error(
        "the start is blocked for this robot (an obstacle, a step or slope it cannot climb, or too close to a wall)"
    )]
    StartBlocked,
    /// The goal cell is not passable.
    #[error(
        "the goal is blocked for this robot (an obstacle, a step or slope it cannot climb, or too close to a wall)"
    )]
    GoalBlocked,
    /// Both are passable, in parts the grid does not connect.
    #[error("no passage wide and gentle enough for this robot connects start and goal")]
    NotConnected,
}

impl NoPath {
    /// Why no path joins `start` and `goal` on `grid`, given that a complete planner found none.
    pub fn explain(grid: &NavGrid, start: Cell, goal: Cell) -> Self {
        if !grid.is_passable(start) {
            NoPath::StartBlocked
        } else if !grid.is_passable(goal) {
            NoPath::GoalBlocked
        } else {
            NoPath::NotConnected
        }
    }
}

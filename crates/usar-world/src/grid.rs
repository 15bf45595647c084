//! Flat row-major grids and the one place where cells and world coordinates meet.
//!
//! Row 0 is the *southernmost* row (smallest y); images, whose row 0 is the top, are flipped at
//! the boundary (loaders, renderers) and nowhere else.

use crate::geometry::Point2;
use serde::{Deserialize, Serialize};

/// A cell address: column (x) and row (y), row 0 at the bottom.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cell {
    pub col: i32,
    pub row: i32,
}

impl Cell {
    pub const fn new(col: i32, row: i32) -> Self {
        Self { col, row }
    }

    /// Chebyshev (king-move) distance in cells.
    pub fn chebyshev(self, other: Cell) -> i32 {
        (self.col - other.col)
            .abs()
            .max((self.row - other.row).abs())
    }
}

/// The 8 neighbour offsets, 4-connected ones first: E, N, W, S, NE, NW, SW, SE.
pub const NEIGHBORS8: [(i32, i32); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

/// Size, resolution and placement of a grid in the world frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridGeometry {
    /// Number of columns.
    pub width: u32,
    /// Number of rows.
    pub height: u32,
    /// Side of one square cell, metres.
    pub resolution_m: f64,
    /// World position of the lower-left corner of cell (0, 0).
    pub origin: Point2,
}

impl GridGeometry {
    pub fn new(width: u32, height: u32, resolution_m: f64, origin: Point2) -> Self {
        Self {
            width,
            height,
            resolution_m,
            origin,
        }
    }

    pub fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn contains(&self, cell: Cell) -> bool {
        cell.col >= 0
            && cell.row >= 0
            && (cell.col as u32) < self.width
            && (cell.row as u32) < self.height
    }

    /// Row-major index of an in-bounds cell.
    #[inline]
    pub fn index(&self, cell: Cell) -> usize {
        debug_assert!(
            self.contains(cell),
            "{cell:?} outside {}x{}",
            self.width,
            self.height
        );
        cell.row as usize * self.width as usize + cell.col as usize
    }

    /// Row-major index, or `None` outside the grid.
    #[inline]
    pub fn checked_index(&self, cell: Cell) -> Option<usize> {
        self.contains(cell).then(|| self.index(cell))
    }

    #[inline]
    pub fn cell_of_index(&self, index: usize) -> Cell {
        let w = self.width as usize;
        Cell::new((index % w) as i32, (index / w) as i32)
    }

    /// The cell containing a world point (may lie outside the grid).
    #[inline]
    pub fn world_to_cell(&self, p: Point2) -> Cell {
        Cell::new(
            ((p.x - self.origin.x) / self.resolution_m).floor() as i32,
            ((p.y - self.origin.y) / self.resolution_m).floor() as i32,
        )
    }

    /// The centre of a cell in world coordinates.
    #[inline]
    pub fn cell_center(&self, cell: Cell) -> Point2 {
        Point2::new(
            self.origin.x + (cell.col as f64 + 0.5) * self.resolution_m,
            self.origin.y + (cell.row as f64 + 0.5) * self.resolution_m,
        )
    }

    /// World width and height, metres.
    pub fn extent_m(&self) -> (f64, f64) {
        (
            self.width as f64 * self.resolution_m,
            self.height as f64 * self.resolution_m,
        )
    }

    /// Area of one cell, m².
    pub fn cell_area_m2(&self) -> f64 {
        self.resolution_m * self.resolution_m
    }
}

/// A flat, row-major grid of small values.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid<T> {
    geometry: GridGeometry,
    data: Vec<T>,
}

impl<T: Clone> Grid<T> {
    pub fn filled(geometry: GridGeometry, value: T) -> Self {
        Self {
            geometry,
            data: vec![value; geometry.len()],
        }
    }
}

impl<T> Grid<T> {
    /// Wraps row-major `data`; `None` if its length does not match the geometry.
    pub fn from_vec(geometry: GridGeometry, data: Vec<T>) -> Option<Self> {
        (data.len() == geometry.len()).then_some(Self { geometry, data })
    }

    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    pub fn width(&self) -> u32 {
        self.geometry.width
    }

    pub fn height(&self) -> u32 {
        self.geometry.height
    }

    pub fn as_slice(&self) -> &[T] {
        &self.data
    }

    pub fn as_mut_slice(&mut self) -> &mut [T] {
        &mut self.data
    }

    pub fn into_vec(self) -> Vec<T> {
        self.data
    }

    #[inline]
    pub fn get(&self, cell: Cell) -> Option<&T> {
        self.geometry.checked_index(cell).map(|i| &self.data[i])
    }

    #[inline]
    pub fn get_mut(&mut self, cell: Cell) -> Option<&mut T> {
        self.geometry
            .checked_index(cell)
            .map(move |i| &mut self.data[i])
    }

    /// Builds a grid of the same geometry by mapping every value.
    pub fn map<U>(&self, f: impl FnMut(&T) -> U) -> Grid<U> {
        Grid {
            geometry: self.geometry,
            data: self.data.iter().map(f).collect(),
        }
    }

    /// Iterates cells with their values, row-major.
    pub fn iter_cells(&self) -> impl Iterator<Item = (Cell, &T)> + '_ {
        let w = self.geometry.width as usize;
        self.data
            .iter()
            .enumerate()
            .map(move |(i, v)| (Cell::new((i % w) as i32, (i / w) as i32), v))
    }
}

impl<T> std::ops::Index<Cell> for Grid<T> {
    type Output = T;
    #[inline]
    fn index(&self, cell: Cell) -> &T {
        &self.data[self.geometry.index(cell)]
    }
}

impl<T> std::ops::IndexMut<Cell> for Grid<T> {
    #[inline]
    fn index_mut(&mut self, cell: Cell) -> &mut T {
        let i = self.geometry.index(cell);
        &mut self.data[i]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_and_cell_round_trip_through_centres() {
        let g = GridGeometry::new(10, 5, 0.1, Point2::new(-1.0, 2.0));
        let c = Cell::new(3, 4);
        assert_eq!(g.world_to_cell(g.cell_center(c)), c);
        assert_eq!(g.world_to_cell(Point2::new(-1.0, 2.0)), Cell::new(0, 0));
        assert_eq!(g.world_to_cell(Point2::new(-1.01, 2.0)), Cell::new(-1, 0));
        assert_eq!(g.index(Cell::new(3, 4)), 43);
        assert_eq!(g.cell_of_index(43), c);
    }
}

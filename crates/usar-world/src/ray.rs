//! Grid traversal along a ray (Amanatides & Woo, 1987): visits, in order, every cell a ray
//! crosses, with the distance at which it enters each one. The laser simulator and the occupancy
//! grid update both walk rays with it; it allocates nothing.
//!
//! [`GridRay::walk_to`] is the fast way through a grid.

use crate::geometry::Point2;
use crate::grid::GridGeometry;
use std::hint::select_unpredictable;

/// A ray being walked cell by cell. Distances are in *cells* (multiply by the resolution for
/// metres).
#[derive(Clone, Copy, Debug)]
pub struct GridRay {
    /// Current cell.
    pub col: i32,
    pub row: i32,
    /// Distance along the ray (cells) at which the current cell was entered (0 for the first).
    pub t_entry: f64,
    step_col: i32,
    step_row: i32,
    t_max_x: f64,
    t_max_y: f64,
    t_delta_x: f64,
    t_delta_y: f64,
}

impl GridRay {
    /// Starts a ray at world point `origin` with direction (`cos`, `sin`) of its angle.
    #[inline]
    pub fn new(geometry: &GridGeometry, origin: Point2, cos: f64, sin: f64) -> Self {
        let inv_res = 1.0 / geometry.resolution_m;
        let px = (origin.x - geometry.origin.x) * inv_res;
        let py = (origin.y - geometry.origin.y) * inv_res;
        let col = px.floor();
        let row = py.floor();
        let (step_col, t_delta_x, t_max_x) = axis(px, col, cos);
        let (step_row, t_delta_y, t_max_y) = axis(py, row, sin);
        Self {
            col: col as i32,
            row: row as i32,
            t_entry: 0.0,
            step_col,
            step_row,
            t_max_x,
            t_max_y,
            t_delta_x,
            t_delta_y,
        }
    }

    /// Moves to the next cell along the ray.
    #[inline(always)]
    pub fn advance(&mut self) {
        if self.t_max_x < self.t_max_y {
            self.col += self.step_col;
            self.t_entry = self.t_max_x;
            self.t_max_x += self.t_delta_x;
        } else {
            self.row += self.step_row;
            self.t_entry = self.t_max_y;
            self.t_max_y += self.t_delta_y;
        }
    }

    /// Distance (cells) at which the ray leaves the current cell: the `t_entry` of the next one.
    #[inline(always)]
    pub fn t_exit(&self) -> f64 {
        // The same choice as `advance` (unlike `f64::min`, also when a distance is NaN).
        if self.t_max_x < self.t_max_y {
            self.t_max_x
        } else {
            self.t_max_y
        }
    }

    /// Walks the ray from its current cell through a grid of `width` × `height` up to distance
    /// `t_end` (cells): calls `visit` with the row-major index of each cell the ray leaves before
    /// `t_end` (precisely: each cell whose `!(t_exit() >= t_end)`), in order, until `visit`
    /// returns `true`. Returns the index and `t_entry` of the cell where the walk ended — the
    /// cell on which `visit` returned `true`, or else the first cell with `t_exit() >= t_end`,
    /// which is *not* visited — or `None` if the ray left the grid first (or starts outside it).
    ///
    /// It visits what the loop `while let Some(i) = ray.index_in(width, height)` with
    /// `if ray.t_exit() >= t_end { return Some((i, ray.t_entry)) }`,
    /// `if visit(i) { return Some((i, ray.t_entry)) }` and `ray.advance()` visits, with the same
    /// arithmetic, but faster: while the ray is more than one cell from the grid's border it
    /// neither tests bounds nor tracks the column and row, only the index (adding a precomputed
    /// offset), and it chooses each step without a branch (the x/y choice of a ray that is not
    /// axis-aligned is unpredictable, and a mispredicted branch per cell costs more than the rest
    /// of the step).
    #[inline(always)]
    pub fn walk_to(
        mut self,
        width: u32,
        height: u32,
        t_end: f64,
        mut visit: impl FnMut(usize) -> bool,
    ) -> Option<(usize, f64)> {
        let mut index = self.index_in(width, height)?;
        let (mut tx, mut ty) = (self.t_max_x, self.t_max_y);
        if !tx.is_nan() && !ty.is_nan() {
            let t_fast = self.t_end_inside(width, height).min(t_end);
            let col_offset = self.step_col as isize;
            let row_offset = self.step_row as isize * width as isize;
            let (dx, dy) = (self.t_delta_x, self.t_delta_y);
            let mut t_entry = self.t_entry;
            let start = index;
            loop {
                // Where the next cell starts: the same choice as `advance` (minsd).
                let t_next = if tx < ty { tx } else { ty };
                // Invariant: `index` is the current cell, inside the grid. While the next cell
                // starts before `t_fast`, it is inside too and the walk has not reached `t_end`.
                if !(t_next < t_fast) {
                    break;
                }
                if visit(index) {
                    return Some((index, t_entry));
                }
                // `advance` without a branch: `x_mask` is all ones to step along x (`tx < ty`),
                // zero along y. It is the sign of `tx - ty`, which is exact: the difference of
                // two unequal floats is never zero, of equal ones +0.0, and here at most one of
                // them is infinite since `t_next < t_fast`. (Written as a comparison, the
                // compiler turns the masked additions below back into jumps.) Each distance adds
                // its delta or +0.0, which leaves it unchanged (distances are never -0.0, see
                // `axis`, nor NaN, tested above).
                let x_mask = ((tx - ty).to_bits() as i64 >> 63) as u64;
                let step_x = x_mask != 0;
                t_entry = t_next;
                tx += f64::from_bits(dx.to_bits() & x_mask);
                ty += f64::from_bits(dy.to_bits() & !x_mask);
                index = index.wrapping_add_signed(select_unpredictable(
                    step_x, col_offset, row_offset,
                ));
            }
            // Near the border or at `t_end`: hand over to the checked walk below.
            if index != start {
                self.col = (index % width as usize) as i32;
                self.row = (index / width as usize) as i32;
                (self.t_entry, self.t_max_x, self.t_max_y) = (t_entry, tx, ty);
            }
        }
        loop {
            if self.t_exit() >= t_end || visit(index) {
                return Some((index, self.t_entry));
            }
            self.advance();
            index = self.index_in(width, height)?;
        }
    }

    /// A distance (cells) such that every cell the ray enters before it lies inside a grid of
    /// `width` × `height`, the current cell being inside: one cell short of where the ray
    /// crosses the grid's border. The crossing of the k-th column boundary ahead is at
    /// `t_max_x + (k − 1)·t_delta_x`; the walk reaches it by k − 1 additions whose rounding
    /// (about 1e-16 relative each) stays far below the one-cell margin.
    #[inline]
    fn t_end_inside(&self, width: u32, height: u32) -> f64 {
        let along = |t_max: f64, t_delta: f64, step: i32, cell: i32, cells: u32| -> f64 {
            let boundaries_inside = match step {
                1 => cells as i32 - 1 - cell,
                -1 => cell,
                _ => return f64::INFINITY,
            };
            if boundaries_inside == 0 {
                t_max
            } else {
                t_max + f64::from(boundaries_inside) * t_delta
            }
        };
        let x = along(self.t_max_x, self.t_delta_x, self.step_col, self.col, width);
        let y = along(self.t_max_y, self.t_delta_y, self.step_row, self.row, height);
        x.min(y) - 1.0
    }

    /// Row-major index of the current cell if it lies inside a grid of `width` × `height`.
    #[inline(always)]
    pub fn index_in(&self, width: u32, height: u32) -> Option<usize> {
        ((self.col as u32) < width && (self.row as u32) < height)
            .then(|| self.row as usize * width as usize + self.col as usize)
    }
}

#[inline]
fn axis(p: f64, cell: f64, dir: f64) -> (i32, f64, f64) {
    if dir > 0.0 {
        (1, 1.0 / dir, (cell + 1.0 - p) / dir)
    } else if dir < 0.0 {
        (-1, -1.0 / dir, (p - cell) / -dir)
    } else {
        (0, f64::INFINITY, f64::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn axis_aligned_ray_visits_consecutive_cells() {
        let g = GridGeometry::new(10, 10, 0.1, Point2::new(0.0, 0.0));
        let mut ray = GridRay::new(&g, Point2::new(0.05, 0.05), 1.0, 0.0);
        let mut cols = vec![ray.col];
        for _ in 0..3 {
            ray.advance();
            cols.push(ray.col);
            assert_eq!(ray.row, 0);
        }
        assert_eq!(cols, vec![0, 1, 2, 3]);
        assert!((ray.t_entry - 2.5).abs() < 1e-12);
    }

    proptest! {
        /// Every point of the segment lies in one of the visited cells, and visited cells are
        /// 4-adjacent: the traversal skips nothing.
        #[test]
        fn traversal_covers_the_segment(x in 0.0f64..5.0, y in 0.0f64..5.0, a in -3.2f64..3.2, len in 0.0f64..3.0) {
            let g = GridGeometry::new(200, 200, 0.05, Point2::new(-2.0, -2.0));
            let (s, c) = a.sin_cos();
            let mut ray = GridRay::new(&g, Point2::new(x, y), c, s);
            let mut visited = vec![(ray.col, ray.row)];
            while ray.t_exit() * g.resolution_m < len {
                let prev = (ray.col, ray.row);
                ray.advance();
                prop_assert_eq!((ray.col - prev.0).abs() + (ray.row - prev.1).abs(), 1);
                visited.push((ray.col, ray.row));
            }
            for k in 0..=200 {
                let d = len * k as f64 / 200.0;
                let cell = g.world_to_cell(Point2::new(x + d * c, y + d * s));
                // A sample exactly on a cell corner may fall in a diagonal neighbour; allow it.
                let near = visited.iter().any(|&(vc, vr)| (vc - cell.col).abs() <= 1 && (vr - cell.row).abs() <= 1);
                prop_assert!(near);
                let exact = visited.contains(&(cell.col, cell.row));
                let on_corner = {
                    let fx = (x + d * c - g.origin.x) / g.resolution_m;
                    let fy = (y + d * s - g.origin.y) / g.resolution_m;
                    (fx - fx.round()).abs() < 1e-9 || (fy - fy.round()).abs() < 1e-9
                };
                prop_assert!(exact || on_corner);
            }
        }
    }
}

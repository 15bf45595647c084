//! Grid traversal along a ray (Amanatides & Woo, 1987): visits, in order, every cell a ray
//! crosses, with the distance at which it enters each one. The laser simulator and the occupancy
//! grid update both walk rays with it; it allocates nothing.

use crate::geometry::Point2;
use crate::grid::GridGeometry;

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

    /// Distance (cells) at which the ray leaves the current cell.
    #[inline]
    pub fn t_exit(&self) -> f64 {
        self.t_max_x.min(self.t_max_y)
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

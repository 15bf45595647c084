//! Grid traversal along a ray (Amanatides & Woo, 1987): visits, in order, every cell a ray
//! crosses, with the distance at which it enters each one. The laser simulator and the occupancy
//! grid update both walk rays with it; it allocates nothing.
//!
//! [`GridRay::walk_to`] is the fast way through a grid: it plans the walk in fixed-point
//! crossing times (integers, so the number of cells before a distance is a division, not a
//! walk), then takes each step with one integer error term (Bresenham's form of the same
//! traversal): no bounds test and no data-dependent branch per cell.

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
    /// |cos| and |sin| of the direction: 1 / t_delta.
    abs_dir_x: f64,
    abs_dir_y: f64,
}

impl GridRay {
    /// Starts a ray at world point `origin` with direction (`cos`, `sin`) of its angle.
    #[inline]
    pub fn new(geometry: &GridGeometry, origin: Point2, cos: f64, sin: f64) -> Self {
        let inv_res = 1.0 / geometry.resolution_m;
        let px = (origin.x - geometry.origin.x) * inv_res;
        let py = (origin.y - geometry.origin.y) * inv_res;
        let col = floor(px);
        let row = floor(py);
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
            abs_dir_x: cos.abs(),
            abs_dir_y: sin.abs(),
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
    /// `t_end`, in order, until `visit` returns `true`. Returns the index and `t_entry` of the
    /// cell where the walk ended — the cell on which `visit` returned `true`, or else the cell in
    /// which the ray reaches `t_end` (its `t_exit() >= t_end`), which is *not* visited — or `None`
    /// if the ray left the grid first (or starts outside it). A NaN `t_end` is never reached.
    ///
    /// This is the loop `while let Some(i) = ray.index_in(width, height)` with
    /// `if ray.t_exit() >= t_end || visit(i) { return Some((i, ray.t_entry)) }` and
    /// `ray.advance()`, with its crossing times in fixed point (2⁻³² cell), which makes it
    /// several times faster: the number of cells to visit is known before the first step, so a
    /// step is a few integer instructions. The k-th crossing time is off by at most about
    /// k·2⁻³³ cell (1e-8 after 100 cells), so the cells visited are those of the `advance` loop
    /// except where the ray passes that close to a cell corner, where the other neighbour of the
    /// corner may be visited instead (the ray touches both); `t_entry` is computed in floating
    /// point from the number of crossings. Rays for which the fixed-point form does not hold (a
    /// NaN origin, a direction far from unit length, a grid side above 2²⁴ cells) take the
    /// `advance` loop.
    #[inline(always)]
    pub fn walk_to(
        self,
        width: u32,
        height: u32,
        t_end: f64,
        mut visit: impl FnMut(usize) -> bool,
    ) -> Option<(usize, f64)> {
        let mut index = self.index_in(width, height)?;
        let Some(plan) = FixedCrossings::new(&self, width, height, t_end) else {
            return self.walk_to_by_advance(width, height, t_end, visit);
        };
        let col_offset = self.step_col as isize;
        let row_offset = self.step_row as isize * width as isize;
        let (dx, dy) = (plan.x.step as i64, plan.y.step as i64);
        // x crossing pending minus y crossing pending: the next step is along x when negative
        // (ties go to y, as in `advance`). |d| < 2^62: see `FixedCrossings::NEVER`.
        let mut d = plan.x.first as i64 - plan.y.first as i64;
        let start = index;
        for step in 0..plan.visits {
            if visit(index) {
                // The steps along x, from the index moved: x·col_offset + (step − x)·row_offset
                // (exact in f64: integers far below 2^53; x = 0 when no step can go along x).
                let moved = index.wrapping_sub(start) as isize;
                let per_x_step = col_offset - row_offset;
                let x_steps = if per_x_step == 0 || col_offset == 0 {
                    0
                } else {
                    ((moved - step as isize * row_offset) as f64 / per_x_step as f64) as usize
                };
                return Some((index, self.t_entry_after(x_steps, step - x_steps)));
            }
            let along_x = d < 0;
            d += select_unpredictable(along_x, dx, -dy);
            index =
                index.wrapping_add_signed(select_unpredictable(along_x, col_offset, row_offset));
        }
        // Reaching the end, the walk crossed every boundary before it.
        plan.reaches_end.then(|| {
            let (x_steps, y_steps) = plan.crossings_before_end;
            (
                index,
                self.t_entry_after(x_steps as usize, y_steps as usize),
            )
        })
    }

    /// [`GridRay::walk_to`] that can jump over blocks of cells known to be of no interest: the
    /// walk ends on the same cell with the same `t_entry` as `walk_to` with the visitor
    /// `|i| visitor.visit(i) == Visit::Stop`, provided that every cell of a rectangle
    /// `visitor.skip` returns would get [`Visit::Next`] or [`Visit::MaySkip`] from
    /// `visitor.visit` and that visiting such a cell has no effect; those cells may not be
    /// visited at all.
    ///
    /// When `visit` answers [`Visit::MaySkip`], `skip(index, col, row)` may give a rectangle of
    /// cells around the current cell (col, row); the walk then moves, in one step, to the last
    /// cell inside the rectangle along the ray: it makes every crossing before the first one that
    /// leaves the rectangle, counted with [`AxisCrossings::before`] (all crossings before a time
    /// are a prefix of the walk's order, whatever the tie rule), and goes on from the cell after
    /// it. A jump costs a few dozen instructions: worth it over rectangles a few cells wide
    /// (empty-space skipping over a distance map, or over blocks of saturated cells).
    #[inline(always)]
    pub fn walk_skipping(
        self,
        width: u32,
        height: u32,
        t_end: f64,
        visitor: &mut impl RayVisitor,
    ) -> Option<(usize, f64)> {
        let mut index = self.index_in(width, height)?;
        let Some(plan) = FixedCrossings::new(&self, width, height, t_end) else {
            return self
                .walk_to_by_advance(width, height, t_end, |i| visitor.visit(i) == Visit::Stop);
        };
        let col_offset = self.step_col as isize;
        let row_offset = self.step_row as isize * width as isize;
        let (dx, dy) = (plan.x.step as i64, plan.y.step as i64);
        let mut d = plan.x.first as i64 - plan.y.first as i64;
        let start = index;
        let mut step = 0usize;
        let mut x_steps = 0usize;
        while step < plan.visits {
            match visitor.visit(index) {
                Visit::Next => {}
                Visit::Stop => {
                    return Some((index, self.t_entry_after(x_steps, step - x_steps)));
                }
                Visit::MaySkip => {
                    let y_steps = step - x_steps;
                    let col = self.col + self.step_col * x_steps as i32;
                    let row = self.row + self.step_row * y_steps as i32;
                    if let Some(rect) = visitor.skip(index, col, row)
                        && let Some((nx, ny)) = plan.crossings_inside(
                            &self, width, height, rect, col, row, x_steps, y_steps,
                        )
                        && nx >= x_steps
                        && ny >= y_steps
                        && nx + ny > step
                    {
                        if nx + ny >= plan.visits {
                            // The rest of the walk lies inside the rectangle.
                            break;
                        }
                        step = nx + ny;
                        x_steps = nx;
                        index = start.wrapping_add_signed(
                            nx as isize * col_offset + ny as isize * row_offset,
                        );
                        d = plan.x.time(nx as u64) as i64 - plan.y.time(ny as u64) as i64;
                        // The cell reached lies in the rectangle: no need to visit it.
                    }
                }
            }
            let along_x = d < 0;
            d += select_unpredictable(along_x, dx, -dy);
            index =
                index.wrapping_add_signed(select_unpredictable(along_x, col_offset, row_offset));
            x_steps += usize::from(along_x);
            step += 1;
        }
        plan.reaches_end.then(|| {
            let (x_steps, y_steps) = plan.crossings_before_end;
            (
                start.wrapping_add_signed(
                    x_steps as isize * col_offset + y_steps as isize * row_offset,
                ),
                self.t_entry_after(x_steps as usize, y_steps as usize),
            )
        })
    }

    /// `t_entry` after `x_steps` steps along x and `y_steps` along y from the current cell: the
    /// time of the later of the last x and the last y crossing.
    fn t_entry_after(&self, x_steps: usize, y_steps: usize) -> f64 {
        let last = |t_max: f64, t_delta: f64, steps: usize| {
            if steps == 0 {
                self.t_entry
            } else {
                t_max + (steps - 1) as f64 * t_delta
            }
        };
        let tx = last(self.t_max_x, self.t_delta_x, x_steps);
        let ty = last(self.t_max_y, self.t_delta_y, y_steps);
        if tx < ty { ty } else { tx }
    }

    /// [`GridRay::walk_to`] by `advance`, in floating point.
    fn walk_to_by_advance(
        mut self,
        width: u32,
        height: u32,
        t_end: f64,
        mut visit: impl FnMut(usize) -> bool,
    ) -> Option<(usize, f64)> {
        loop {
            let index = self.index_in(width, height)?;
            if self.t_exit() >= t_end || visit(index) {
                return Some((index, self.t_entry));
            }
            self.advance();
        }
    }

    /// Row-major index of the current cell if it lies inside a grid of `width` × `height`.
    #[inline(always)]
    pub fn index_in(&self, width: u32, height: u32) -> Option<usize> {
        ((self.col as u32) < width && (self.row as u32) < height)
            .then(|| self.row as usize * width as usize + self.col as usize)
    }
}

/// What the visitor of [`GridRay::walk_skipping`] says of a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visit {
    /// Go on to the next cell.
    Next,
    /// End the walk on this cell.
    Stop,
    /// Go on; the cell may lie in a rectangle of cells the walk can jump over (ask `skip`).
    MaySkip,
}

/// The cells of a [`GridRay::walk_skipping`]: what to do on each, and which ones to jump over.
pub trait RayVisitor {
    /// Called on each cell the walk does not jump over, by row-major index.
    fn visit(&mut self, index: usize) -> Visit;
    /// After [`Visit::MaySkip`] on the cell at (`col`, `row`): a rectangle around it whose
    /// cells the walk may jump over, if any.
    fn skip(&mut self, index: usize, col: i32, row: i32) -> Option<CellRect>;
}

/// A rectangle of cells, bounds included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellRect {
    pub col_min: i32,
    pub col_max: i32,
    pub row_min: i32,
    pub row_max: i32,
}

/// The crossing times of one axis's cell boundaries ahead of the ray, in fixed point (units of
/// 2⁻³² cell): the k-th (k ≥ 0) is at `first + k·step`. Being integers, the times add up exactly,
/// so the number of crossings before a time is a division rather than a walk.
#[derive(Clone, Copy, Debug)]
struct AxisCrossings {
    first: u64,
    step: u64,
    /// About 1 / `step`.
    rate: f64,
    /// Crossings that stay inside the grid (the next one leaves it).
    inside: u64,
}

impl AxisCrossings {
    /// Crossings strictly before `time`.
    #[inline]
    fn before(&self, time: u64) -> u64 {
        if time <= self.first {
            return 0;
        }
        // The largest k with k·step ≤ span, from a floating-point estimate (`rate` is within
        // 2⁻³⁰ of 1/step, so it is off by one at most below 2²⁹ crossings) corrected exactly;
        // an integer division costs more than the rest of a ray's set-up.
        let span = time - self.first - 1;
        let mut k = (span as i64 as f64 * self.rate) as i64 as u64;
        while k > 0 && k * self.step > span {
            k -= 1;
        }
        while (k + 1) * self.step <= span {
            k += 1;
        }
        k + 1
    }

    /// Time of crossing `k` (0-based), or [`FixedCrossings::NEVER`] when that is later.
    #[inline]
    fn time(&self, k: u64) -> u64 {
        self.first
            .saturating_add(k.saturating_mul(self.step))
            .min(FixedCrossings::NEVER)
    }

    /// Index of the crossing that takes the ray, now `done` crossings in at `cell` and moving by
    /// `step` (±1 or 0) per crossing, out of `min..=max` (`u64::MAX`: never).
    #[inline]
    fn leaving_index(done: usize, cell: i32, step: i32, min: i32, max: i32) -> u64 {
        match step {
            1 => (done + (max - cell) as usize) as u64,
            -1 => (done + (cell - min) as usize) as u64,
            _ => u64::MAX,
        }
    }

    /// Time of the crossing that leaves the grid, if it is among the first `crossings`.
    #[inline]
    fn leaving_among(&self, crossings: u64) -> Option<u64> {
        // Then it comes before a time below 2^61: no overflow.
        (crossings > self.inside).then(|| self.first + self.inside * self.step)
    }
}

/// How a [`GridRay::walk_to`] goes, planned before its first step.
#[derive(Clone, Copy, Debug)]
struct FixedCrossings {
    x: AxisCrossings,
    y: AxisCrossings,
    /// Cells visited: those the ray leaves before `t_end` (as many as the crossings before it),
    /// or, when it leaves the grid first, every cell up to the last one inside (one more than
    /// the crossings before the leaving one).
    visits: usize,
    /// Whether the walk reaches `t_end` (else it leaves the grid).
    reaches_end: bool,
    /// Crossings along x and along y before `t_end`.
    crossings_before_end: (u64, u64),
}

impl FixedCrossings {
    /// 2³² fixed-point units per cell.
    const ONE: f64 = 4_294_967_296.0;
    /// Times from here on never come: 2⁶¹ units = 2²⁹ cells, farther than any crossing of a
    /// grid of at most 2²⁴ cells a side by a ray whose longer direction component is at least
    /// 1/2. Every time the walk uses is below it and every step at most it, so the difference
    /// of two pending crossing times stays below 2⁶² in magnitude.
    const NEVER: u64 = 1 << 61;
    /// Largest grid side handled in fixed point.
    const MAX_SIDE: u32 = 1 << 24;

    fn fixed(t: f64) -> u64 {
        let units = t * Self::ONE;
        if units < Self::NEVER as f64 {
            // In [0, 2^61) (a negative time is 0): the signed conversion is one instruction.
            (units + 0.5).max(0.0) as i64 as u64
        } else {
            Self::NEVER
        }
    }

    /// The plan for `ray`, or `None` where the fixed-point form does not hold (see `walk_to`).
    #[inline(always)]
    fn new(ray: &GridRay, width: u32, height: u32, t_end: f64) -> Option<Self> {
        let (tdx, tdy) = (ray.t_delta_x, ray.t_delta_y);
        // A unit direction has t_delta ≥ 1 on both axes and ≤ √2 on one of them.
        let unit_like = tdx >= 0.5 && tdy >= 0.5 && tdx.min(tdy) <= 2.0;
        if !unit_like || ray.t_max_x.is_nan() || ray.t_max_y.is_nan() {
            return None;
        }
        if width > Self::MAX_SIDE || height > Self::MAX_SIDE {
            return None;
        }
        let axis = |t_max: f64, t_delta: f64, abs_dir: f64, step: i32, cell: i32, cells: u32| {
            AxisCrossings {
                first: Self::fixed(t_max),
                step: Self::fixed(t_delta).max(1),
                rate: abs_dir / Self::ONE,
                inside: match step {
                    1 => u64::from(cells) - 1 - cell as u64,
                    -1 => cell as u64,
                    _ => u64::MAX,
                },
            }
        };
        let x = axis(
            ray.t_max_x,
            tdx,
            ray.abs_dir_x,
            ray.step_col,
            ray.col,
            width,
        );
        let y = axis(
            ray.t_max_y,
            tdy,
            ray.abs_dir_y,
            ray.step_row,
            ray.row,
            height,
        );
        // `fixed` maps NaN to NEVER: a NaN end is never reached.
        let end = Self::fixed(t_end);
        let (x_before_end, y_before_end) = (x.before(end), y.before(end));
        let leaving = (x.leaving_among(x_before_end), y.leaving_among(y_before_end));
        let (visits, reaches_end) = match leaving {
            (None, None) => (x_before_end + y_before_end, true),
            // Leaving along y first (a tie goes to y, as in `advance`): the x crossings before.
            (Some(tx), Some(ty)) if ty <= tx => (y.inside + x.before(ty) + 1, false),
            (None, Some(ty)) => (y.inside + x.before(ty) + 1, false),
            // Leaving along x first: every y crossing up to then comes before it.
            (Some(tx), _) => (x.inside + y.before(tx + 1) + 1, false),
        };
        Some(Self {
            x,
            y,
            visits: visits as usize,
            reaches_end,
            crossings_before_end: (x_before_end, y_before_end),
        })
    }
}

impl FixedCrossings {
    /// Crossings along x and along y made (from the ray's start) before the first one that
    /// takes a ray at (`col`, `row`), `x_steps` crossings along x and `y_steps` along y in, out
    /// of `rect` (clipped to the grid); `None` when the cell is not inside it. The axis that
    /// leaves first made exactly the crossings up to the leaving one; only the other one is
    /// counted.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn crossings_inside(
        &self,
        ray: &GridRay,
        width: u32,
        height: u32,
        rect: CellRect,
        col: i32,
        row: i32,
        x_steps: usize,
        y_steps: usize,
    ) -> Option<(usize, usize)> {
        let (col_min, col_max) = (rect.col_min.max(0), rect.col_max.min(width as i32 - 1));
        let (row_min, row_max) = (rect.row_min.max(0), rect.row_max.min(height as i32 - 1));
        if !(col_min <= col && col <= col_max && row_min <= row && row <= row_max) {
            return None;
        }
        let kx = AxisCrossings::leaving_index(x_steps, col, ray.step_col, col_min, col_max);
        let ky = AxisCrossings::leaving_index(y_steps, row, ray.step_row, row_min, row_max);
        let (tx, ty) = (self.x.time(kx), self.y.time(ky));
        Some(if tx < ty {
            (kx as usize, self.y.before(tx) as usize)
        } else if ty < tx {
            (self.x.before(ty) as usize, ky as usize)
        } else if tx < FixedCrossings::NEVER {
            (kx as usize, ky as usize)
        } else {
            (self.x.before(tx) as usize, self.y.before(ty) as usize)
        })
    }
}

/// `x.floor()` without a library call (SSE2 has no rounding instruction).
#[inline]
fn floor(x: f64) -> f64 {
    // Beyond 2^52 every float is an integer; NaN fails the test and is returned.
    if x.abs() < 4_503_599_627_370_496.0 {
        let truncated = x as i64 as f64;
        if truncated > x {
            truncated - 1.0
        } else if truncated == x {
            x // keeps the sign of -0.0
        } else {
            truncated
        }
    } else {
        x
    }
}

#[inline]
fn axis(p: f64, cell: f64, dir: f64) -> (i32, f64, f64) {
    // One division: the first crossing is the fraction of the cell left times t_delta.
    if dir > 0.0 {
        let t_delta = 1.0 / dir;
        (1, t_delta, (cell + 1.0 - p) * t_delta)
    } else if dir < 0.0 {
        let t_delta = -1.0 / dir;
        (-1, t_delta, (p - cell) * t_delta)
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

        /// `walk_to` visits the cells of the `advance` loop, up to a swap at a cell corner
        /// that the ray passes within the fixed-point resolution, and ends the same way.
        #[test]
        fn walk_to_visits_the_cells_of_the_advance_loop(
            x in -0.5f64..6.5, y in -0.5f64..6.5, a in -3.2f64..3.2,
            t_end in -1.0f64..150.0, width in 1u32..60, height in 1u32..60,
            stop_after in proptest::option::of(0usize..80),
        ) {
            let g = GridGeometry::new(width, height, 0.1, Point2::new(0.0, 0.0));
            let (s, c) = a.sin_cos();
            let ray = GridRay::new(&g, Point2::new(x, y), c, s);
            let walk = |fast: bool| {
                let mut cells = Vec::new();
                let visit = |i| {
                    cells.push(i);
                    stop_after == Some(cells.len() - 1)
                };
                let end = if fast {
                    ray.walk_to(width, height, t_end, visit)
                } else {
                    ray.walk_to_by_advance(width, height, t_end, visit)
                };
                (cells, end)
            };
            let (fast, fast_end) = walk(true);
            let (slow, slow_end) = walk(false);
            prop_assert_eq!(fast.len(), slow.len());
            for k in 0..fast.len() {
                let swapped_at_corner = k > 0
                    && k + 1 < fast.len()
                    && fast[k - 1] == slow[k - 1]
                    && fast[k + 1] == slow[k + 1];
                prop_assert!(fast[k] == slow[k] || swapped_at_corner, "{fast:?} vs {slow:?}");
            }
            match (fast_end, slow_end) {
                (None, None) => {}
                (Some((i, t)), Some((j, u))) => {
                    prop_assert_eq!(i, j);
                    prop_assert!((t - u).abs() < 1e-6, "t_entry {t} vs {u}");
                }
                ends => prop_assert!(false, "ends differ: {ends:?}"),
            }
        }
    }

    proptest! {
        /// `walk_skipping`, jumping over squares free of stopping cells, ends where `walk_to`
        /// ends, with the same `t_entry`.
        #[test]
        fn walk_skipping_ends_where_walk_to_ends(
            x in -0.5f64..4.5, y in -0.5f64..4.5, a in -3.2f64..3.2,
            t_end in -1.0f64..100.0, width in 1u32..45, height in 1u32..45,
            stops in proptest::collection::vec((0u32..45, 0u32..45), 0..40),
            min_radius in 0i32..4,
        ) {
            let g = GridGeometry::new(width, height, 0.1, Point2::new(0.0, 0.0));
            let (s, c) = a.sin_cos();
            let ray = GridRay::new(&g, Point2::new(x, y), c, s);
            let stop: Vec<bool> = {
                let mut v = vec![false; (width * height) as usize];
                for &(sc, sr) in &stops {
                    if sc < width && sr < height {
                        v[(sr * width + sc) as usize] = true;
                    }
                }
                v
            };
            let is_stop = |col: i32, row: i32| {
                col >= 0 && row >= 0 && (col as u32) < width && (row as u32) < height
                    && stop[(row as u32 * width + col as u32) as usize]
            };
            // The largest square around a cell free of stopping cells (radius up to 20).
            let clear_radius = |col: i32, row: i32| {
                (0..20).take_while(|&r| {
                    (-r..=r).all(|dr| (-r..=r).all(|dc| !is_stop(col + dc, row + dr)))
                }).last()
            };
            let expected = ray.walk_to(width, height, t_end, |i| stop[i]);
            struct Probe<'a, F> {
                stop: &'a [bool],
                width: u32,
                min_radius: i32,
                clear_radius: F,
            }
            impl<F: Fn(i32, i32) -> Option<i32>> RayVisitor for Probe<'_, F> {
                fn visit(&mut self, i: usize) -> Visit {
                    if self.stop[i] { Visit::Stop } else { Visit::MaySkip }
                }
                fn skip(&mut self, i: usize, col: i32, row: i32) -> Option<CellRect> {
                    assert_eq!(i, (row as u32 * self.width + col as u32) as usize);
                    (self.clear_radius)(col, row)
                        .filter(|&r| r >= self.min_radius)
                        .map(|r| CellRect {
                            col_min: col - r,
                            col_max: col + r,
                            row_min: row - r,
                            row_max: row + r,
                        })
                }
            }
            let mut probe = Probe { stop: &stop, width, min_radius, clear_radius };
            let skipping = ray.walk_skipping(width, height, t_end, &mut probe);
            prop_assert_eq!(expected, skipping);
        }
    }

    #[test]
    fn walk_to_visits_the_last_cell_before_the_ray_leaves_the_grid() {
        // Regression: the fixed-point walk stopped one cell short of the border.
        let g = GridGeometry::new(5, 3, 1.0, Point2::new(0.0, 0.0));
        let ray = GridRay::new(&g, Point2::new(0.5, 1.5), 1.0, 0.0);
        let mut cells = Vec::new();
        let end = ray.walk_to(5, 3, 100.0, |i| {
            cells.push(i);
            false
        });
        assert_eq!(end, None);
        assert_eq!(cells, vec![5, 6, 7, 8, 9]);
    }

    #[test]
    fn walk_to_returns_the_cell_that_reaches_the_end_unvisited() {
        let g = GridGeometry::new(10, 1, 1.0, Point2::new(0.0, 0.0));
        let ray = GridRay::new(&g, Point2::new(0.5, 0.5), 1.0, 0.0);
        let mut cells = Vec::new();
        let end = ray.walk_to(10, 1, 3.2, |i| {
            cells.push(i);
            false
        });
        // Cells 0..=2 are left before t = 3.2 (their exits: 0.5, 1.5, 2.5); cell 3 holds it.
        assert_eq!(cells, vec![0, 1, 2]);
        assert_eq!(end, Some((3, 2.5)));
        // A NaN end is never reached: the walk runs to the border.
        let end = ray.walk_to(10, 1, f64::NAN, |_| false);
        assert_eq!(end, None);
        // An end at or before the start is reached in the first cell, which is not visited.
        let end = ray.walk_to(10, 1, -2.0, |_| panic!("nothing to visit"));
        assert_eq!(end, Some((0, 0.0)));
    }
}

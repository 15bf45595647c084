//! The paper-000 cell view: a scene seen as coarse cells (paper 000 §VI: 20 × 20 cells of
//! 0.84 m²), each with a class that follows from the heights inside it (§IV-A-4, Fig. 4) and the
//! cell categories of §V (open, climbable and non-climbable obstacle, victim; a drop counts as
//! non-climbable in the paper and has its own class here).
//!
//! For every coarse cell the view fits the plane `z = a·x + b·y + c` by least squares to the
//! floor heights of its obstacle-free fine cells ([`LeastSquaresPlane`]) and classifies it with
//! [`CellViewParams`]:
//!
//! 1. more than `max_obstacle_fraction` of its fine cells are walls or furniture (or none is
//!    free) → [`CellClass::NonClimbable`];
//! 2. its median height lies more than `drop_depth_m` below the reference floor →
//!    [`CellClass::Drop`];
//! 3. slope, roughness (RMS residual of the fit) and height deviation (the larger of
//!    `highest − reference` and `reference − lowest`) within the open limits →
//!    [`CellClass::Open`];
//! 4. within the climbable limits → [`CellClass::Climbable`];
//! 5. otherwise → [`CellClass::NonClimbable`].
//!
//! The **reference floor** is the median of the median heights of the *flat* cells (slope and
//! roughness within the open limits, obstacle fraction within its limit); a scene without flat
//! cells uses the median of all obstacle-free fine cells. So the view assumes one ground level,
//! as in the paper's simulated scenes: a raised platform reads as rubble, a lowered one as a drop.
//!
//! A cell holding a victim (its position) is [`CellClass::Victim`]; its terrain class is kept in
//! [`CellView::terrain_classes`]. The terrain under a victim need not be passable: a victim cell
//! is entered (by [`CellView::reachable`]) exactly when its terrain could be. The generators only
//! put victims on open or climbable terrain.
//!
//! **Alignment.** The coarse grid has `floor(extent / side)` cells per axis and is centred on
//! the fine grid: the leftover strip (extent mod side) is split equally between both borders and
//! belongs to no coarse cell. A fine cell belongs to the coarse cell that holds its centre. The
//! rubble generator pads its 20 × 20 arena with one fine cell of boundary wall on each side, so
//! its coarse cells start at the arena's corner and hold no wall.

mod params;
mod plane;

pub use self::params::{CellViewParams, PAPER_CELL_AREA_M2, PAPER_CELL_SIDE_M};
pub use self::plane::{LeastSquaresPlane, PlaneFit};

use crate::geometry::{Point2, Rect};
use crate::grid::{Cell, GridGeometry, NEIGHBORS8};
use crate::scene::{Scene, obstacle};
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// The class of a coarse cell (paper 000 §V categories i–iv; drops from §IV-A-4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CellClass {
    /// Obstacle-free, level and smooth: every robot drives through.
    Open,
    /// Rubble a tracked robot can climb over.
    Climbable,
    /// Rubble too steep, rough or high to climb, or a cell blocked by walls or furniture.
    NonClimbable,
    /// A hole: the floor falls away abruptly (non-climbable in the paper, Fig. 4(c)).
    Drop,
    /// A cell holding a victim.
    Victim,
}

impl CellClass {
    pub const ALL: [CellClass; 5] = [
        CellClass::Open,
        CellClass::Climbable,
        CellClass::NonClimbable,
        CellClass::Drop,
        CellClass::Victim,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            CellClass::Open => "open",
            CellClass::Climbable => "climbable",
            CellClass::NonClimbable => "non_climbable",
            CellClass::Drop => "drop",
            CellClass::Victim => "victim",
        }
    }

    /// Whether a robot may drive onto terrain of this class (for terrain classes, not `Victim`).
    pub fn is_passable_terrain(self, can_climb: bool) -> bool {
        match self {
            CellClass::Open => true,
            CellClass::Climbable => can_climb,
            CellClass::NonClimbable | CellClass::Drop | CellClass::Victim => false,
        }
    }
}

impl std::fmt::Display for CellClass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What the view measured in one coarse cell. Heights are over the obstacle-free fine cells;
/// a cell without any has zero heights, slope and roughness and `obstacle_fraction` 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CellTerrain {
    /// Inclination of the least-squares plane, radians.
    pub slope_rad: f64,
    /// Direction in which the plane rises, radians (0 on level ground).
    pub uphill_rad: f64,
    /// RMS residual of the plane fit, metres.
    pub roughness_m: f64,
    pub mean_height_m: f64,
    pub median_height_m: f64,
    pub min_height_m: f64,
    pub max_height_m: f64,
    /// Share of the cell's fine cells taken by walls or furniture, 0–1.
    pub obstacle_fraction: f64,
    /// Number of fine cells in the coarse cell (obstacles included).
    pub fine_cells: u32,
}

/// A scene seen as coarse cells; see the [module documentation](self).
#[derive(Clone, Debug, PartialEq)]
pub struct CellView {
    /// The coarse grid: `cols × rows` cells of side `cell_size_m`, origin at the lower-left
    /// corner of cell (0, 0) in the world frame.
    pub geometry: GridGeometry,
    pub cols: u32,
    pub rows: u32,
    pub cell_size_m: f64,
    /// Height of the reference floor, metres (see the module documentation).
    pub reference_floor_m: f64,
    /// Class of every coarse cell, row-major (row 0 south), victims included.
    pub classes: Vec<CellClass>,
    /// Class of every coarse cell's terrain, never `Victim`.
    pub terrain_classes: Vec<CellClass>,
    /// Measurements of every coarse cell, row-major.
    pub terrain: Vec<CellTerrain>,
}

impl CellView {
    /// Builds the view of `scene`. Never panics: a cell size that is not a positive finite
    /// number falls back to the scene's, then to [`PAPER_CELL_SIDE_M`], and is raised to the
    /// fine resolution if smaller. Check outside parameters with [`CellViewParams::validate`].
    pub fn from_scene(scene: &Scene, params: &CellViewParams) -> CellView {
        let fine = *scene.geometry();
        let cell_size_m = choose_cell_size(scene, params);
        let (extent_x, extent_y) = fine.extent_m();
        let cols = axis_cells(extent_x, cell_size_m);
        let rows = axis_cells(extent_y, cell_size_m);
        let origin = Point2::new(
            fine.origin.x + (extent_x - f64::from(cols) * cell_size_m) / 2.0,
            fine.origin.y + (extent_y - f64::from(rows) * cell_size_m) / 2.0,
        );
        let geometry = GridGeometry::new(cols, rows, cell_size_m, origin);
        let col_ranges = fine_ranges(
            fine.width,
            fine.resolution_m,
            origin.x - fine.origin.x,
            cell_size_m,
            cols,
        );
        let row_ranges = fine_ranges(
            fine.height,
            fine.resolution_m,
            origin.y - fine.origin.y,
            cell_size_m,
            rows,
        );

        let heights = scene.floor_height_m.as_slice();
        let obstacles = scene.obstacle.as_slice();
        let width = fine.width as usize;
        let res = fine.resolution_m;
        let mut terrain = Vec::with_capacity(geometry.len());
        let mut buffer: Vec<f32> = Vec::new();
        for (row, rows_fine) in row_ranges.iter().enumerate() {
            for (col, cols_fine) in col_ranges.iter().enumerate() {
                let centre = geometry.cell_center(Cell::new(col as i32, row as i32));
                let x0 = fine.origin.x + 0.5 * res - centre.x;
                let y0 = fine.origin.y + 0.5 * res - centre.y;
                let mut plane = LeastSquaresPlane::new();
                let mut blocked = 0u32;
                let mut sum = 0.0f64;
                buffer.clear();
                for r in rows_fine.clone() {
                    let y = y0 + r as f64 * res;
                    let base = r * width;
                    for c in cols_fine.clone() {
                        if obstacles[base + c] != obstacle::NONE {
                            blocked += 1;
                            continue;
                        }
                        let z = heights[base + c];
                        plane.push(x0 + c as f64 * res, y, f64::from(z));
                        sum += f64::from(z);
                        buffer.push(z);
                    }
                }
                terrain.push(measure(&plane, &mut buffer, blocked, sum));
            }
        }

        let reference_floor_m = reference_floor(&terrain, params, scene);
        let terrain_classes: Vec<CellClass> = terrain
            .iter()
            .map(|t| classify(t, reference_floor_m, params))
            .collect();
        let mut classes = terrain_classes.clone();
        for victim in &scene.victims {
            if let Some(i) = geometry.checked_index(geometry.world_to_cell(victim.position)) {
                classes[i] = CellClass::Victim;
            }
        }
        CellView {
            geometry,
            cols,
            rows,
            cell_size_m,
            reference_floor_m,
            classes,
            terrain_classes,
            terrain,
        }
    }

    /// Row-major index of a coarse cell, `None` outside the view.
    pub fn index(&self, coarse: Cell) -> Option<usize> {
        self.geometry.checked_index(coarse)
    }

    /// Class of a coarse cell; outside the view everything is `NonClimbable` (the boundary).
    pub fn class(&self, coarse: Cell) -> CellClass {
        self.index(coarse)
            .map_or(CellClass::NonClimbable, |i| self.classes[i])
    }

    /// Terrain class of a coarse cell (never `Victim`); `NonClimbable` outside the view.
    pub fn terrain_class(&self, coarse: Cell) -> CellClass {
        self.index(coarse)
            .map_or(CellClass::NonClimbable, |i| self.terrain_classes[i])
    }

    /// Measurements of a coarse cell, `None` outside the view.
    pub fn terrain_at(&self, coarse: Cell) -> Option<&CellTerrain> {
        self.index(coarse).map(|i| &self.terrain[i])
    }

    /// The coarse cell holding a world point, `None` outside the view.
    pub fn cell_of(&self, p: Point2) -> Option<Cell> {
        let c = self.geometry.world_to_cell(p);
        self.geometry.contains(c).then_some(c)
    }

    /// The centre of a coarse cell in the world frame.
    pub fn cell_center(&self, coarse: Cell) -> Point2 {
        self.geometry.cell_center(coarse)
    }

    /// The square a coarse cell covers in the world frame.
    pub fn cell_rect(&self, coarse: Cell) -> Rect {
        let s = self.cell_size_m;
        let x0 = self.geometry.origin.x + f64::from(coarse.col) * s;
        let y0 = self.geometry.origin.y + f64::from(coarse.row) * s;
        Rect::new(x0, y0, x0 + s, y0 + s)
    }

    /// Number of cells of a class (victim cells counted as `Victim`).
    pub fn count(&self, class: CellClass) -> usize {
        self.classes.iter().filter(|&&c| c == class).count()
    }

    /// Whether a robot may enter a coarse cell: open terrain, or climbable terrain when it can
    /// climb. A victim cell counts by its terrain.
    pub fn is_passable(&self, coarse: Cell, can_climb: bool) -> bool {
        self.terrain_class(coarse).is_passable_terrain(can_climb)
    }

    /// The coarse cells a robot starting in `start` can reach, 4-connected through passable cells
    /// (see [`CellView::is_passable`]), as a row-major mask. All false when `start` is outside
    /// the view or not passable.
    pub fn reachable(&self, start: Cell, can_climb: bool) -> Vec<bool> {
        let mut mask = vec![false; self.classes.len()];
        if !self.is_passable(start, can_climb) {
            return mask;
        }
        let mut stack = vec![start];
        mask[self.geometry.index(start)] = true;
        while let Some(c) = stack.pop() {
            for &(dc, dr) in &NEIGHBORS8[..4] {
                let n = Cell::new(c.col + dc, c.row + dr);
                let Some(i) = self.index(n) else { continue };
                if !mask[i] && self.terrain_classes[i].is_passable_terrain(can_climb) {
                    mask[i] = true;
                    stack.push(n);
                }
            }
        }
        mask
    }
}

fn choose_cell_size(scene: &Scene, params: &CellViewParams) -> f64 {
    let positive = |v: f64| (v.is_finite() && v > 0.0).then_some(v);
    let side = params
        .cell_size_m
        .and_then(positive)
        .or_else(|| scene.coarse_cell_m.and_then(positive))
        .unwrap_or(PAPER_CELL_SIDE_M);
    side.max(scene.geometry().resolution_m)
}

/// Whole coarse cells along an axis (at least one; a tolerance absorbs rounding of exact fits).
fn axis_cells(extent_m: f64, side_m: f64) -> u32 {
    let n = (extent_m / side_m + 1e-9).floor();
    n.clamp(1.0, f64::from(u32::MAX)) as u32
}

/// For each coarse index along an axis, the range of fine indices whose centres lie in it.
/// `offset_m` is the coarse origin relative to the fine origin.
fn fine_ranges(
    fine_len: u32,
    res: f64,
    offset_m: f64,
    side: f64,
    coarse_len: u32,
) -> Vec<Range<usize>> {
    let mut ranges = vec![0..0; coarse_len as usize];
    for f in 0..fine_len as usize {
        let k = (((f as f64 + 0.5) * res - offset_m) / side).floor();
        if k >= 0.0 && k < f64::from(coarse_len) {
            let r = &mut ranges[k as usize];
            if r.start == r.end {
                *r = f..f + 1;
            } else {
                r.end = f + 1;
            }
        }
    }
    ranges
}

fn measure(plane: &LeastSquaresPlane, heights: &mut [f32], blocked: u32, sum: f64) -> CellTerrain {
    let free = plane.len();
    let fine_cells = free + blocked;
    let obstacle_fraction = if fine_cells == 0 {
        1.0
    } else {
        f64::from(blocked) / f64::from(fine_cells)
    };
    let Some(fit) = plane.fit() else {
        return CellTerrain {
            obstacle_fraction,
            fine_cells,
            ..CellTerrain::default()
        };
    };
    let (min, max) = heights
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &z| {
            (lo.min(z), hi.max(z))
        });
    CellTerrain {
        slope_rad: fit.slope_rad,
        uphill_rad: fit.uphill_rad,
        roughness_m: fit.roughness_m,
        mean_height_m: sum / f64::from(free),
        median_height_m: median(heights),
        min_height_m: f64::from(min),
        max_height_m: f64::from(max),
        obstacle_fraction,
        fine_cells,
    }
}

/// Median of a non-empty slice (mean of the two middle values for an even length); reorders it.
fn median(values: &mut [f32]) -> f64 {
    let n = values.len();
    let (left, mid, _) = values.select_nth_unstable_by(n / 2, f32::total_cmp);
    let upper = f64::from(*mid);
    if n % 2 == 1 {
        upper
    } else {
        let lower = left.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        (f64::from(lower) + upper) / 2.0
    }
}

fn is_flat(t: &CellTerrain, params: &CellViewParams) -> bool {
    t.fine_cells > 0
        && t.obstacle_fraction < 1.0
        && t.obstacle_fraction <= params.max_obstacle_fraction
        && t.slope_rad <= params.open_max_slope_rad
        && t.roughness_m <= params.open_max_roughness_m
}

/// Median of the flat cells' medians; without flat cells, the median of all free fine cells.
fn reference_floor(terrain: &[CellTerrain], params: &CellViewParams, scene: &Scene) -> f64 {
    let mut flat: Vec<f32> = terrain
        .iter()
        .filter(|t| is_flat(t, params))
        .map(|t| t.median_height_m as f32)
        .collect();
    if !flat.is_empty() {
        return median(&mut flat);
    }
    let mut free: Vec<f32> = scene
        .floor_height_m
        .as_slice()
        .iter()
        .zip(scene.obstacle.as_slice())
        .filter(|&(_, &o)| o == obstacle::NONE)
        .map(|(&z, _)| z)
        .collect();
    if free.is_empty() {
        0.0
    } else {
        median(&mut free)
    }
}

fn classify(t: &CellTerrain, reference: f64, p: &CellViewParams) -> CellClass {
    if t.obstacle_fraction >= 1.0 || t.obstacle_fraction > p.max_obstacle_fraction {
        return CellClass::NonClimbable;
    }
    if t.median_height_m < reference - p.drop_depth_m {
        return CellClass::Drop;
    }
    let deviation = (t.max_height_m - reference).max(reference - t.min_height_m);
    p.terrain_class(t.slope_rad, t.roughness_m, deviation)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_even_and_odd_lengths() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
    }

    #[test]
    fn paper_cell_side_is_the_root_of_the_paper_area() {
        assert!((PAPER_CELL_SIDE_M * PAPER_CELL_SIDE_M - PAPER_CELL_AREA_M2).abs() < 1e-15);
    }

    #[test]
    fn fine_ranges_split_the_leftover_between_both_borders() {
        // 22 fine cells of 0.1 m, coarse side 1.0 m: two coarse cells, origin offset 0.1 m.
        let ranges = fine_ranges(22, 0.1, 0.1, 1.0, 2);
        assert_eq!(ranges, vec![1..11, 11..21]);
    }
}

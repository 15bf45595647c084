//! Paper 000 §VI rubble arenas: 20 × 20 coarse cells of 0.84 m² with open floor, climbable and
//! non-climbable rubble, drops, 7–8 victims in corners and hard-to-reach places, heat sources
//! that are not victims, and three start poses.
//!
//! The terrain is made of floor heights (and furniture-like slabs in the obstacle layer), never of
//! labels: every coarse cell is painted so that the [cell view](crate::cellview) with default
//! parameters classifies it as the generator intended, and the intention is kept in
//! `ground_truth.features` (`Rubble { climbable }` or `Drop`, one per coarse cell) so that tests can
//! compare. Generation runs in three steps:
//!
//! 1. `layout`: the intended class of every coarse cell. Barriers of non-climbable rubble split
//!    the arena into isolated regions by recursive division; each barrier is crossed by one gate,
//!    a single open cell or a climbable crossing (paper: regions "the robot could only enter
//!    through a single open cell or by traversing over climbable obstacles"). Clutter blobs of
//!    rubble and holes follow until the style's class shares are met, never cutting the passable
//!    cells apart.
//! 2. `placement`: start pose 0, the victims (corners, dead ends, far away, behind climbable
//!    rubble), the other two start poses (far from each other) and the heat sources.
//! 3. `paint`: floor heights and slabs of the fine grid, and the ground truth.
//!
//! Every victim and every start pose is reachable from start pose 0 by a robot that climbs; with
//! `style.needs_climb_only_victim()` at least one victim is reachable only over climbable rubble.

mod layout;
mod paint;
mod placement;
mod style;
mod zone;

pub use self::style::{ClassShares, RubbleStyle};
pub use self::zone::{RubbleZone, lay_rubble};

use crate::cellview::PAPER_CELL_AREA_M2;
use crate::error::{Result, WorldError};
use crate::geometry::{Point2, Pose2};
use crate::grid::{Cell, GridGeometry};
use crate::scene::{HeatSource, Provenance, Scene, Victim, obstacle};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::ops::RangeInclusive;
use std::path::Path;

/// Parameters of a rubble arena. `Default` gives the paper's arena: 20 × 20 cells of 0.84 m²,
/// 10 fine cells per coarse side, 7–8 victims, 1–2 heat sources, the training style.
#[derive(Clone, Debug, PartialEq)]
pub struct RubbleParams {
    /// Coarse cells along x (paper 000 §VI: 20).
    pub cols: u32,
    /// Coarse cells along y (paper 000 §VI: 20).
    pub rows: u32,
    /// Area of one coarse cell, m² (paper 000 §VI: 0.84).
    pub cell_area_m2: f64,
    /// Fine cells along the side of a coarse cell; the fine resolution is `√cell_area_m2 / this`,
    /// so coarse cells align with fine cells (default 10: 0.0917 m, close to the usual 0.1 m).
    pub fine_cells_per_side: u32,
    /// Number of victims, drawn uniformly (paper 000 §VI: "7–8 victims").
    pub victims: RangeInclusive<u32>,
    /// Number of heat sources that are not victims, drawn uniformly (default 1–2).
    pub heat_sources: RangeInclusive<u32>,
    /// Layout style: the training scenes or one of the evaluation scenes A, B, C.
    pub style: RubbleStyle,
    /// Heights and sizes of the painted terrain.
    pub terrain: RubbleTerrain,
}

impl Default for RubbleParams {
    fn default() -> Self {
        Self {
            cols: 20,
            rows: 20,
            cell_area_m2: PAPER_CELL_AREA_M2,
            fine_cells_per_side: 10,
            victims: 7..=8,
            heat_sources: 1..=2,
            style: RubbleStyle::Random,
            terrain: RubbleTerrain::default(),
        }
    }
}

/// How each intended class is painted into the fine grid. The defaults keep every measured
/// quantity well inside the cell view's default limits (in brackets):
///
/// - open floor: uniform noise ±`open_noise_m` (roughness ≈ 0.002 m [0.02], height ≤ 0.004 m [0.05]);
/// - climbable rubble: a ramp of `climbable_slope_rad` (8–13° [5°, 20°]) rising from a foot of
///   `ramp_foot_m` toward a neighbour that is not open floor, or (with probability
///   `1 − ramp_share`) a level layer of loose rubble `layer_height_m` high; both with uniform
///   noise ±`climbable_noise_m` (roughness ≈ 0.029 m [0.02, 0.05]); a ramp is flattened where
///   needed (large coarse cells) so that its top without noise stays ≤ `ramp_top_m` (0.25 m),
///   so the highest point stays ≤ 0.30 m [0.35];
/// - non-climbable rubble: a rough cone `pile_peak_m` high (0.6–1.4 m [0.35]) with noise
///   `0..pile_noise_m`, or (with probability `slab_share`) a furniture-like slab covering
///   `slab_cover` of the cell (≥ 50 % [20 %]);
/// - drop: a hole `drop_depth_m` deep (0.4–1.0 m [0.25]) with a rough floor ±`drop_noise_m`.
#[derive(Clone, Debug, PartialEq)]
pub struct RubbleTerrain {
    pub open_noise_m: f64,
    pub climbable_slope_rad: RangeInclusive<f64>,
    pub ramp_foot_m: RangeInclusive<f64>,
    pub layer_height_m: RangeInclusive<f64>,
    pub ramp_share: f64,
    pub ramp_top_m: f64,
    pub climbable_noise_m: f64,
    pub pile_peak_m: RangeInclusive<f64>,
    pub pile_noise_m: f64,
    pub slab_share: f64,
    pub slab_cover: RangeInclusive<f64>,
    /// Height recorded in the ground truth for a slab (the obstacle layer has no height), metres.
    pub slab_height_m: f64,
    pub drop_depth_m: RangeInclusive<f64>,
    pub drop_noise_m: f64,
}

impl Default for RubbleTerrain {
    fn default() -> Self {
        Self {
            open_noise_m: 0.004,
            climbable_slope_rad: 8f64.to_radians()..=13f64.to_radians(),
            ramp_foot_m: 0.03..=0.05,
            layer_height_m: 0.07..=0.12,
            ramp_share: 0.6,
            ramp_top_m: 0.25,
            climbable_noise_m: 0.05,
            pile_peak_m: 0.6..=1.4,
            pile_noise_m: 0.1,
            slab_share: 0.3,
            slab_cover: 0.5..=1.0,
            slab_height_m: 1.0,
            drop_depth_m: 0.4..=1.0,
            drop_noise_m: 0.02,
        }
    }
}

/// Limits [`generate_rubble`] clamps to (and [`RubbleParams::validate`] reports).
const MIN_SIDE_CELLS: u32 = 5;
const MAX_SIDE_CELLS: u32 = 200;
const FINE_PER_SIDE: RangeInclusive<u32> = 3..=40;
const CELL_AREA_M2: RangeInclusive<f64> = 0.01..=100.0;
/// Layouts tried before the last one is returned as it is, possibly short of a victim or a
/// class share (never needed with the defaults: 1 200 arenas of all styles met every target on
/// the first try).
const MAX_ATTEMPTS: u32 = 64;

impl RubbleParams {
    /// Parameters for one of the styles, otherwise the defaults.
    pub fn with_style(style: RubbleStyle) -> Self {
        Self {
            style,
            ..Self::default()
        }
    }

    /// Side of a coarse cell, metres.
    pub fn cell_side_m(&self) -> f64 {
        self.sanitized().cell_area_m2.sqrt()
    }

    /// Reports the first parameter outside its accepted range; `source` names where the
    /// parameters came from. [`generate_rubble`] clamps instead of failing.
    pub fn validate(&self, source: &Path) -> Result<()> {
        for (field, v) in [("cols", self.cols), ("rows", self.rows)] {
            if !(MIN_SIDE_CELLS..=MAX_SIDE_CELLS).contains(&v) {
                return Err(WorldError::invalid(
                    source,
                    field,
                    v,
                    format!("{MIN_SIDE_CELLS}..={MAX_SIDE_CELLS} coarse cells"),
                ));
            }
        }
        if !FINE_PER_SIDE.contains(&self.fine_cells_per_side) {
            return Err(WorldError::invalid(
                source,
                "fine_cells_per_side",
                self.fine_cells_per_side,
                format!("{}..={}", FINE_PER_SIDE.start(), FINE_PER_SIDE.end()),
            ));
        }
        if !CELL_AREA_M2.contains(&self.cell_area_m2) {
            return Err(WorldError::invalid(
                source,
                "cell_area_m2",
                self.cell_area_m2,
                format!("{}..={} m²", CELL_AREA_M2.start(), CELL_AREA_M2.end()),
            ));
        }
        for (field, r) in [
            ("victims", &self.victims),
            ("heat_sources", &self.heat_sources),
        ] {
            if r.is_empty() {
                return Err(WorldError::invalid(
                    source,
                    field,
                    format!("{}..={}", r.start(), r.end()),
                    "a range min..=max with min ≤ max",
                ));
            }
        }
        Ok(())
    }

    /// A copy with every value clamped into its accepted range.
    fn sanitized(&self) -> RubbleParams {
        let mut p = self.clone();
        p.cols = p.cols.clamp(MIN_SIDE_CELLS, MAX_SIDE_CELLS);
        p.rows = p.rows.clamp(MIN_SIDE_CELLS, MAX_SIDE_CELLS);
        p.fine_cells_per_side = p
            .fine_cells_per_side
            .clamp(*FINE_PER_SIDE.start(), *FINE_PER_SIDE.end());
        p.cell_area_m2 = if p.cell_area_m2.is_finite() {
            p.cell_area_m2
                .clamp(*CELL_AREA_M2.start(), *CELL_AREA_M2.end())
        } else {
            PAPER_CELL_AREA_M2
        };
        let ordered = |r: &RangeInclusive<u32>| *r.start().min(r.end())..=*r.start().max(r.end());
        p.victims = ordered(&p.victims);
        p.heat_sources = ordered(&p.heat_sources);
        p
    }
}

/// Generates a rubble arena (deterministic in `seed` and `params`). Out-of-range parameters are
/// clamped (see [`RubbleParams::validate`]).
pub fn generate_rubble(seed: u64, params: &RubbleParams) -> Scene {
    let params = params.sanitized();
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let config = params.style.config();
    let mut last = None;
    for _ in 0..MAX_ATTEMPTS {
        let Some(layout) = layout::build(
            &mut rng,
            &config,
            params.cols as i32,
            params.rows as i32,
            &params.terrain,
        ) else {
            continue;
        };
        let victims = rng.random_range(params.victims.clone());
        let heat = rng.random_range(params.heat_sources.clone());
        let placement = placement::place(&mut rng, &layout, &config, victims, heat);
        let complete = placement.complete;
        last = Some((layout, placement));
        if complete {
            break;
        }
    }
    let (layout, placement) = match last {
        Some(found) => found,
        // Only reachable with extreme parameters: an unconstrained layout.
        None => {
            let layout = layout::build_unchecked(
                &mut rng,
                &config,
                params.cols as i32,
                params.rows as i32,
                &params.terrain,
            );
            let placement = placement::place(
                &mut rng,
                &layout,
                &config,
                *params.victims.start(),
                *params.heat_sources.start(),
            );
            (layout, placement)
        }
    };
    assemble(&mut rng, seed, &params, &layout, &placement)
}

fn assemble(
    rng: &mut Pcg64Mcg,
    seed: u64,
    params: &RubbleParams,
    layout: &layout::Layout,
    placement: &placement::Placement,
) -> Scene {
    let n = params.fine_cells_per_side;
    let side = params.cell_area_m2.sqrt();
    let res = side / f64::from(n);
    // One fine cell of boundary wall outside the arena on every side: the arena's lower-left
    // corner is the world origin and every coarse cell is wall-free.
    let geometry = GridGeometry::new(
        params.cols * n + 2,
        params.rows * n + 2,
        res,
        Point2::new(-res, -res),
    );
    let mut scene = Scene::empty(format!("rubble-{}-{seed}", params.style.as_str()), geometry);
    scene.provenance = Provenance {
        source: "rubble".into(),
        seed: Some(seed),
        detail: format!(
            "style={} cols={} rows={} cell_area_m2={} fine_cells_per_side={}",
            params.style.as_str(),
            params.cols,
            params.rows,
            params.cell_area_m2,
            n
        ),
    };
    scene.coarse_cell_m = Some(side);
    let (w, h) = (geometry.width as i32, geometry.height as i32);
    for col in 0..w {
        scene.obstacle[Cell::new(col, 0)] = obstacle::WALL;
        scene.obstacle[Cell::new(col, h - 1)] = obstacle::WALL;
    }
    for row in 0..h {
        scene.obstacle[Cell::new(0, row)] = obstacle::WALL;
        scene.obstacle[Cell::new(w - 1, row)] = obstacle::WALL;
    }
    let painter = paint::Painter {
        fine_per_side: n,
        side_m: side,
        terrain: &params.terrain,
    };
    scene.ground_truth.features = painter.paint(rng, &mut scene, layout);

    let centre = |c: Cell| {
        Point2::new(
            (f64::from(c.col) + 0.5) * side,
            (f64::from(c.row) + 0.5) * side,
        )
    };
    scene.start_poses = placement
        .starts
        .iter()
        .map(|&(c, theta)| Pose2::new(centre(c).x, centre(c).y, theta))
        .collect();
    let buried_count = rng.random_range(2..=4usize).min(placement.victims.len());
    for (i, v) in placement.victims.iter().enumerate() {
        let offset = placement::corner_offset(layout, v.cell, 0.25 * side);
        let jitter = 0.05 * side;
        let position = Point2::new(
            centre(v.cell).x + offset.x + rng.random_range(-jitter..=jitter),
            centre(v.cell).y + offset.y + rng.random_range(-jitter..=jitter),
        );
        // The first few victims (in placement order: the hardest to reach) are partly buried.
        let buried_fraction = if i < buried_count {
            rng.random_range(0.3..=0.8)
        } else {
            rng.random_range(0.0..=0.15)
        };
        scene.victims.push(Victim {
            id: i as u32 + 1,
            position,
            heat_c: rng.random_range(30.0..=37.0),
            visible_size_m2: rng.random_range(0.25..=0.7),
            buried_fraction,
        });
    }
    for (i, &cell) in placement.heat_sources.iter().enumerate() {
        let (kind, heat, size) = match rng.random_range(0..3u8) {
            0 => (
                "radiator",
                rng.random_range(40.0..=60.0),
                rng.random_range(0.3..=0.6),
            ),
            1 => (
                "warm pipe",
                rng.random_range(30.0..=40.0),
                rng.random_range(0.05..=0.2),
            ),
            _ => (
                "smouldering debris",
                rng.random_range(60.0..=150.0),
                rng.random_range(0.1..=0.5),
            ),
        };
        let jitter = 0.25 * side;
        scene.heat_sources.push(HeatSource {
            id: i as u32 + 1,
            position: Point2::new(
                centre(cell).x + rng.random_range(-jitter..=jitter),
                centre(cell).y + rng.random_range(-jitter..=jitter),
            ),
            heat_c: heat,
            size_m2: size,
            kind: kind.into(),
        });
    }
    scene
}

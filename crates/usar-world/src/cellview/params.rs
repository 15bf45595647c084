//! Thresholds of the cell classification, with their sources.

use super::CellClass;
use crate::error::{Result, WorldError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Side of a paper-000 coarse cell, metres: `√0.84` (paper 000 §VI: "a 20 by 20 cell environment
/// (approximately 336 m²) with individual cells having an area of 0.84 m²").
pub const PAPER_CELL_SIDE_M: f64 = 0.916_515_138_991_168;

/// Area of a paper-000 coarse cell, m² (paper 000 §VI).
pub const PAPER_CELL_AREA_M2: f64 = 0.84;

/// How the terrain of a coarse cell is classified (paper 000 §IV-A-4 and Fig. 4).
///
/// The paper classifies a rubble pile as open, climbable or non-climbable from the slope and the
/// smoothness of a least-squares plane fitted to its depth profile, and counts a sudden drop as
/// non-climbable; it gives no numbers. The defaults below are for a small tracked robot of the
/// paper's kind (about 0.3 m tall, no flippers):
///
/// | field | default | why |
/// |---|---|---|
/// | `open_max_slope_rad` | 5° | an accessible ramp is ≤ 1:12 ≈ 4.8°; floors of damaged buildings tilt a few degrees |
/// | `open_max_roughness_m` | 0.02 m | tile, carpet and dust stay well below it; loose rubble (bricks, 5–10 cm) above |
/// | `open_max_height_m` | 0.05 m | a door sill or a cable cover; anything higher must be climbed |
/// | `climbable_max_slope_rad` | 20° | typical limit of a small tracked robot on loose material (paper 004: wheeled robots ≤ 15°, crawlers ≤ 35° on firm slopes) |
/// | `climbable_max_roughness_m` | 0.05 m | half a brick: tracks bridge it, deeper voids trap them |
/// | `climbable_max_height_m` | 0.35 m | about the robot's own height: higher piles topple it |
/// | `drop_depth_m` | 0.25 m | a step down the robot cannot drive back up (Fig. 4(c)) |
/// | `max_obstacle_fraction` | 0.2 | a fifth of the cell blocked by walls or slabs leaves no room for a robot that fills the cell |
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellViewParams {
    /// Side of a coarse cell, metres. `None` (the default): the scene's `coarse_cell_m`, or
    /// [`PAPER_CELL_SIDE_M`] when the scene has none. `Some(side)` overrides the scene.
    pub cell_size_m: Option<f64>,
    /// Largest slope of the fitted plane of an open cell, radians.
    pub open_max_slope_rad: f64,
    /// Largest RMS residual of the plane fit of an open cell, metres.
    pub open_max_roughness_m: f64,
    /// Largest deviation of an open cell's floor (its highest and its lowest fine cell) from the
    /// reference floor, metres.
    pub open_max_height_m: f64,
    /// Largest slope of a climbable cell, radians.
    pub climbable_max_slope_rad: f64,
    /// Largest roughness of a climbable cell, metres.
    pub climbable_max_roughness_m: f64,
    /// Largest deviation of a climbable cell's floor from the reference floor, metres.
    pub climbable_max_height_m: f64,
    /// A cell whose median floor height lies more than this below the reference floor is a drop,
    /// metres.
    pub drop_depth_m: f64,
    /// A cell with more than this fraction of its fine cells taken by walls or furniture is
    /// non-climbable.
    pub max_obstacle_fraction: f64,
}

impl Default for CellViewParams {
    fn default() -> Self {
        Self {
            cell_size_m: None,
            open_max_slope_rad: 5f64.to_radians(),
            open_max_roughness_m: 0.02,
            open_max_height_m: 0.05,
            climbable_max_slope_rad: 20f64.to_radians(),
            climbable_max_roughness_m: 0.05,
            climbable_max_height_m: 0.35,
            drop_depth_m: 0.25,
            max_obstacle_fraction: 0.2,
        }
    }
}

impl CellViewParams {
    /// The terrain class of a surface from its plane fit (slope, RMS roughness) and its height
    /// deviation from the reference floor (§IV-A-4, Fig. 4): within the open limits → open,
    /// within the climbable limits → climbable, otherwise non-climbable.
    pub fn terrain_class(&self, slope_rad: f64, roughness_m: f64, deviation_m: f64) -> CellClass {
        let within = |slope: f64, roughness: f64, height: f64| {
            slope_rad <= slope && roughness_m <= roughness && deviation_m <= height
        };
        if within(
            self.open_max_slope_rad,
            self.open_max_roughness_m,
            self.open_max_height_m,
        ) {
            CellClass::Open
        } else if within(
            self.climbable_max_slope_rad,
            self.climbable_max_roughness_m,
            self.climbable_max_height_m,
        ) {
            CellClass::Climbable
        } else {
            CellClass::NonClimbable
        }
    }

    /// Checks parameters that come from outside (a configuration file, the command line);
    /// `source` names where they came from in the error message.
    pub fn validate(&self, source: &Path) -> Result<()> {
        if let Some(side) = self.cell_size_m.filter(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(WorldError::invalid(
                source,
                "cell_size_m",
                side,
                "a positive side in metres",
            ));
        }
        let non_negative = [
            ("open_max_slope_rad", self.open_max_slope_rad),
            ("open_max_roughness_m", self.open_max_roughness_m),
            ("open_max_height_m", self.open_max_height_m),
            ("climbable_max_slope_rad", self.climbable_max_slope_rad),
            ("climbable_max_roughness_m", self.climbable_max_roughness_m),
            ("climbable_max_height_m", self.climbable_max_height_m),
            ("drop_depth_m", self.drop_depth_m),
        ];
        for (field, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(WorldError::invalid(source, field, v, "a finite number ≥ 0"));
            }
        }
        for (field, v) in [
            ("open_max_slope_rad", self.open_max_slope_rad),
            ("climbable_max_slope_rad", self.climbable_max_slope_rad),
        ] {
            if v >= std::f64::consts::FRAC_PI_2 {
                return Err(WorldError::invalid(source, field, v, "an angle below π/2"));
            }
        }
        let ordered = [
            (
                "climbable_max_slope_rad",
                self.open_max_slope_rad,
                self.climbable_max_slope_rad,
            ),
            (
                "climbable_max_roughness_m",
                self.open_max_roughness_m,
                self.climbable_max_roughness_m,
            ),
            (
                "climbable_max_height_m",
                self.open_max_height_m,
                self.climbable_max_height_m,
            ),
        ];
        for (field, open, climbable) in ordered {
            if climbable < open {
                return Err(WorldError::invalid(
                    source,
                    field,
                    climbable,
                    format!("at least the open limit {open}"),
                ));
            }
        }
        if !(0.0..=1.0).contains(&self.max_obstacle_fraction) {
            return Err(WorldError::invalid(
                source,
                "max_obstacle_fraction",
                self.max_obstacle_fraction,
                "a fraction in [0, 1]",
            ));
        }
        Ok(())
    }
}

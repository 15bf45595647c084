//! Ground truth a generator knows and a test needs: junctions, dead ends, corners, halls, slopes,
//! stairs. Never visible to a robot.

use crate::geometry::{Point2, Rect};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundTruth {
    #[serde(default)]
    pub junctions: Vec<Junction>,
    #[serde(default)]
    pub features: Vec<TerrainFeature>,
}

/// The kinds of divergence points of a passage network (paper 004 §III).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JunctionKind {
    DeadEnd,
    Corner,
    TJunction,
    Crossing,
}

/// Where passages meet, turn or end.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Junction {
    pub kind: JunctionKind,
    pub position: Point2,
}

/// A region with a terrain property a test can check against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub enum TerrainFeature {
    /// An open hall: free space wider than the laser's reach in at least one direction.
    Hall { region: Rect },
    /// A ramp of constant inclination; `uphill_rad` is the direction in which the floor rises.
    Slope {
        region: Rect,
        inclination_rad: f64,
        uphill_rad: f64,
    },
    /// A flight of stairs; `uphill_rad` is the direction of the rising steps.
    Stairs {
        region: Rect,
        step_height_m: f64,
        step_depth_m: f64,
        steps: u32,
        uphill_rad: f64,
    },
    /// A pile of rubble (paper 000), climbable or not by a tracked robot.
    Rubble {
        region: Rect,
        peak_height_m: f64,
        climbable: bool,
    },
    /// A hole in the floor.
    Drop { region: Rect, depth_m: f64 },
}

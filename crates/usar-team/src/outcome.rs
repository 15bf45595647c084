//! What a team mission produced: final metrics, a time series, per-robot figures.

use serde::Serialize;
use usar_map::OccupancyGrid;
use usar_world::Point2;

/// Why the mission ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Finish {
    /// No reachable frontier was left.
    Explored,
    /// The configured coverage was reached.
    CoverageTarget,
    /// Coverage stopped growing (frontiers were left that no robot could resolve).
    Stalled,
    /// The simulated time ran out.
    TimeLimit,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sample {
    pub time_s: f64,
    pub coverage: f64,
    pub explored_area_m2: f64,
    pub victims_seen: usize,
    pub distance_m: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VictimSighting {
    pub victim_id: u32,
    pub robot: usize,
    pub time_s: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RobotOutcome {
    pub robot: usize,
    pub distance_m: f64,
    pub collisions: u32,
    /// Positions once per simulated second.
    #[serde(skip)]
    pub trajectory: Vec<Point2>,
}

#[derive(Clone, Debug, Serialize)]
pub struct TeamOutcome {
    pub scene: String,
    pub robots: usize,
    pub time_s: f64,
    pub finish: Finish,
    /// Known part of the reachable area at the base station, in [0, 1].
    pub coverage: f64,
    pub explored_area_m2: f64,
    pub reachable_area_m2: f64,
    pub victims_total: usize,
    /// Victims whose human heat signature reached some robot's thermal camera.
    pub victims_seen: usize,
    pub victim_sightings: Vec<VictimSighting>,
    pub distance_m: f64,
    pub collisions: u32,
    pub per_robot: Vec<RobotOutcome>,
    pub series: Vec<Sample>,
    #[serde(skip)]
    pub merged_map: OccupancyGrid,
}

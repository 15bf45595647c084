//! What a team mission produced: final metrics, a time series, per-robot figures.

use serde::Serialize;
use std::collections::BTreeMap;
use usar_map::OccupancyGrid;
use usar_world::{Point2, RoomLabel};

/// Why the mission ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Finish {
    /// No reachable frontier was left.
    Explored,
    /// The configured coverage was reached.
    CoverageTarget,
    /// The configured fraction of the relevant area was reached (paper 002 §4.4).
    RelevantTarget,
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
    /// Explored relevant area (free floor of the rooms the hypothesis makes relevant), m².
    pub relevant_area_m2: f64,
    /// Candidate locations assigned so far, by the true label of their room.
    pub assigned_per_label: BTreeMap<RoomLabel, u32>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VictimSighting {
    pub victim_id: u32,
    pub robot: usize,
    pub time_s: f64,
}

/// A candidate location given to a robot at an auction (paper 002 §3.3): what the robot chose
/// and why.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Allocation {
    pub time_s: f64,
    pub robot: usize,
    /// The candidate location, metres.
    pub x_m: f64,
    pub y_m: f64,
    /// The label the semantic mapping module perceived for its room.
    pub label: Option<RoomLabel>,
    /// S(p) under the hypothesis (raw, before normalisation).
    pub relevance: f64,
    /// A(p): frontier length, cells (the whole room's with one candidate per room).
    pub frontier_cells: usize,
    /// Path length priced for the bid, metres.
    pub path_m: f64,
    /// The winning bid u(p, r) (after MRv2's discount and the commitment bonus).
    pub utility: f64,
    /// i(p) (1 under SR).
    pub ideal_robots: usize,
    /// How much of the candidate's room the team's map knew at the auction, 0 to 1 (None when
    /// the candidate lies in no room). It shows a strategy sending robots back to rooms already
    /// mostly seen, for the small frontiers that furniture shadows leave.
    pub room_known: Option<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RobotOutcome {
    pub robot: usize,
    pub distance_m: f64,
    pub collisions: u32,
    /// The largest distance between where the team believed the robot was and where it was,
    /// metres (0 under the localization oracle).
    pub max_pose_error_m: f64,
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
    /// Explored relevant area at the end, m², and the relevant area there is.
    pub relevant_area_m2: f64,
    pub relevant_total_m2: f64,
    /// When the known fraction of the relevant area first reached `relevant_target` (checked
    /// at each merge), simulated seconds.
    pub time_to_relevant_s: Option<f64>,
    pub relevant_target: f64,
    pub assigned_per_label: BTreeMap<RoomLabel, u32>,
    /// Every candidate given to a robot at an auction, in order.
    #[serde(skip)]
    pub allocations: Vec<Allocation>,
    #[serde(skip)]
    pub merged_map: OccupancyGrid,
}

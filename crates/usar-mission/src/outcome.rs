//! What a mission produced: per-system figures, the victims table, the series and the
//! pieces a picture needs.

use serde::Serialize;
use std::collections::BTreeMap;
use usar_btm::build::StopReason;
use usar_btm::model::Btm;
use usar_map::OccupancyGrid;
use usar_rescue::desk::HandOffRecord;
use usar_sim::host::RadioStats;
use usar_world::Point2;

/// What the team did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TeamFigures {
    pub robots: usize,
    pub relevant_area_m2: f64,
    pub relevant_total_m2: f64,
    /// Known part of the reachable floor.
    pub coverage: f64,
    pub explored_area_m2: f64,
    pub victims_total: usize,
    pub victims_seen: usize,
    pub distance_m: f64,
    pub collisions: u32,
    pub max_pose_error_m: f64,
    /// BTMs the base station received (and could not read), and the keep-out zones it drew
    /// from them.
    pub btm_maps_received: u32,
    pub btm_maps_unreadable: u32,
    pub keep_out_zones: usize,
}

/// What the crawler did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CrawlerFigures {
    pub nodes: usize,
    pub links: usize,
    pub searched_links: usize,
    pub unsearched_links: usize,
    pub nodes_by_type: BTreeMap<String, usize>,
    /// Why it stopped (`None`: the mission ended first).
    pub stop: Option<StopReason>,
    pub distance_m: f64,
    pub collisions: u32,
    pub max_position_error_m: f64,
    pub maps_sent: u32,
}

/// What paper 000's robot did in its zone.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RescuerFigures {
    /// Its zone's cells, and those it visited.
    pub zone_cells: usize,
    pub cells_visited: usize,
    /// The policy's training trials (0: read from a file).
    pub policy_trials: u32,
    pub primitives: u64,
    /// Possible victims it met (warm regions with a human signature), still undecided at the
    /// end, tagged (and how many of those were real victims).
    pub possible_victims: usize,
    pub pending: usize,
    pub tags: usize,
    pub true_tags: usize,
    pub handoffs_victim: u32,
    pub handoffs_stuck: u32,
    /// Seconds it stood waiting for the operator.
    pub waiting_s: f64,
    pub collisions: u32,
    pub distance_m: f64,
    /// Whether its policy ended the search (Exit).
    pub finished: bool,
}

/// What the one operator did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OperatorFigures {
    /// Hand-offs asked (by the rescuer, and by the base station for the team's reports) and
    /// answered.
    pub asked: usize,
    pub answered: usize,
    /// Seconds from a question to its answer: mean and longest.
    pub mean_wait_s: f64,
    pub max_wait_s: f64,
    /// Share of the mission the operator spent answering.
    pub busy_fraction: f64,
}

/// A victim: who detected it, who confirmed it, when.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VictimRow {
    pub id: u32,
    pub x_m: f64,
    pub y_m: f64,
    /// `team-K` (the team's K-th robot) or `rescuer`, and when (`None`: missed).
    pub detected_by: Option<String>,
    pub detected_at_s: Option<f64>,
    /// `operator` (a hand-off answered) or `rescuer` (it tagged by itself, p above 0.7).
    pub confirmed_by: Option<String>,
    pub confirmed_at_s: Option<f64>,
}

/// The victims at a glance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct VictimFigures {
    pub total: usize,
    pub detected: usize,
    pub confirmed: usize,
    pub missed: usize,
    /// Confirmations of what was no victim (the operator's false positives).
    pub false_confirmations: usize,
}

/// Coverage and relevant area at one time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MissionSample {
    pub time_s: f64,
    pub coverage: f64,
    pub relevant_area_m2: f64,
}

/// The mission's result.
#[derive(Clone, Debug, Serialize)]
pub struct MissionOutcome {
    pub scene: String,
    pub seed: u64,
    pub time_s: f64,
    pub team: TeamFigures,
    pub crawler: Option<CrawlerFigures>,
    pub rescuer: Option<RescuerFigures>,
    pub operator: OperatorFigures,
    pub victim_figures: VictimFigures,
    /// Collision events in which another robot stopped a robot's motion, counted per robot
    /// stopped (a head-on meeting counts twice), over all controllers.
    pub robot_contacts: u32,
    pub radio: RadioStats,
    pub victims: Vec<VictimRow>,
    /// Every hand-off: asked, answered, how.
    pub handoffs: Vec<HandOffRecord>,
    pub series: Vec<MissionSample>,
    /// For pictures: the team's merged map, its robots' believed trajectories, the crawler's
    /// BTM and estimated trajectory, the keep-out segments.
    #[serde(skip)]
    pub merged_map: OccupancyGrid,
    #[serde(skip)]
    pub team_trajectories: Vec<Vec<Point2>>,
    #[serde(skip)]
    pub btm: Option<Btm>,
    #[serde(skip)]
    pub crawler_trajectory: Vec<Point2>,
    /// The rescuer's zone and believed path (cell centres).
    #[serde(skip)]
    pub rescuer_zone: Option<usar_world::GridGeometry>,
    #[serde(skip)]
    pub rescuer_trajectory: Vec<Point2>,
    #[serde(skip)]
    pub keep_outs: Vec<(Point2, Point2, f64)>,
}

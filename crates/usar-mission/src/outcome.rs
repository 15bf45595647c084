//! What a mission produced: per-system figures, the victims table, the series and the
//! pieces a picture needs.

use serde::Serialize;
use std::collections::BTreeMap;
use usar_btm::build::StopReason;
use usar_btm::model::Btm;
use usar_map::OccupancyGrid;
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

/// A victim: who saw it and when.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VictimRow {
    pub id: u32,
    pub x_m: f64,
    pub y_m: f64,
    /// The team robot that first saw it, and when (`None`: missed).
    pub seen_by: Option<usize>,
    pub seen_at_s: Option<f64>,
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
    /// Collision events in which another robot stopped a robot's motion, counted per robot
    /// stopped (a head-on meeting counts twice), over all controllers.
    pub robot_contacts: u32,
    pub radio: RadioStats,
    pub victims: Vec<VictimRow>,
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
    #[serde(skip)]
    pub keep_outs: Vec<(Point2, Point2, f64)>,
}

//! What `usar team run` and the `team` campaign runner report of a mission (paper 002 §4):
//! final relevant area, total area and distance, and the same every simulated minute.

use crate::outcome::{Finish, RobotOutcome, TeamOutcome};
use serde::Serialize;
use std::collections::BTreeMap;
use usar_world::RoomLabel;

/// One sample of the per-minute series.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MinuteSample {
    pub time_s: f64,
    pub relevant_area_m2: f64,
    pub total_area_m2: f64,
    pub distance_m: f64,
    pub assigned_per_label: BTreeMap<RoomLabel, u32>,
}

/// The summary of one run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunSummary {
    pub scene: String,
    pub robots: usize,
    pub strategy: String,
    pub coordination: String,
    pub hypothesis: String,
    pub seed: u64,
    pub finish: Finish,
    pub time_s: f64,
    /// Explored relevant area at the end, m².
    pub relevant_area_m2: f64,
    /// Explored (known) area at the end, m².
    pub total_area_m2: f64,
    /// Distance travelled by the whole team, m.
    pub distance_m: f64,
    /// The relevant area of the scene (free floor of the relevant rooms), m².
    pub relevant_total_m2: f64,
    /// When `relevant_target` of the relevant area was first known, seconds.
    pub time_to_relevant_s: Option<f64>,
    pub relevant_target: f64,
    pub assigned_per_label: BTreeMap<RoomLabel, u32>,
    pub collisions: u32,
    /// Each robot's distance and collisions (not its trajectory): where the team's time went.
    pub per_robot: Vec<RobotOutcome>,
    pub series: Vec<MinuteSample>,
}

impl RunSummary {
    pub fn new(
        outcome: &TeamOutcome,
        strategy: &str,
        coordination: &str,
        hypothesis: &str,
        seed: u64,
    ) -> Self {
        Self {
            scene: outcome.scene.clone(),
            robots: outcome.robots,
            strategy: strategy.into(),
            coordination: coordination.into(),
            hypothesis: hypothesis.into(),
            seed,
            finish: outcome.finish,
            time_s: outcome.time_s,
            relevant_area_m2: outcome.relevant_area_m2,
            total_area_m2: outcome.explored_area_m2,
            distance_m: outcome.distance_m,
            relevant_total_m2: outcome.relevant_total_m2,
            time_to_relevant_s: outcome.time_to_relevant_s,
            relevant_target: outcome.relevant_target,
            assigned_per_label: outcome.assigned_per_label.clone(),
            collisions: outcome.collisions,
            per_robot: outcome
                .per_robot
                .iter()
                .map(|r| RobotOutcome {
                    trajectory: Vec::new(),
                    ..*r
                })
                .collect(),
            series: outcome
                .series
                .iter()
                .map(|s| MinuteSample {
                    time_s: s.time_s,
                    relevant_area_m2: s.relevant_area_m2,
                    total_area_m2: s.explored_area_m2,
                    distance_m: s.distance_m,
                    assigned_per_label: s.assigned_per_label.clone(),
                })
                .collect(),
        }
    }
}

//! The evaluation of a team: what its merged map, its reports and its pose estimates are worth
//! against the ground truth. It follows the team from outside; the team never reads it.

use super::*;
use usar_sim::RobotId;
use usar_sim::host::Evaluator;

/// The truth-side bookkeeping of one team.
pub struct TeamEvaluation {
    /// The part of the reachable area the team's merged map knows.
    coverage: CoverageCounter,
    /// The relevant area the team's merged map knows (the scene's room layer); its random
    /// stream is never drawn from.
    relevant: SemanticMap,
    /// Merges of the team's map taken in.
    merges_seen: u64,
    victims_seen: Vec<VictimSighting>,
    /// Per robot: the largest error of the team's pose estimate so far, metres.
    max_pose_error_m: Vec<f64>,
    /// Auction assignments per true room label of their target.
    assigned_per_label: BTreeMap<RoomLabel, u32>,
    relevant_target: f64,
    time_to_relevant_s: Option<f64>,
}

impl TeamEvaluation {
    /// The evaluation of a team configured by `config` on `scene`, its base station at `base`.
    pub fn new(scene: &Scene, config: &TeamConfig, base: Point2) -> Self {
        let geometry = map_geometry(scene, config.map_resolution_m);
        let x = &config.exploration;
        Self {
            coverage: CoverageCounter::new(scene, base, &geometry),
            relevant: SemanticMap::new(
                scene,
                &geometry,
                &x.hypothesis,
                x.label_errors,
                Pcg64Mcg::seed_from_u64(0),
            ),
            merges_seen: 0,
            victims_seen: Vec::new(),
            max_pose_error_m: vec![0.0; config.robots],
            assigned_per_label: RoomLabel::ALL.into_iter().map(|l| (l, 0)).collect(),
            relevant_target: config.stop_at_relevant.unwrap_or(DEFAULT_RELEVANT_TARGET),
            time_to_relevant_s: None,
        }
    }

    /// Takes in what the team did at its last step: a merge of its map (coverage, relevant
    /// area), its assignments (by true room label), its victim reports (which victims they
    /// were) and where its robots believe they are. `robots` are the team's robots in the host.
    pub fn update(&mut self, team: &mut TeamController, truth: &Evaluator<'_>, robots: &[RobotId]) {
        if team.merges() != self.merges_seen {
            self.merges_seen = team.merges();
            let base = &team.base;
            self.coverage.update_from(&base.merged, base.last_changes());
            self.relevant.update_from(&base.merged, base.last_changes());
            if self.time_to_relevant_s.is_none()
                && self.relevant.relevant_fraction() >= self.relevant_target
            {
                self.time_to_relevant_s = Some(truth.time_s());
            }
        }
        let g = *team.base.merged.geometry();
        for a in team.take_assignments() {
            let room = self.relevant.room_near(&g, a.target);
            if let Some(k) = room {
                *self
                    .assigned_per_label
                    .entry(self.relevant.rooms()[k].label)
                    .or_default() += 1;
            }
        }
        for ((a, &id), worst) in team
            .agents
            .iter()
            .zip(robots)
            .zip(&mut self.max_pose_error_m)
        {
            *worst = worst.max(a.pose.position().distance(truth.robot(id).pose.position()));
        }
        let reports = team.take_reports();
        self.record_reports(&reports, truth);
    }

    /// Scores victim reports the caller took from the team ([`TeamController::take_reports`])
    /// before [`TeamEvaluation::update`] could.
    pub fn record_reports(&mut self, reports: &[VictimReport], truth: &Evaluator<'_>) {
        for report in reports {
            if let Some(HeatTruth::Victim(id)) = truth.truth_of(report.reading)
                && !self.victims_seen.iter().any(|v| v.victim_id == id)
            {
                self.victims_seen.push(VictimSighting {
                    victim_id: id,
                    robot: report.robot,
                    time_s: report.time_s,
                });
            }
        }
    }

    /// The known fraction of the reachable area.
    pub fn coverage(&self) -> f64 {
        self.coverage.coverage()
    }

    /// Map cells of the reachable area.
    pub fn reachable_cells(&self) -> usize {
        self.coverage.reachable_cells()
    }

    /// Explored relevant area, m², and the relevant area there is.
    pub fn relevant_area_m2(&self) -> f64 {
        self.relevant.relevant_area_m2()
    }

    pub fn relevant_total_m2(&self) -> f64 {
        self.relevant.relevant_total_m2()
    }

    pub fn relevant_target(&self) -> f64 {
        self.relevant_target
    }

    pub fn time_to_relevant_s(&self) -> Option<f64> {
        self.time_to_relevant_s
    }

    /// The victims the team's reports were, first sighting of each, in order.
    pub fn victims_seen(&self) -> &[VictimSighting] {
        &self.victims_seen
    }

    pub fn max_pose_error_m(&self) -> &[f64] {
        &self.max_pose_error_m
    }

    pub fn assigned_per_label(&self) -> &BTreeMap<RoomLabel, u32> {
        &self.assigned_per_label
    }
}

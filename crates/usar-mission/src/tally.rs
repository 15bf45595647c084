//! The evaluation's tally at the end of a mission: each victim (who detected it, who confirmed
//! it), the rescuer's figures and the operator's — from ground truth, after the fact.

use crate::mission::Mission;
use crate::outcome::{OperatorFigures, RescuerFigures, VictimFigures, VictimRow};
use usar_sim::host::Evaluator;
use usar_sim::sensors::{DetectionId, HeatTruth};

/// The victim a reading saw, if any.
fn victim_of(truth: &Evaluator<'_>, reading: DetectionId) -> Option<u32> {
    match truth.truth_of(reading) {
        Some(HeatTruth::Victim(id)) => Some(id),
        _ => None,
    }
}

/// The earliest (who, when), if any; the first listed among equals.
fn earliest(events: impl IntoIterator<Item = (String, f64)>) -> Option<(String, f64)> {
    events
        .into_iter()
        .reduce(|a, b| if b.1 < a.1 { b } else { a })
}

impl Mission<'_> {
    /// Each victim of the scene: who detected it first, who confirmed it first.
    pub(crate) fn victim_rows(&self, truth: &Evaluator<'_>) -> Vec<VictimRow> {
        let eval = &self.eval;
        self.scene
            .victims
            .iter()
            .map(|v| {
                let by_team = eval
                    .victims_seen()
                    .iter()
                    .find(|s| s.victim_id == v.id)
                    .map(|s| (format!("team-{}", s.robot), s.time_s));
                let by_rescuer = self.rescuer.as_ref().and_then(|r| {
                    r.seen
                        .iter()
                        .find(|&&(id, _)| id == v.id)
                        .map(|&(_, t)| ("rescuer".to_string(), t))
                });
                let on_board = self
                    .board
                    .entries
                    .iter()
                    .filter(|e| victim_of(truth, e.report.reading) == Some(v.id))
                    .filter_map(|e| match e.confirmed {
                        Some((true, t)) => Some(("operator".to_string(), t)),
                        _ => None,
                    });
                let tagged = self.rescuer.iter().flat_map(|r| {
                    r.controller
                        .tags
                        .iter()
                        .filter(|t| victim_of(truth, t.source) == Some(v.id))
                        .map(|t| {
                            let who = if t.by_operator { "operator" } else { "rescuer" };
                            (who.to_string(), t.time_s)
                        })
                });
                let detected = earliest(by_team.into_iter().chain(by_rescuer));
                let confirmed = earliest(on_board.chain(tagged));
                VictimRow {
                    id: v.id,
                    x_m: v.position.x,
                    y_m: v.position.y,
                    detected_at_s: detected.as_ref().map(|d| d.1),
                    detected_by: detected.map(|d| d.0),
                    confirmed_at_s: confirmed.as_ref().map(|c| c.1),
                    confirmed_by: confirmed.map(|c| c.0),
                }
            })
            .collect()
    }

    /// Counts over the victims table, and the confirmations of what was no victim.
    pub(crate) fn victim_figures(
        &self,
        rows: &[VictimRow],
        truth: &Evaluator<'_>,
    ) -> VictimFigures {
        let detected = rows.iter().filter(|r| r.detected_by.is_some()).count();
        let false_on_board = self
            .board
            .entries
            .iter()
            .filter(|e| matches!(e.confirmed, Some((true, _))))
            .filter(|e| victim_of(truth, e.report.reading).is_none())
            .count();
        let false_tags = self.rescuer.as_ref().map_or(0, |r| {
            r.controller
                .tags
                .iter()
                .filter(|t| victim_of(truth, t.source).is_none())
                .count()
        });
        VictimFigures {
            total: rows.len(),
            detected,
            confirmed: rows.iter().filter(|r| r.confirmed_by.is_some()).count(),
            missed: rows.len() - detected,
            false_confirmations: false_on_board + false_tags,
        }
    }

    /// What the rescuer did, if the mission has one.
    pub(crate) fn rescuer_figures(&self, truth: &Evaluator<'_>) -> Option<RescuerFigures> {
        let r = self.rescuer.as_ref()?;
        let c = &r.controller;
        let body = truth.robot(self.host.fleet(r.fleet)[0]);
        let tags = &c.tags;
        Some(RescuerFigures {
            zone_cells: c.zone().len(),
            cells_visited: c.agent().map_or(0, |a| a.visited().filter(|&v| v).count()),
            policy_trials: r.trained_trials,
            primitives: c.log.primitives,
            possible_victims: c.agent().map_or(0, |a| a.victim_sources().count()),
            pending: r.pending(),
            tags: tags.len(),
            true_tags: tags
                .iter()
                .filter(|t| victim_of(truth, t.source).is_some())
                .count(),
            handoffs_victim: c.handoffs().0,
            handoffs_stuck: c.handoffs().1,
            waiting_s: c.log.waiting_s,
            collisions: body.collisions,
            distance_m: body.distance_m,
            finished: c.log.finished,
        })
    }

    /// What the operator did over `time_s` seconds.
    pub(crate) fn operator_figures(&self, time_s: f64) -> OperatorFigures {
        let timeline = &self.desk.timeline;
        let waits: Vec<f64> = timeline.iter().map(|h| h.answered_s - h.asked_s).collect();
        let busy = timeline
            .iter()
            .fold(0.0, |b, h| b + (h.answered_s - h.started_s));
        OperatorFigures {
            asked: self.desk.asked,
            answered: timeline.len(),
            mean_wait_s: if waits.is_empty() {
                0.0
            } else {
                waits.iter().sum::<f64>() / waits.len() as f64
            },
            max_wait_s: waits.iter().copied().fold(0.0, f64::max),
            busy_fraction: if time_s > 0.0 { busy / time_s } else { 0.0 },
        }
    }
}

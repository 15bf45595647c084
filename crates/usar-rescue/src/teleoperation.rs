//! The semi-autonomous vs teleoperated comparison (paper 000 §VII-B, Table III, Fig. 16–18):
//! every simulated participant runs the same scene twice — once as the operator of the
//! semi-autonomous robot (answering its hand-offs), once driving alone.
//!
//! In the **teleoperated mode** the participant chooses every command from the camera view
//! and the robot's map (its [`crate::operator::HandOff::drive`]) and identifies victims by
//! looking: a heat region with a human signature in the cell ahead is tagged with probability
//! `accuracy` if it is a victim, `false_positive_rate` if not. Participants get disoriented:
//! every command they give up with probability `(1 − skill) · give_up_rate`, and they stop
//! when the map shows nothing left to explore.

use crate::analysis::{MeanSd, mean_sd};
use crate::domain::{DomainConfig, RescueDomain, RescueScene};
use crate::evaluation::{EvalConfig, run_once};
use crate::exploration::ExplorationWeights;
use crate::hierarchy::action;
use crate::operator::{HandOff, OperatorProfile, SimulatedOperator, VictimDecision, VictimRequest};
use crate::perception::victim_probability;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::Serialize;
use usar_maxq::MaxqQ;
use usar_sim::CellAction;
use usar_sim::sensors::HeatTruth;
use usar_world::Cell;

/// One participant's two trials.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ParticipantResult {
    pub operator: OperatorProfile,
    pub semi_autonomous: TrialResult,
    pub teleoperated: TrialResult,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrialResult {
    pub victims_found: u32,
    pub false_identifications: u32,
    /// Percentage of the reachable cells explored.
    pub explored_percent: f64,
    pub collisions: u32,
    pub time_s: f64,
    pub handoffs: u32,
}

/// Per command, the chance a participant of skill 0 gives up (scaled by 1 − skill).
pub const GIVE_UP_RATE: f64 = 0.004;

/// Runs the study on `scene` from start pose 0.
pub fn study(
    policy: &MaxqQ,
    scene: &RescueScene,
    participants: &[OperatorProfile],
    domain: &DomainConfig,
    seed: u64,
) -> Vec<ParticipantResult> {
    let weights = ExplorationWeights::named("travel").expect("Table II case");
    let (reachable, victims) = scene.reachable(scene.start(0).map_or(Cell::new(0, 0), |s| s.0));
    let reachable_cells = reachable.iter().filter(|&&r| r).count().max(1);
    participants
        .iter()
        .enumerate()
        .map(|(k, profile)| {
            let s = seed.wrapping_add(k as u64 * 0x9E37_79B9);
            let config = EvalConfig {
                operator: profile.clone(),
                domain: domain.clone(),
                ..EvalConfig::default()
            };
            let semi = run_once(policy, scene, 0, &weights, &config, s).map(
                |(_, stats, coverage, _, _, _)| TrialResult {
                    victims_found: stats.victims_found,
                    false_identifications: stats.false_tags,
                    explored_percent: 100.0 * coverage,
                    collisions: stats.robot_collisions + stats.operator_collisions,
                    time_s: stats.time_s,
                    handoffs: stats.handoffs_stuck + stats.handoffs_victim,
                },
            );
            let tele = teleoperate(scene, profile, domain, &reachable, reachable_cells, s);
            let _ = &victims;
            ParticipantResult {
                operator: profile.clone(),
                semi_autonomous: semi.unwrap_or(TrialResult {
                    victims_found: 0,
                    false_identifications: 0,
                    explored_percent: 0.0,
                    collisions: 0,
                    time_s: 0.0,
                    handoffs: 0,
                }),
                teleoperated: tele,
            }
        })
        .collect()
}

/// One teleoperated trial.
fn teleoperate(
    scene: &RescueScene,
    profile: &OperatorProfile,
    config: &DomainConfig,
    reachable: &[bool],
    reachable_cells: usize,
    seed: u64,
) -> TrialResult {
    let start = scene.start(0).unwrap_or((Cell::new(0, 0), 0));
    let operator = SimulatedOperator::new(profile.clone(), seed ^ 0x7E1E);
    let weights = ExplorationWeights::named("equal").expect("Table II case");
    let mut d =
        RescueDomain::new(scene, start, weights, config.clone(), operator, seed).teleoperated();
    let mut rng = Pcg64Mcg::seed_from_u64(seed ^ 0x61FE);
    let mut decided: Vec<(i32, i32)> = Vec::new();
    let (mut found, mut false_ids) = (0u32, 0u32);
    let view = &scene.view;
    for _ in 0..6000 {
        // Look at the cell ahead: a warm body or object there is identified once.
        let (dc, dr) = d.agent.robot.ahead();
        let ahead = (d.agent.robot.cell.col + dc, d.agent.robot.cell.row + dr);
        if !decided.contains(&ahead) {
            let truth = scene
                .scene
                .victims
                .iter()
                .filter(|v| {
                    view.cell_of(v.position)
                        .is_some_and(|c| (c.col, c.row) == ahead)
                })
                .map(|v| (HeatTruth::Victim(v.id), v.heat_c, v.exposed_size_m2()))
                .chain(
                    scene
                        .scene
                        .heat_sources
                        .iter()
                        .filter(|h| {
                            view.cell_of(h.position)
                                .is_some_and(|c| (c.col, c.row) == ahead)
                        })
                        .map(|h| (HeatTruth::Other(h.id), h.heat_c, h.size_m2)),
                )
                .next();
            if let Some((truth, heat_c, size)) = truth {
                decided.push(ahead);
                let request = VictimRequest {
                    cell: ahead,
                    probability: victim_probability((28.0..=40.0).contains(&heat_c), size),
                    size_m2: size,
                    truth,
                };
                if d.operator.identify_victim(&request) == VictimDecision::Tag {
                    match truth {
                        HeatTruth::Victim(_) => found += 1,
                        HeatTruth::Other(_) => false_ids += 1,
                    }
                }
            }
        }
        if d.guidance().heading.is_none()
            || rng.random::<f64>() < (1.0 - profile.skill) * GIVE_UP_RATE
        {
            break;
        }
        let request = d.navigation_request();
        let command = d.operator.drive(&request);
        d.act(match command {
            CellAction::Forward => action::FORWARD,
            CellAction::Backward => action::BACKWARD,
            CellAction::RotateLeft => action::ROTATE_LEFT,
            CellAction::RotateRight => action::ROTATE_RIGHT,
        });
    }
    let visited = d.visited().zip(reachable).filter(|&(v, &r)| v && r).count();
    TrialResult {
        victims_found: found,
        false_identifications: false_ids,
        explored_percent: 100.0 * visited as f64 / reachable_cells as f64,
        collisions: d.agent.stats.robot_collisions + d.agent.stats.operator_collisions,
        time_s: d.agent.stats.time_s,
        handoffs: 0,
    }
}

/// One mode's results over the participants: mean and sd of each measure.
#[derive(Serialize)]
pub struct StudySide {
    pub victims_found: MeanSd,
    pub false_identifications: MeanSd,
    pub explored_percent: MeanSd,
    pub collisions: MeanSd,
    pub time_s: MeanSd,
}

impl StudySide {
    /// Mean and sd over the trials `pick` chooses from each participant.
    pub fn over(
        results: &[ParticipantResult],
        pick: impl Fn(&ParticipantResult) -> &TrialResult,
    ) -> Self {
        let mean = |f: &dyn Fn(&TrialResult) -> f64| {
            mean_sd(&results.iter().map(|p| f(pick(p))).collect::<Vec<_>>())
        };
        StudySide {
            victims_found: mean(&|t| f64::from(t.victims_found)),
            false_identifications: mean(&|t| f64::from(t.false_identifications)),
            explored_percent: mean(&|t| t.explored_percent),
            collisions: mean(&|t| f64::from(t.collisions)),
            time_s: mean(&|t| t.time_s),
        }
    }
}

/// The study's results: every participant, and each mode summarised (Table III).
#[derive(Serialize)]
pub struct StudySummary {
    pub participants: Vec<ParticipantResult>,
    pub semi_autonomous: StudySide,
    pub teleoperated: StudySide,
}

impl StudySummary {
    /// Summarises the participants' results of [`study`].
    pub fn new(participants: Vec<ParticipantResult>) -> Self {
        StudySummary {
            semi_autonomous: StudySide::over(&participants, |p| &p.semi_autonomous),
            teleoperated: StudySide::over(&participants, |p| &p.teleoperated),
            participants,
        }
    }
}

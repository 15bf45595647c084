//! Human control (paper 000 §IV-A-5, §VII-B): the one interface through which the robot hands
//! a task to its operator, and a simulated operator that answers it in batch runs (a person
//! will answer it in the console).
//!
//! The robot hands off in two situations: it is **stuck** (its navigation commands do not take
//! effect) — the operator drives until one of their commands succeeds — and a **victim is
//! uncertain** (0.3 ≤ p ≤ 0.7) — the operator tags or rejects it.

use crate::cell_map::MapCell;
use crate::exploration::Direction;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use usar_sim::CellAction;
use usar_sim::sensors::HeatTruth;
use usar_world::cellview::CellClass;

/// An uncertain victim shown to the operator: the thermal measurement that caused it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VictimRequest {
    pub cell: (i32, i32),
    pub probability: f64,
    pub size_m2: f64,
    /// What the camera shows. A person looks at the image; the simulated operator reads this.
    pub truth: HeatTruth,
}

/// The operator's answer about a possible victim.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VictimDecision {
    Tag,
    Reject,
}

/// What the operator sees when asked to drive: the robot's map around it and its cameras.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavigationRequest {
    pub cell: (i32, i32),
    pub heading: Direction,
    /// The robot's map of its four neighbours by [`Direction::index`].
    pub neighbours: [MapCell; 4],
    /// What the front and rear cameras show of the four neighbours (true terrain, and whether a
    /// victim lies there). A person sees it on screen; the simulated operator reads it.
    pub camera: [(CellClass, bool); 4],
    /// Where the exploration would go next, if anywhere.
    pub suggested: Option<Direction>,
}

/// The hand-off interface (paper 000 Fig. 1, HRI interface).
pub trait HandOff {
    /// Tag or reject an uncertain victim.
    fn identify_victim(&mut self, request: &VictimRequest) -> VictimDecision;
    /// The next command while the operator has the robot.
    fn drive(&mut self, request: &NavigationRequest) -> CellAction;
    /// Seconds between a hand-off request and the operator's first answer.
    fn response_delay_s(&mut self) -> f64;
    /// Seconds the operator takes per command while driving.
    fn command_time_s(&self) -> f64;
}

/// How a simulated operator behaves.
///
/// - `delay_s`: mean response time to a hand-off (uniform in ½…1½ of it);
/// - `accuracy`: probability of recognising a real victim as one;
/// - `false_positive_rate`: probability of tagging a heat source that is not a victim;
/// - `skill` (0–1): probability that a driving command is the sensible one (toward open
///   ground, away from obstacles); otherwise the command is a random one and may collide.
///   Unskilled operators also command more slowly (`command_time_s` grows as skill falls).
///
/// In a file every field may be left out (the expert's value) and unknown fields are refused.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OperatorProfile {
    pub name: String,
    pub delay_s: f64,
    pub accuracy: f64,
    pub false_positive_rate: f64,
    pub skill: f64,
}

impl Default for OperatorProfile {
    fn default() -> Self {
        Self::expert()
    }
}

impl OperatorProfile {
    /// A trained operator who never errs: the evaluation's default, so that what the runs
    /// measure is the robot.
    pub fn expert() -> Self {
        Self {
            name: "expert".into(),
            delay_s: 5.0,
            accuracy: 1.0,
            false_positive_rate: 0.0,
            skill: 1.0,
        }
    }

    /// Ten novice-to-good operators for the teleoperation study (§VII-B: "none of these
    /// participants had any previous experience"): skills 0.55–0.95, accuracies 0.75–0.98,
    /// false-positive rates 0.02–0.25, response delays 3–12 s, drawn from `seed`.
    pub fn participants(seed: u64) -> Vec<OperatorProfile> {
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        (1..=10)
            .map(|k| OperatorProfile {
                name: format!("participant-{k}"),
                delay_s: rng.random_range(3.0..=12.0),
                accuracy: rng.random_range(0.75..=0.98),
                false_positive_rate: rng.random_range(0.02..=0.25),
                skill: rng.random_range(0.55..=0.95),
            })
            .collect()
    }
}

/// A simulated operator answering hand-offs with its own random stream.
pub struct SimulatedOperator {
    pub profile: OperatorProfile,
    rng: Pcg64Mcg,
}

impl SimulatedOperator {
    pub fn new(profile: OperatorProfile, seed: u64) -> Self {
        Self {
            profile,
            rng: Pcg64Mcg::seed_from_u64(seed),
        }
    }

    /// The sensible command: toward the suggested direction if the camera shows it free; to
    /// face it if it is not (a victim or an unknown cell to look at); otherwise toward any
    /// free neighbour, preferring cells not visited.
    fn sensible(request: &NavigationRequest) -> CellAction {
        let free = |d: Direction| {
            let (class, victim) = request.camera[d.index()];
            class.is_passable_terrain(true) && !victim
        };
        let face = request
            .suggested
            .filter(|&d| !free(d) && d != request.heading);
        let want = request.suggested.filter(|&d| free(d)).or(face).or_else(|| {
            Direction::ALL
                .into_iter()
                .filter(|&d| free(d))
                .min_by_key(|d| request.neighbours[d.index()].is_visited())
        });
        let Some(want) = want else {
            return CellAction::RotateLeft;
        };
        if face == Some(want) {
            let h = request.heading.index();
            return if (want.index() + 4 - h) % 4 == 3 {
                CellAction::RotateRight
            } else {
                CellAction::RotateLeft
            };
        }
        let h = request.heading.index();
        match (want.index() + 4 - h) % 4 {
            0 => CellAction::Forward,
            2 => CellAction::Backward,
            1 => CellAction::RotateLeft,
            _ => CellAction::RotateRight,
        }
    }
}

impl HandOff for SimulatedOperator {
    fn identify_victim(&mut self, request: &VictimRequest) -> VictimDecision {
        let tag = match request.truth {
            HeatTruth::Victim(_) => self.rng.random::<f64>() < self.profile.accuracy,
            HeatTruth::Other(_) => self.rng.random::<f64>() < self.profile.false_positive_rate,
        };
        if tag {
            VictimDecision::Tag
        } else {
            VictimDecision::Reject
        }
    }

    fn drive(&mut self, request: &NavigationRequest) -> CellAction {
        if self.rng.random::<f64>() < self.profile.skill {
            Self::sensible(request)
        } else {
            CellAction::ALL[self.rng.random_range(0..4)]
        }
    }

    fn response_delay_s(&mut self) -> f64 {
        self.profile.delay_s * self.rng.random_range(0.5..=1.5)
    }

    fn command_time_s(&self) -> f64 {
        // 1.5 s for a perfect driver, 3 s at skill 0.5.
        1.5 / self.profile.skill.clamp(0.2, 1.0)
    }
}

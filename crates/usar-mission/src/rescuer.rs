//! Paper 000's robot in the mission: its policy (a file, or trained at the start), its
//! oracles, its controller, and what it did (its zone is [`crate::zone`]'s).

use crate::{MissionError, RescuerPart};
use std::sync::Arc;
use usar_maxq::MaxqQ;
use usar_rescue::controller::RescueController;
use usar_rescue::exploration::ExplorationWeights;
use usar_rescue::policy::PolicyFile;
use usar_rescue::training::{TrainConfig, train};
use usar_rescue::{DomainConfig, VictimMark};
use usar_sim::host::{FleetId, Oracles};
use usar_sim::sensors::{DetectionId, HeatTruth};
use usar_world::{GridGeometry, Point2};

/// The rescuer on the host, and what the evaluation keeps of it.
pub(crate) struct Rescuer {
    pub fleet: FleetId,
    pub controller: RescueController,
    /// The policy's training trials (0: read from a file).
    pub trained_trials: u32,
    /// Its possible victims already scored, and the true victims among them with when they
    /// were first seen.
    pub sightings_seen: usize,
    pub seen: Vec<(u32, f64)>,
    /// The cell centres it believed it stood on, in order.
    pub trajectory: Vec<Point2>,
}

pub(crate) fn bad(field: &str, message: String) -> MissionError {
    MissionError::Config {
        field: format!("rescuer.{field}"),
        message,
    }
}

/// The rescuer's learned policy: read from `part.policy`, or trained for `part.train_trials`
/// trials with `seed`. Returns it and the trials trained.
pub(crate) fn policy(part: &RescuerPart, seed: u64) -> Result<(Arc<MaxqQ>, u32), MissionError> {
    if !part.policy.is_empty() {
        let file = PolicyFile::load(std::path::Path::new(&part.policy))
            .map_err(|e| bad("policy", e.to_string()))?;
        return Ok((Arc::new(file.learner), 0));
    }
    usar_rescue::training::check_trials(part.train_trials)
        .map_err(|e| bad("train_trials", e.problem()))?;
    let config = TrainConfig {
        seed,
        trials: part.train_trials,
        flat: false,
        weights: weights(part)?,
        ..TrainConfig::default()
    };
    Ok((Arc::new(train(&config, |_| {}).0), part.train_trials))
}

/// The Table II case named by `part.weights`.
pub(crate) fn weights(part: &RescuerPart) -> Result<ExplorationWeights, MissionError> {
    ExplorationWeights::named(&part.weights).ok_or_else(|| {
        bad(
            "weights",
            format!("found `{}`, expected a Table II case name", part.weights),
        )
    })
}

impl Rescuer {
    pub(crate) fn new(fleet: FleetId, controller: RescueController, trained_trials: u32) -> Self {
        Self {
            fleet,
            controller,
            trained_trials,
            sightings_seen: 0,
            seen: Vec::new(),
            trajectory: Vec::new(),
        }
    }

    /// Scores the possible victims it met since the last call (`truth` resolves their
    /// readings) and extends its believed trajectory.
    pub(crate) fn follow(&mut self, now_s: f64, truth: impl Fn(DetectionId) -> Option<HeatTruth>) {
        let Some(agent) = self.controller.agent() else {
            return;
        };
        for (source, _) in agent.victim_sources().skip(self.sightings_seen) {
            self.sightings_seen += 1;
            if let Some(HeatTruth::Victim(id)) = truth(source)
                && !self.seen.iter().any(|&(v, _)| v == id)
            {
                self.seen.push((id, now_s));
            }
        }
        let p = self.controller.zone().cell_center(agent.robot.cell);
        if self.trajectory.last() != Some(&p) {
            self.trajectory.push(p);
        }
    }

    /// Its possible victims still undecided.
    pub(crate) fn pending(&self) -> usize {
        self.controller.agent().map_or(0, |a| {
            a.victim_sources()
                .filter(|(_, m)| *m == VictimMark::Pending)
                .count()
        })
    }
}

/// The oracles `part` gives the rescuer: its true pose (paper 000's robot knows its cell) or
/// none.
pub(crate) fn oracles(part: &RescuerPart) -> Result<Oracles, MissionError> {
    let localization = match part.localization.as_str() {
        "true" => true,
        "estimated" => false,
        other => {
            return Err(bad(
                "localization",
                format!("found `{other}`, expected true or estimated"),
            ));
        }
    };
    Ok(Oracles { localization })
}

/// The controller for `part` on `zone`.
pub(crate) fn controller(
    part: &RescuerPart,
    zone: GridGeometry,
    policy: Arc<MaxqQ>,
) -> Result<RescueController, MissionError> {
    Ok(RescueController::new(
        zone,
        policy,
        weights(part)?,
        DomainConfig::default(),
        part.max_primitives,
    ))
}

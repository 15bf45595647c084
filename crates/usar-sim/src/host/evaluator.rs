//! Ground truth for evaluation: metrics, reports, pictures. Controllers never receive one.

use super::RadioStats;
use crate::sensors::{DetectionId, HeatTruth};
use crate::simulation::{RobotId, SimRobot, Simulation};
use usar_world::Scene;

/// The truth of a host at one moment.
pub struct Evaluator<'a> {
    sim: &'a Simulation,
    detections: &'a [HeatTruth],
    radio: RadioStats,
}

impl<'a> Evaluator<'a> {
    pub(super) fn new(sim: &'a Simulation, detections: &'a [HeatTruth], radio: RadioStats) -> Self {
        Self {
            sim,
            detections,
            radio,
        }
    }

    /// What the radio carried and lost so far.
    pub fn radio(&self) -> RadioStats {
        self.radio
    }

    pub fn scene(&self) -> &'a Scene {
        self.sim.scene()
    }

    pub fn time_s(&self) -> f64 {
        self.sim.time_s()
    }

    /// Every robot's true state (pose, distance driven, collisions, failure).
    pub fn robots(&self) -> &'a [SimRobot] {
        self.sim.robots()
    }

    pub fn robot(&self, id: RobotId) -> &'a SimRobot {
        self.sim.robot(id)
    }

    /// Which source caused a thermal reading.
    pub fn truth_of(&self, reading: DetectionId) -> Option<HeatTruth> {
        self.detections.get(reading.0 as usize).copied()
    }

    /// The simulation itself (for renderers that draw the whole truth).
    pub fn simulation(&self) -> &'a Simulation {
        self.sim
    }
}

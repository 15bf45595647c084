//! The host: one [`Simulation`] holding every robot of every controller, stepped together.
//!
//! A controller drives a *fleet* — the robots it was given — and sees them only through a
//! [`FleetIo`]: their sensor readings (laser, tilted laser, depth array, thermal camera,
//! infrared, odometry, attitude, contact), a radio, and the velocity commands it sets. It cannot
//! reach the [`Scene`]: what a paper assumes a robot knows but a real one does not comes
//! through a named oracle ([`Oracles`]), off unless asked for. Ground truth is for evaluation
//! only, through an [`Evaluator`] that controllers never receive.
//!
//! ```
//! use std::sync::Arc;
//! use usar_sim::host::{Controller, FleetIo, Host, Oracles};
//! use usar_sim::{RobotSpec, SimConfig, Velocity};
//! use usar_world::{GridGeometry, Point2, Pose2, Scene};
//!
//! /// Drives forward until the bumper touches something.
//! struct Forward;
//! impl Controller for Forward {
//!     fn step(&mut self, io: &mut FleetIo<'_>) {
//!         for k in 0..io.len() {
//!             let v = if io.contact(k) { 0.0 } else { 0.5 };
//!             io.command(k, Velocity { linear_mps: v, angular_radps: 0.0 });
//!         }
//!     }
//! }
//!
//! let scene = Arc::new(Scene::empty("hall", GridGeometry::new(100, 100, 0.1, Point2::new(0.0, 0.0))));
//! let mut host = Host::new(scene, SimConfig::default(), 7, Oracles::default());
//! let fleet = host.add_fleet(&[(RobotSpec::wheeled(), Pose2::new(5.0, 5.0, 0.0))]).unwrap();
//! let mut forward = Forward;
//! for _ in 0..10 {
//!     host.step(&mut [(fleet, &mut forward as &mut dyn Controller)]);
//! }
//! let truth = host.evaluator();
//! assert!((truth.robot(host.fleet(fleet)[0]).pose.x - 5.5).abs() < 1e-9);
//! ```

mod evaluator;
mod io;
mod radio;

pub use self::evaluator::Evaluator;
pub use self::io::FleetIo;
pub use self::radio::{Endpoint, INBOX_CAP, Message, Radio, RadioSpec, RadioStats};

use crate::robot::RobotSpec;
use crate::sensors::HeatTruth;
use crate::simulation::{PlacementError, RobotId, SimConfig, Simulation, Velocity};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use usar_world::{Pose2, Scene};

/// Knowledge a paper assumes its robots have and a real robot lacks, each given to controllers
/// only when switched on and named where it is used.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Oracles {
    /// The robots' true poses (`--localization true`): [`FleetIo::true_pose`] answers, and
    /// readings are stamped with the true pose instead of the odometry estimate.
    #[serde(default)]
    pub localization: bool,
}

/// The robots one controller drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FleetId(pub usize);

/// A controller: decides its robots' commands from what they sense.
pub trait Controller {
    /// Called once per simulation step, before the world moves: read the fleet's sensors,
    /// set its commands (a robot given none stops).
    fn step(&mut self, io: &mut FleetIo<'_>);
}

/// The world every controller runs in.
pub struct Host {
    sim: Simulation,
    /// Each fleet's robots and the oracles its controller gets.
    fleets: Vec<(Vec<RobotId>, Oracles)>,
    /// Robots that stop for good at a time: (time, robot), in the order scheduled.
    failures: Vec<(f64, RobotId)>,
    commands: Vec<Velocity>,
    oracles: Oracles,
    /// The source of each thermal reading handed out, by [`crate::sensors::DetectionId`].
    detections: Vec<HeatTruth>,
    radio: Radio,
    /// The fleet whose controller runs the base station (its radio end).
    base_owner: Option<FleetId>,
}

impl Host {
    /// A host on `scene`, its noise and radio streams derived from `seed`.
    pub fn new(scene: Arc<Scene>, config: SimConfig, seed: u64, oracles: Oracles) -> Self {
        let radio = Radio::new(RadioSpec::default(), seed);
        Self {
            sim: Simulation::new(scene, config, seed),
            fleets: Vec::new(),
            failures: Vec::new(),
            commands: Vec::new(),
            oracles,
            detections: Vec::new(),
            radio,
            base_owner: None,
        }
    }

    /// The controller of `fleet` runs the base station: it alone sends and receives as
    /// [`Endpoint::Base`].
    pub fn set_base_owner(&mut self, fleet: FleetId) {
        self.base_owner = Some(fleet);
    }

    /// The radio between robots and the base station (unlimited unless set).
    pub fn with_radio(mut self, spec: RadioSpec) -> Self {
        self.radio.set_spec(spec);
        self
    }

    /// Places a fleet's robots; their ids follow those of the fleets added before. Its
    /// controller gets the host's oracles.
    pub fn add_fleet(&mut self, robots: &[(RobotSpec, Pose2)]) -> Result<FleetId, PlacementError> {
        self.add_fleet_with(robots, self.oracles)
    }

    /// [`Host::add_fleet`] with oracles of its own for this fleet's controller (in a mission
    /// one controller may assume what another does not).
    pub fn add_fleet_with(
        &mut self,
        robots: &[(RobotSpec, Pose2)],
        oracles: Oracles,
    ) -> Result<FleetId, PlacementError> {
        let mut ids = Vec::with_capacity(robots.len());
        for (spec, pose) in robots {
            ids.push(self.sim.add_robot(spec.clone(), *pose)?);
        }
        self.commands
            .resize(self.sim.robots().len(), Velocity::default());
        self.fleets.push((ids, oracles));
        Ok(FleetId(self.fleets.len() - 1))
    }

    /// The simulation ids of a fleet's robots, in the order they were given.
    pub fn fleet(&self, fleet: FleetId) -> &[RobotId] {
        &self.fleets[fleet.0].0
    }

    /// Robot `robot` stops for good (moves and senses no more) once the clock reaches `at_s`.
    pub fn schedule_failure(&mut self, robot: RobotId, at_s: f64) {
        self.failures.push((at_s, robot));
    }

    /// The oracles fleets get unless added with their own.
    pub fn oracles(&self) -> Oracles {
        self.oracles
    }

    pub fn time_s(&self) -> f64 {
        self.sim.time_s()
    }

    pub fn dt_s(&self) -> f64 {
        self.sim.config().dt_s
    }

    /// Ground truth, for metrics, reports and pictures.
    pub fn evaluator(&self) -> Evaluator<'_> {
        Evaluator::new(&self.sim, &self.detections, self.radio.stats())
    }

    /// One step: every controller decides for its fleet, then the world moves.
    pub fn step(&mut self, controllers: &mut [(FleetId, &mut dyn Controller)]) {
        for (fleet, controller) in controllers.iter_mut() {
            self.decide(*fleet, &mut **controller);
        }
        self.advance();
    }

    /// Lets `controller` set the commands of `fleet` for the coming step (failures due by now
    /// happen first, so a controller never drives a robot that has failed).
    pub fn decide(&mut self, fleet: FleetId, controller: &mut dyn Controller) {
        self.apply_failures();
        let (robots, oracles) = &self.fleets[fleet.0];
        let mut io = FleetIo::new(
            &mut self.sim,
            robots,
            &mut self.commands,
            &mut self.detections,
            &mut self.radio,
            *oracles,
            self.base_owner == Some(fleet),
        );
        controller.step(&mut io);
    }

    /// The command robot `robot` got for the coming step.
    pub fn command(&self, robot: RobotId) -> Velocity {
        self.commands[robot.0]
    }

    /// Replaces a robot's command for the coming step (teleoperation by a person).
    pub fn override_command(&mut self, robot: RobotId, command: Velocity) {
        self.commands[robot.0] = command;
    }

    /// Moves the world one step with the commands set, then clears them.
    pub fn advance(&mut self) {
        self.apply_failures();
        self.sim.step(&self.commands);
        self.commands.fill(Velocity::default());
        self.radio.tick();
    }

    fn apply_failures(&mut self) {
        let now = self.sim.time_s();
        for &(at_s, id) in &self.failures {
            if at_s <= now && !self.sim.robot(id).failed {
                self.sim.fail_robot(id);
            }
        }
    }
}

#[cfg(test)]
mod tests;

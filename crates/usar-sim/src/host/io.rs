//! What a controller sees of its robots and how it drives them: the only door between a
//! controller and the world. Robot `k` is the fleet's k-th robot.

use super::Oracles;
use super::radio::{Endpoint, Message, Radio};
use crate::robot::RobotSpec;
use crate::sensors::{
    Attitude, DepthImage, DetectionId, HeatTruth, InfraredReading, LaserScan, Odometry,
    ThermalReading, TiltedScan,
};
use crate::simulation::{RobotId, Simulation, Velocity};
use usar_world::{Point2, Pose2};

/// One controller's view of its fleet for one step. It gives readings, commands and the radio,
/// and no path to the scene or the simulation — neither of these compiles:
///
/// ```compile_fail
/// fn peek(io: &usar_sim::host::FleetIo<'_>) -> usize {
///     io.sim.scene().victims.len()
/// }
/// ```
///
/// ```compile_fail
/// fn truth(io: &usar_sim::host::FleetIo<'_>) -> usar_world::Pose2 {
///     io.sim.robot(io.id(0)).pose
/// }
/// ```
pub struct FleetIo<'a> {
    sim: &'a mut Simulation,
    robots: &'a [RobotId],
    commands: &'a mut [Velocity],
    detections: &'a mut Vec<HeatTruth>,
    radio: &'a mut Radio,
    oracles: Oracles,
    /// Whether this controller runs the base station.
    owns_base: bool,
}

impl<'a> FleetIo<'a> {
    pub(super) fn new(
        sim: &'a mut Simulation,
        robots: &'a [RobotId],
        commands: &'a mut [Velocity],
        detections: &'a mut Vec<HeatTruth>,
        radio: &'a mut Radio,
        oracles: Oracles,
        owns_base: bool,
    ) -> Self {
        Self {
            sim,
            robots,
            commands,
            detections,
            radio,
            oracles,
            owns_base,
        }
    }

    /// How many robots the fleet has.
    pub fn len(&self) -> usize {
        self.robots.len()
    }

    pub fn is_empty(&self) -> bool {
        self.robots.is_empty()
    }

    /// The robot's id in the host (its name on the radio).
    pub fn id(&self, k: usize) -> RobotId {
        self.robots[k]
    }

    /// The mission clock, seconds.
    pub fn time_s(&self) -> f64 {
        self.sim.time_s()
    }

    /// The length of a step, seconds.
    pub fn dt_s(&self) -> f64 {
        self.sim.config().dt_s
    }

    /// The robot's model: size, abilities, speeds, sensor mounts.
    pub fn spec(&self, k: usize) -> &RobotSpec {
        &self.sim.robot(self.robots[k]).spec
    }

    /// Whether the robot still answers (a failed robot neither moves, senses nor talks).
    pub fn alive(&self, k: usize) -> bool {
        !self.sim.robot(self.robots[k]).failed
    }

    /// Dead reckoning from the wheels or tracks.
    pub fn odometry(&self, k: usize) -> Odometry {
        self.sim.robot(self.robots[k]).odometry.clone()
    }

    /// Whether the robot's last motion was stopped by something (its bumper).
    pub fn contact(&self, k: usize) -> bool {
        self.sim.robot(self.robots[k]).in_contact()
    }

    /// The velocity the robot's last step achieved, as its encoders count it: exact (the drift
    /// of dead reckoning is in [`FleetIo::odometry`]).
    pub fn achieved(&self, k: usize) -> Velocity {
        self.sim.robot(self.robots[k]).last_motion()
    }

    /// The localization oracle ([`Oracles::localization`]): the robot's true pose, or `None`
    /// when the oracle is off.
    pub fn true_pose(&self, k: usize) -> Option<Pose2> {
        self.oracles
            .localization
            .then(|| self.sim.robot(self.robots[k]).pose)
    }

    /// The pose readings are stamped with: the true pose under the localization oracle,
    /// the odometry estimate otherwise.
    fn stamp(&self, k: usize) -> Pose2 {
        let r = self.sim.robot(self.robots[k]);
        if self.oracles.localization {
            r.pose
        } else {
            r.odometry.estimate
        }
    }

    /// A 2-D laser scan into `scan` (its buffer reused), stamped (see [`FleetIo::true_pose`]);
    /// a failed robot's scan has no beams.
    pub fn laser(&mut self, k: usize, scan: &mut LaserScan) {
        if self.alive(k) {
            self.sim.scan_laser(self.robots[k], scan);
        } else {
            scan.ranges_m.clear();
        }
        scan.pose = self.stamp(k);
    }

    /// The laser tilted down at the floor ahead, stamped.
    pub fn tilted_laser(&mut self, k: usize) -> TiltedScan {
        let mut scan = self.sim.read_tilted_laser(self.robots[k]);
        scan.pose = self.stamp(k);
        scan
    }

    /// The front depth array, stamped.
    pub fn depth(&mut self, k: usize) -> DepthImage {
        let mut image = self.sim.read_depth(self.robots[k]);
        image.pose = self.stamp(k);
        image
    }

    pub fn infrared(&mut self, k: usize) -> InfraredReading {
        self.sim.read_infrared(self.robots[k])
    }

    pub fn attitude(&mut self, k: usize) -> Attitude {
        self.sim.read_attitude(self.robots[k])
    }

    /// The thermal camera's warm regions, by bearing (none from a failed robot). Which
    /// source caused each is kept by the host for the evaluator, under the reading's opaque
    /// number.
    pub fn thermal(&mut self, k: usize) -> Vec<ThermalReading> {
        if !self.alive(k) {
            return Vec::new();
        }
        let mut seen = self.sim.read_thermal(self.robots[k]);
        // The simulator lists victims first: in bearing order the list says nothing of that.
        seen.sort_by(|a, b| a.bearing_rad.total_cmp(&b.bearing_rad));
        seen.into_iter()
            .map(|d| {
                let id = DetectionId(self.detections.len() as u64);
                self.detections.push(d.truth);
                ThermalReading {
                    id,
                    bearing_rad: d.bearing_rad,
                    range_m: d.range_m,
                    temperature_c: d.temperature_c,
                    human_signature: d.human_signature,
                    size_m2: d.size_m2,
                }
            })
            .collect()
    }

    /// Sets the robot's velocity for the coming step.
    pub fn command(&mut self, k: usize, v: Velocity) {
        self.commands[self.robots[k].0] = v;
    }

    fn place(&self, end: Endpoint) -> Option<Point2> {
        match end {
            Endpoint::Robot(id) => self.sim.robots().get(id.0).map(|r| r.pose.position()),
            Endpoint::Base => self.radio.spec().base,
        }
    }

    /// Whether this controller may speak and listen as `end`: one of its own robots that still
    /// answers, or the base station when it runs it.
    fn speaks_as(&self, end: Endpoint) -> bool {
        match end {
            Endpoint::Robot(id) => self
                .robots
                .iter()
                .position(|&r| r == id)
                .is_some_and(|k| self.alive(k)),
            Endpoint::Base => self.owns_base,
        }
    }

    /// Sends `payload` on `topic` from `from` (one of the fleet's robots, or the base station
    /// when the controller runs it) to `to`; it arrives at the next step, if the radio carries
    /// it. Returns `false`, sending nothing, when `from` is not this controller's to speak as.
    pub fn send(&mut self, from: Endpoint, to: Endpoint, topic: &str, payload: Vec<u8>) -> bool {
        if !self.speaks_as(from) {
            return false;
        }
        let (from_at, to_at) = (self.place(from), self.place(to));
        let message = Message {
            from,
            to,
            topic: topic.to_string(),
            payload,
            sent_s: self.sim.time_s(),
        };
        self.radio.send(message, from_at, to_at);
        true
    }

    /// Whether robot `k`'s radio reaches the base station now (range, and one draw of the
    /// loss): a map upload or a bid gets through.
    pub fn link_to_base(&mut self, k: usize) -> bool {
        let at = self.sim.robot(self.robots[k]).pose.position();
        // Drawn for a failed robot too, so that one robot's failure leaves the others' draws.
        let link = self.radio.link_to_base(at);
        link && self.alive(k)
    }

    /// The messages on `topic` that have arrived for `to` (one of the fleet's robots, or the
    /// base station when the controller runs it), oldest first; none for another's end.
    pub fn receive(&mut self, to: Endpoint, topic: &str) -> Vec<Message> {
        if !self.speaks_as(to) {
            return Vec::new();
        }
        self.radio.receive(to, topic)
    }
}

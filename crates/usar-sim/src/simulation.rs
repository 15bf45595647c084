//! The time-stepped world: several robots moving by unicycle kinematics (v, ω) in one scene.
//! Motions that would put a footprint on a blocked cell or on another robot are stopped and
//! counted as collisions; robots never pass through walls.

use crate::robot::RobotSpec;
use crate::sensors::{
    Attitude, Body, DepthImage, HeatDetection, InfraredReading, LaserModel, LaserScan, Odometry,
    SensingWorld, TiltedScan,
};
use crate::traversability::{compute_blocked, footprint_cells};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use usar_world::{Grid, Pose2, Scene};

/// A robot's noise: the thermal camera draws from a stream of its own, every other sensor and
/// the odometry from the robot's main stream (both derived from the robot's seed). The thermal
/// camera is the one sensor that sees the victim list: a victim more or less in view must not
/// shift the noise of the laser a controller maps with.
///
/// One stream per sensor would be cleaner still; measured, it moves the BTM builder's result
/// on the real Willow Garage floor (a corridor junction missed) and its node spread over five
/// seeds on the course (0.64 m, from 0.5 m) — the builder's sensitivity to its noise
/// realisation that issue 23 is about.
#[derive(Clone, Debug)]
struct NoiseStreams {
    main: Pcg64Mcg,
    thermal: Pcg64Mcg,
}

impl NoiseStreams {
    fn new(robot_seed: u64) -> Self {
        Self {
            main: Pcg64Mcg::seed_from_u64(robot_seed),
            thermal: Pcg64Mcg::seed_from_u64(derive_seed(robot_seed, THERMAL_STREAM)),
        }
    }
}

/// The thermal camera's stream, derived from the robot's seed.
const THERMAL_STREAM: u64 = 4;

/// Index of a robot in its simulation, in the order robots were added.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct RobotId(pub usize);

/// A velocity command for a unicycle robot.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Velocity {
    pub linear_mps: f64,
    pub angular_radps: f64,
}

/// The opposite command: one step of it undoes one step of the original (see
/// [`SimRobot::last_motion`]).
impl std::ops::Neg for Velocity {
    type Output = Velocity;

    fn neg(self) -> Velocity {
        Velocity {
            linear_mps: -self.linear_mps,
            angular_radps: -self.angular_radps,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    /// Length of one time step, seconds.
    pub dt_s: f64,
    /// Whether robots block each other (their footprints may not overlap).
    pub robots_collide: bool,
    /// Whether robots show in each other's 2-D laser scans (their footprints, as rectangles
    /// taller than the lasers are mounted).
    #[serde(default)]
    pub robots_in_lasers: bool,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            dt_s: 0.1,
            robots_collide: true,
            robots_in_lasers: false,
        }
    }
}

/// A robot in the simulation: its true state, its own noise streams and odometry.
#[derive(Clone, Debug)]
pub struct SimRobot {
    pub id: RobotId,
    pub spec: Arc<RobotSpec>,
    /// True pose (ground truth).
    pub pose: Pose2,
    /// Collision events: each time a motion is stopped after one that was not.
    pub collisions: u32,
    /// The collision events where another robot stopped the motion.
    pub robot_contacts: u32,
    /// Distance actually travelled, metres.
    pub distance_m: f64,
    /// A failed robot no longer moves or senses.
    pub failed: bool,
    pub odometry: Odometry,
    in_contact: bool,
    /// The velocity its last step actually achieved (the command, scaled down when an obstacle
    /// stopped it part-way): driving the negation for one step retraces the motion exactly.
    last_motion: Velocity,
    noise: NoiseStreams,
    blocked: Arc<Grid<bool>>,
    laser: Arc<LaserModel>,
    /// Its circumscribed radius (the broad test of robot-robot contact).
    radius_m: f64,
}

impl SimRobot {
    /// The ground truth of where this robot can stand (`true` = blocked).
    pub fn blocked(&self) -> &Grid<bool> {
        &self.blocked
    }

    /// Whether its last commanded motion was stopped by an obstacle or another robot (what a
    /// bumper would tell).
    pub fn in_contact(&self) -> bool {
        self.in_contact
    }

    /// The velocity its last step actually achieved (zero when it did not move).
    pub fn last_motion(&self) -> Velocity {
        self.last_motion
    }
}

/// Why a robot could not be added.
#[derive(Debug, thiserror::Error)]
pub enum PlacementError {
    /// The start pose puts the footprint on a blocked cell or another robot.
    #[error("robot {name} cannot start at ({x:.2}, {y:.2}): its footprint is not free there")]
    NotFree { name: String, x: f64, y: f64 },
    /// The robot spec is physically implausible.
    #[error("robot {name}: {message}")]
    BadSpec { name: String, message: String },
}

/// The simulator.
pub struct Simulation {
    scene: Arc<Scene>,
    world: Arc<SensingWorld>,
    robots: Vec<SimRobot>,
    config: SimConfig,
    seed: u64,
    time_s: f64,
    blocked_cache: Vec<(RobotSpec, Arc<Grid<bool>>)>,
    /// Scratch: the other robots as laser bodies.
    bodies: Vec<Body>,
}

/// SplitMix64: a well-mixed 64-bit value from a seed and a stream number, so that each robot's
/// noise stream is independent of the others and of the number of robots.
pub fn derive_seed(seed: u64, stream: u64) -> u64 {
    let mut z = seed ^ stream.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Simulation {
    pub fn new(scene: Arc<Scene>, config: SimConfig, seed: u64) -> Self {
        let world = Arc::new(SensingWorld::new(&scene));
        Self {
            scene,
            world,
            robots: Vec::new(),
            config,
            seed,
            time_s: 0.0,
            blocked_cache: Vec::new(),
            bodies: Vec::new(),
        }
    }

    pub fn scene(&self) -> &Arc<Scene> {
        &self.scene
    }

    pub fn sensing_world(&self) -> &Arc<SensingWorld> {
        &self.world
    }

    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    pub fn robots(&self) -> &[SimRobot] {
        &self.robots
    }

    pub fn robot(&self, id: RobotId) -> &SimRobot {
        &self.robots[id.0]
    }

    /// The ground-truth blocked grid for a robot spec (computed once per distinct spec).
    pub fn blocked_for(&mut self, spec: &RobotSpec) -> Arc<Grid<bool>> {
        let key = |s: &RobotSpec| (s.length_m, s.max_inclination_rad, s.max_step_m);
        if let Some((_, g)) = self.blocked_cache.iter().find(|(s, _)| key(s) == key(spec)) {
            return g.clone();
        }
        let g = Arc::new(compute_blocked(&self.scene, spec));
        self.blocked_cache.push((spec.clone(), g.clone()));
        g
    }

    /// Adds a robot at `pose`. Its noise stream is derived from the simulation seed and its id.
    pub fn add_robot(&mut self, spec: RobotSpec, pose: Pose2) -> Result<RobotId, PlacementError> {
        spec.validate().map_err(|e| PlacementError::BadSpec {
            name: spec.name.clone(),
            message: e.to_string(),
        })?;
        let id = RobotId(self.robots.len());
        let blocked = self.blocked_for(&spec);
        let laser = Arc::new(LaserModel::new(spec.laser.clone()));
        let radius_m = spec.circumscribed_radius_m();
        let robot = SimRobot {
            id,
            spec: Arc::new(spec),
            pose,
            collisions: 0,
            robot_contacts: 0,
            distance_m: 0.0,
            failed: false,
            odometry: Odometry::new(pose),
            in_contact: false,
            last_motion: Velocity::default(),
            noise: NoiseStreams::new(derive_seed(self.seed, id.0 as u64)),
            blocked,
            laser,
            radius_m,
        };
        if !self.pose_is_free(&robot, pose) {
            return Err(PlacementError::NotFree {
                name: robot.spec.name.to_string(),
                x: pose.x,
                y: pose.y,
            });
        }
        self.robots.push(robot);
        Ok(id)
    }

    /// Marks a robot as failed: it stops for good.
    pub fn fail_robot(&mut self, id: RobotId) {
        self.robots[id.0].failed = true;
        self.robots[id.0].last_motion = Velocity::default();
    }

    /// Floor height under a point (0 outside the grid or on an obstacle).
    pub fn floor_z(&self, p: usar_world::Point2) -> f64 {
        match self.world.height_at(p) {
            Some(h) if h.is_finite() => f64::from(h),
            _ => 0.0,
        }
    }

    fn overlaps_a_robot(&self, robot: &SimRobot, pose: Pose2) -> bool {
        self.config.robots_collide
            && self
                .robots
                .iter()
                .any(|o| o.id != robot.id && rectangles_overlap((pose, robot), (o.pose, o)))
    }

    fn pose_is_free(&self, robot: &SimRobot, pose: Pose2) -> bool {
        let g = self.scene.geometry();
        let inside = footprint_cells(g, pose, robot.spec.length_m, robot.spec.width_m, |c| {
            robot.blocked.get(c).is_some_and(|&b| !b)
        });
        inside && !self.overlaps_a_robot(robot, pose)
    }

    /// Advances time by one step; `commands[i]` drives robot i (missing commands mean stop).
    /// Robots move in id order; each motion is split into sub-steps of at most half a cell (at
    /// the footprint's corners when turning) and stops at the first blocked sub-step.
    pub fn step(&mut self, commands: &[Velocity]) {
        let dt = self.config.dt_s;
        let half_cell = self.scene.geometry().resolution_m / 2.0;
        for i in 0..self.robots.len() {
            if self.robots[i].failed {
                continue;
            }
            let cmd = commands.get(i).copied().unwrap_or_default();
            let spec = self.robots[i].spec.clone();
            let v = cmd
                .linear_mps
                .clamp(-spec.max_linear_mps, spec.max_linear_mps);
            let w = cmd
                .angular_radps
                .clamp(-spec.max_angular_radps, spec.max_angular_radps);
            let (ds, dth) = (v * dt, w * dt);
            let sweep = ds.abs().max(dth.abs() * spec.circumscribed_radius_m());
            let n = ((sweep / half_cell).ceil() as usize).max(1);
            let (ds_n, dth_n) = (ds / n as f64, dth / n as f64);
            let mut stopped = false;
            let mut by_robot = false;
            let mut done = 0;
            for _ in 0..n {
                let p = self.robots[i].pose;
                let mid = p.theta + dth_n / 2.0;
                let next = Pose2::new(
                    p.x + ds_n * mid.cos(),
                    p.y + ds_n * mid.sin(),
                    usar_world::normalize_angle(p.theta + dth_n),
                );
                if !self.pose_is_free(&self.robots[i], next) {
                    stopped = true;
                    by_robot = self.overlaps_a_robot(&self.robots[i], next);
                    break;
                }
                let r = &mut self.robots[i];
                r.pose = next;
                r.distance_m += ds_n.abs();
                let noise = r.spec.noise.clone();
                r.odometry.integrate(ds_n, dth_n, &noise, &mut r.noise.main);
                done += 1;
            }
            let r = &mut self.robots[i];
            let achieved = done as f64 / n as f64;
            r.last_motion = Velocity {
                linear_mps: v * achieved,
                angular_radps: w * achieved,
            };
            if stopped && !r.in_contact {
                r.collisions += 1;
                r.robot_contacts += u32::from(by_robot);
            }
            r.in_contact = stopped;
        }
        self.time_s += dt;
    }

    /// Moves a robot to `pose` if its footprint is free there (teleport; used by cell-level
    /// controllers and tests). Returns whether it moved.
    pub fn try_place(&mut self, id: RobotId, pose: Pose2) -> bool {
        let free = self.pose_is_free(&self.robots[id.0], pose);
        if free {
            let r = &mut self.robots[id.0];
            r.distance_m += r.pose.position().distance(pose.position());
            r.pose = pose;
        }
        free
    }

    /// Takes a 2-D laser scan from robot `id` into `scan` (buffer reused).
    pub fn scan_laser(&mut self, id: RobotId, scan: &mut LaserScan) {
        let floor = self.floor_z(self.robots[id.0].pose.position());
        // The other robots as bodies, in a buffer kept between scans.
        let mut bodies = std::mem::take(&mut self.bodies);
        bodies.clear();
        if self.config.robots_in_lasers {
            bodies.extend(self.robots.iter().filter(|o| o.id != id).map(|o| Body {
                pose: o.pose,
                half_length_m: o.spec.length_m / 2.0,
                half_width_m: o.spec.width_m / 2.0,
            }));
        }
        let r = &mut self.robots[id.0];
        r.laser
            .scan_among(&self.world, &bodies, r.pose, floor, &mut r.noise.main, scan);
        self.bodies = bodies;
    }

    pub fn read_thermal(&mut self, id: RobotId) -> Vec<HeatDetection> {
        let floor = self.floor_z(self.robots[id.0].pose.position());
        let r = &mut self.robots[id.0];
        crate::sensors::read_thermal(
            &r.spec.thermal,
            &self.scene,
            &self.world,
            r.pose,
            floor,
            &mut r.noise.thermal,
        )
    }

    pub fn read_depth(&mut self, id: RobotId) -> DepthImage {
        let floor = self.floor_z(self.robots[id.0].pose.position());
        let r = &mut self.robots[id.0];
        crate::sensors::read_depth(&r.spec.depth, &self.world, r.pose, floor, &mut r.noise.main)
    }

    pub fn read_tilted_laser(&mut self, id: RobotId) -> TiltedScan {
        let floor = self.floor_z(self.robots[id.0].pose.position());
        let r = &mut self.robots[id.0];
        crate::sensors::read_tilted_laser(
            &r.spec.tilted_laser,
            &self.world,
            r.pose,
            floor,
            &mut r.noise.main,
        )
    }

    pub fn read_infrared(&mut self, id: RobotId) -> InfraredReading {
        let floor = self.floor_z(self.robots[id.0].pose.position());
        let r = &mut self.robots[id.0];
        crate::sensors::read_infrared(
            &r.spec.infrared,
            &self.world,
            r.pose,
            floor,
            &mut r.noise.main,
        )
    }

    pub fn read_attitude(&mut self, id: RobotId) -> Attitude {
        let r = &mut self.robots[id.0];
        crate::sensors::read_attitude(
            &self.world,
            r.pose,
            r.spec.length_m,
            r.spec.width_m,
            &r.spec.noise,
            &mut r.noise.main,
        )
    }
}

/// Separating-axis test of two robots' footprint rectangles.
fn rectangles_overlap((a, ra): (Pose2, &SimRobot), (b, rb): (Pose2, &SimRobot)) -> bool {
    let (sa, sb) = (&*ra.spec, &*rb.spec);
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let reach = ra.radius_m + rb.radius_m;
    if dx * dx + dy * dy > reach * reach {
        return false;
    }
    let axes = |p: Pose2| {
        let (s, c) = p.theta.sin_cos();
        [(c, s), (-s, c)]
    };
    let half = |p: Pose2, spec: &RobotSpec, (ax, ay): (f64, f64)| {
        let [(ux, uy), (vx, vy)] = axes(p);
        spec.length_m / 2.0 * (ux * ax + uy * ay).abs()
            + spec.width_m / 2.0 * (vx * ax + vy * ay).abs()
    };
    axes(a).into_iter().chain(axes(b)).all(|axis| {
        let distance = (dx * axis.0 + dy * axis.1).abs();
        distance < half(a, sa, axis) + half(b, sb, axis)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::{Cell, GridGeometry, Point2, obstacle};

    fn walled_box() -> Arc<Scene> {
        let g = GridGeometry::new(60, 40, 0.1, Point2::new(0.0, 0.0));
        let mut s = Scene::empty("box", g);
        for row in 0..40 {
            s.obstacle[Cell::new(45, row)] = obstacle::WALL;
        }
        Arc::new(s)
    }

    /// A wheeled robot at `pose` in [`walled_box`].
    fn wheeled_in_box(pose: Pose2) -> (Simulation, RobotId) {
        let mut sim = Simulation::new(walled_box(), SimConfig::default(), 1);
        let id = sim.add_robot(RobotSpec::wheeled(), pose).unwrap();
        (sim, id)
    }

    #[test]
    fn driving_into_a_wall_stops_and_counts_one_collision() {
        let (mut sim, id) = wheeled_in_box(Pose2::new(2.0, 2.0, 0.0));
        for _ in 0..100 {
            sim.step(&[Velocity {
                linear_mps: 0.5,
                angular_radps: 0.0,
            }]);
        }
        let r = sim.robot(id);
        assert_eq!(r.collisions, 1);
        // Wall cell 45 spans x ∈ [4.5, 4.6): the front (x + 0.25) stops short of its centre 4.55.
        assert!(r.pose.x + 0.25 < 4.55 && r.pose.x > 4.1, "{}", r.pose.x);
    }

    #[test]
    fn the_negated_last_motion_retraces_a_step_even_one_stopped_by_a_wall() {
        let (mut sim, id) = wheeled_in_box(Pose2::new(3.9, 2.0, 0.3));
        let forward = Velocity {
            linear_mps: 0.5,
            angular_radps: 0.4,
        };
        let mut poses = vec![sim.robot(id).pose];
        let mut motions = Vec::new();
        for _ in 0..8 {
            sim.step(&[forward]);
            poses.push(sim.robot(id).pose);
            motions.push(sim.robot(id).last_motion());
        }
        assert!(
            motions.contains(&forward) && motions.iter().any(|&m| m != forward),
            "the wall stops the robot after some free steps: {motions:?}"
        );
        for (k, m) in motions.iter().enumerate().rev() {
            sim.step(&[-*m]);
            let (p, q) = (sim.robot(id).pose, poses[k]);
            assert!(
                (p.x - q.x).abs() < 1e-9
                    && (p.y - q.y).abs() < 1e-9
                    && (p.theta - q.theta).abs() < 1e-9,
                "step {k}: {p:?} against {q:?}"
            );
        }
    }

    #[test]
    fn robots_do_not_overlap() {
        let mut sim = Simulation::new(walled_box(), SimConfig::default(), 1);
        sim.add_robot(RobotSpec::wheeled(), Pose2::new(1.0, 2.0, 0.0))
            .unwrap();
        sim.add_robot(
            RobotSpec::wheeled(),
            Pose2::new(3.0, 2.0, std::f64::consts::PI),
        )
        .unwrap();
        assert!(
            sim.add_robot(RobotSpec::wheeled(), Pose2::new(3.1, 2.0, 0.0))
                .is_err()
        );
        for _ in 0..60 {
            let go = Velocity {
                linear_mps: 0.5,
                angular_radps: 0.0,
            };
            sim.step(&[go, go]);
        }
        let (a, b) = (sim.robots()[0].pose, sim.robots()[1].pose);
        assert!(b.x - a.x >= 0.5 - 1e-9, "{} {}", a.x, b.x);
        assert_eq!(sim.robots()[0].collisions, 1);
    }
}

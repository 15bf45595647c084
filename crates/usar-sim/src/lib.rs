//! `usar-sim` is the simulator: robot models with footprints and climbing abilities (a tracked
//! crawler and a wheeled base), unicycle kinematics with collision detection against the 2.5-D
//! scene and between robots, and sensors with seeded noise — the 2-D laser, the laser tilted
//! down, the front depth array D_xy, the thermal camera, infrared proximity, odometry and
//! attitude.
//!
//! A run is a pure function of (scene, configuration, seed): every robot draws its noise from
//! its own `Pcg64Mcg` streams derived from the seed and its id (one for the thermal camera, one
//! for everything else). [`host`] runs controllers on one simulation: each sees only its own
//! robots' readings.
//!
//! ```
//! use std::sync::Arc;
//! use usar_sim::{RobotSpec, SimConfig, Simulation, Velocity, sensors::LaserScan};
//! use usar_world::{GridGeometry, Point2, Pose2, Scene};
//!
//! let scene = Arc::new(Scene::empty("hall", GridGeometry::new(100, 100, 0.1, Point2::new(0.0, 0.0))));
//! let mut sim = Simulation::new(scene, SimConfig::default(), 7);
//! let robot = sim.add_robot(RobotSpec::wheeled(), Pose2::new(5.0, 5.0, 0.0)).unwrap();
//! sim.step(&[Velocity { linear_mps: 0.5, angular_radps: 0.0 }]);
//! let mut scan = LaserScan::default();
//! sim.scan_laser(robot, &mut scan);
//! assert_eq!(scan.ranges_m.len(), 360);
//! assert!((sim.robot(robot).pose.x - 5.05).abs() < 1e-9);
//! ```

mod cell_robot;
pub mod host;
mod robot;
pub mod sensors;
mod simulation;
mod traversability;

pub use self::cell_robot::{CellAction, CellOutcome, CellRobot, RotationStep};
pub use self::robot::{FieldError, Locomotion, RobotSpec};
pub use self::simulation::{
    PlacementError, RobotId, SimConfig, SimRobot, Simulation, Velocity, derive_seed,
};
pub use self::traversability::{compute_blocked, footprint_cells};

/// Errors reading simulator inputs.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A file could not be read, or is past the input limits ([`usar_world::limits`]).
    #[error(transparent)]
    File(#[from] usar_world::WorldError),
    /// A robot file is malformed or holds an implausible value.
    #[error("{path}: {message}")]
    RobotFile { path: String, message: String },
}

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! Sensors with seeded noise. Each sensor has a spec (serialisable, part of a [`crate::RobotSpec`])
//! and a function that reads the ground truth through [`SensingWorld`] with the robot's own random
//! stream.

mod depth;
mod infrared;
mod laser;
mod proprioception;
mod sensing_world;
mod thermal;
mod tilted_laser;

pub use self::depth::{DepthSpec, read_depth};
pub use self::infrared::{InfraredSpec, read_infrared};
pub use self::laser::{Body, LaserModel, LaserSpec};
pub use self::proprioception::{NoiseSpec, Odometry, read_attitude};
pub use self::sensing_world::SensingWorld;
pub use self::thermal::{HeatDetection, HeatTruth, ThermalSpec, read_thermal};
pub use self::tilted_laser::{TiltedLaserSpec, read_tilted_laser};
/// The readings themselves live in `usar-readings`, below the simulator and the maps.
pub use usar_readings::{
    Attitude, DepthImage, DetectionId, InfraredReading, LaserScan, ThermalReading, TiltedScan,
};

use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// A zero-mean Gaussian sample with standard deviation `sd` (0 draws nothing).
#[inline]
pub(crate) fn gaussian(rng: &mut impl Rng, sd: f64) -> f64 {
    if sd > 0.0 {
        let z: f64 = StandardNormal.sample(rng);
        sd * z
    } else {
        0.0
    }
}

//! Infrared proximity sensors on the sides and back (paper 000: five sensors around the
//! perimeter, used to detect obstacles in the neighbouring cells).

use super::{SensingWorld, gaussian};
use rand::Rng;
use serde::{Deserialize, Serialize};
use usar_readings::InfraredReading;
use usar_world::Pose2;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InfraredSpec {
    /// Directions of the sensors relative to the heading, radians (left positive).
    pub directions_rad: Vec<f64>,
    pub max_range_m: f64,
    pub mount_height_m: f64,
    pub range_noise_sd_m: f64,
}

impl Default for InfraredSpec {
    /// Left, back-left, back, back-right, right; 1.0 m reach (one paper-000 cell beside the
    /// robot).
    fn default() -> Self {
        let deg = [90.0f64, 135.0, 180.0, -135.0, -90.0];
        Self {
            directions_rad: deg.iter().map(|d| d.to_radians()).collect(),
            max_range_m: 1.0,
            mount_height_m: 0.1,
            range_noise_sd_m: 0.005,
        }
    }
}

pub fn read_infrared(
    spec: &InfraredSpec,
    world: &SensingWorld,
    pose: Pose2,
    floor_z_m: f64,
    rng: &mut impl Rng,
) -> InfraredReading {
    let z = (floor_z_m + spec.mount_height_m) as f32;
    let ranges_m = spec
        .directions_rad
        .iter()
        .map(|&a| {
            let (s, c) = (pose.theta + a).sin_cos();
            world
                .cast_horizontal(pose.position(), c, s, z, spec.max_range_m)
                .map(|d| (d + gaussian(rng, spec.range_noise_sd_m)).clamp(0.0, spec.max_range_m))
        })
        .collect();
    InfraredReading { ranges_m }
}

//! Odometry (the robot's own estimate of its motion, drifting with noise) and attitude (pitch and
//! roll from the terrain under the footprint).

use super::{SensingWorld, gaussian};
use rand::Rng;
use serde::{Deserialize, Serialize};
use usar_readings::Attitude;
use usar_world::{Point2, Pose2};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseSpec {
    /// Odometry: standard deviation of the translation error per metre driven.
    pub odometry_translation_sd_per_m: f64,
    /// Odometry: standard deviation of the heading error per radian turned.
    pub odometry_rotation_sd_per_rad: f64,
    /// Attitude: standard deviation of pitch and roll, radians.
    pub attitude_sd_rad: f64,
}

impl Default for NoiseSpec {
    fn default() -> Self {
        Self {
            odometry_translation_sd_per_m: 0.02,
            odometry_rotation_sd_per_rad: 0.02,
            attitude_sd_rad: 0.5f64.to_radians(),
        }
    }
}

/// Dead-reckoned pose: integrates noisy increments of the true motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Odometry {
    pub estimate: Pose2,
    /// Distance driven according to the wheels/tracks, metres.
    pub distance_m: f64,
}

impl Odometry {
    pub fn new(start: Pose2) -> Self {
        Self {
            estimate: start,
            distance_m: 0.0,
        }
    }

    /// Adds one motion increment: `forward_m` along the heading, then a turn of `turn_rad`.
    pub fn integrate(
        &mut self,
        forward_m: f64,
        turn_rad: f64,
        noise: &NoiseSpec,
        rng: &mut impl Rng,
    ) {
        let forward = forward_m
            + gaussian(
                rng,
                noise.odometry_translation_sd_per_m * forward_m.abs().sqrt(),
            );
        let turn = turn_rad
            + gaussian(
                rng,
                noise.odometry_rotation_sd_per_rad * turn_rad.abs().sqrt(),
            );
        let e = &mut self.estimate;
        e.x += forward * e.theta.cos();
        e.y += forward * e.theta.sin();
        e.theta = usar_world::normalize_angle(e.theta + turn);
        self.distance_m += forward.abs();
    }
}

/// Attitude of a `length_m` × `width_m` robot at `pose`, from the floor heights under the middle
/// of its front, back, left and right edges (obstacle cells count as the robot's own floor).
pub fn read_attitude(
    world: &SensingWorld,
    pose: Pose2,
    length_m: f64,
    width_m: f64,
    noise: &NoiseSpec,
    rng: &mut impl Rng,
) -> Attitude {
    let floor = |p: Point2, fallback: f64| match world.height_at(p) {
        Some(h) if h.is_finite() => f64::from(h),
        _ => fallback,
    };
    let centre = floor(pose.position(), 0.0);
    let at = |x: f64, y: f64| floor(pose.to_world(Point2::new(x, y)), centre);
    let (front, back) = (at(length_m / 2.0, 0.0), at(-length_m / 2.0, 0.0));
    let (left, right) = (at(0.0, width_m / 2.0), at(0.0, -width_m / 2.0));
    Attitude {
        pitch_rad: (front - back).atan2(length_m) + gaussian(rng, noise.attitude_sd_rad),
        roll_rad: (left - right).atan2(width_m) + gaussian(rng, noise.attitude_sd_rad),
    }
}

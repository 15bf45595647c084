//! The laser tilted down (paper 004 Fig. 5): a fan of beams in a plane inclined towards the
//! floor ahead. On a flat floor every beam returns the reference range L; an obstacle of height
//! h in front shortens it to l₁, and h = (L − l₁)·cos θ, θ being the tilt from the vertical.

use super::{SensingWorld, gaussian};
use rand::Rng;
use serde::{Deserialize, Serialize};
use usar_readings::TiltedScan;
use usar_world::Pose2;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TiltedLaserSpec {
    /// Height of the sensor above the floor under the robot, metres (paper 004: H).
    pub mount_height_m: f64,
    /// Tilt of the central beam from the vertical, radians (paper 004: θ). 60° looks at the
    /// floor H / cos θ = 1 m away along the beam with the default 0.5 m mount.
    pub tilt_from_vertical_rad: f64,
    /// Beams across the fan.
    pub beams: u32,
    /// Angular width of the fan, radians.
    pub fov_rad: f64,
    pub max_range_m: f64,
    pub range_noise_sd_m: f64,
}

impl Default for TiltedLaserSpec {
    fn default() -> Self {
        Self {
            mount_height_m: 0.5,
            tilt_from_vertical_rad: 60f64.to_radians(),
            beams: 41,
            fov_rad: 60f64.to_radians(),
            max_range_m: 4.0,
            range_noise_sd_m: 0.005,
        }
    }
}

impl TiltedLaserSpec {
    /// Range L the central beam returns on a flat floor (paper 004 Fig. 5).
    pub fn flat_floor_range_m(&self) -> f64 {
        self.mount_height_m / self.tilt_from_vertical_rad.cos()
    }
}

/// Reads the tilted laser from `pose` on a floor at `floor_z_m`.
///
/// Beam i has direction d = R_z(heading)·R_y(pitch)·(cos φᵢ, sin φᵢ, 0) in the tilted plane: its
/// horizontal heading is heading + atan(tan φᵢ / cos p) and its pitch below the horizon is
/// asin(sin p·cos φᵢ), with p = π/2 − θ.
pub fn read_tilted_laser(
    spec: &TiltedLaserSpec,
    world: &SensingWorld,
    pose: Pose2,
    floor_z_m: f64,
    rng: &mut impl Rng,
) -> TiltedScan {
    let n = spec.beams.max(1) as usize;
    let inc = if n > 1 {
        spec.fov_rad / (n - 1) as f64
    } else {
        0.0
    };
    let yaw_min = -spec.fov_rad / 2.0;
    let p = std::f64::consts::FRAC_PI_2 - spec.tilt_from_vertical_rad;
    let (sp, cp) = p.sin_cos();
    let z0 = floor_z_m + spec.mount_height_m;
    let ranges_m = (0..n)
        .map(|i| {
            let phi = yaw_min + i as f64 * inc;
            let (sphi, cphi) = phi.sin_cos();
            // Tilted-plane beam (cos φ, sin φ, 0) pitched down by p about the body y axis.
            let (bx, by, bz) = (cphi * cp, sphi, -cphi * sp);
            let horizontal = bx.hypot(by);
            let pitch_down = (-bz).atan2(horizontal);
            let yaw = pose.theta + by.atan2(bx);
            let (s, c) = yaw.sin_cos();
            match world.cast_3d(pose.position(), z0, c, s, pitch_down, spec.max_range_m) {
                Some(d) => (d + gaussian(rng, spec.range_noise_sd_m)).max(0.0) as f32,
                None => f32::INFINITY,
            }
        })
        .collect();
    TiltedScan {
        pose,
        yaw_min_rad: yaw_min,
        yaw_increment_rad: inc,
        ranges_m,
    }
}

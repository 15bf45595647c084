//! The front 3-D depth sensor giving the D_xy array of paper 000 (Fig. 4): a small grid of
//! ranges looking at the terrain in front of the robot, from which rubble is classified.

use super::{SensingWorld, gaussian};
use rand::Rng;
use serde::{Deserialize, Serialize};
use usar_readings::DepthImage;
use usar_world::Pose2;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DepthSpec {
    /// Rows (vertical samples) of D_xy; row 0 is the top of the field of view.
    pub rows: u32,
    /// Columns (horizontal samples) of D_xy; column 0 is the left.
    pub cols: u32,
    pub hfov_rad: f64,
    pub vfov_rad: f64,
    /// Pitch of the optical axis below the horizon, radians.
    pub pitch_down_rad: f64,
    pub mount_height_m: f64,
    /// Paper 000 §VII: the sensing range was set to one cell length (0.914 m) ahead; the beams
    /// are longer because they look down at an angle.
    pub max_range_m: f64,
    pub range_noise_sd_m: f64,
}

impl Default for DepthSpec {
    fn default() -> Self {
        Self {
            rows: 12,
            cols: 12,
            hfov_rad: 58f64.to_radians(),
            vfov_rad: 45f64.to_radians(),
            pitch_down_rad: 30f64.to_radians(),
            mount_height_m: 0.4,
            max_range_m: 2.0,
            range_noise_sd_m: 0.005,
        }
    }
}

/// Reads D_xy from `pose` on a floor at `floor_z_m`.
pub fn read_depth(
    spec: &DepthSpec,
    world: &SensingWorld,
    pose: Pose2,
    floor_z_m: f64,
    rng: &mut impl Rng,
) -> DepthImage {
    let spread = |n: u32, fov: f64, i: u32| {
        if n > 1 {
            -fov / 2.0 + fov * f64::from(i) / f64::from(n - 1)
        } else {
            0.0
        }
    };
    let col_yaw_rad: Vec<f64> = (0..spec.cols)
        .map(|c| -spread(spec.cols, spec.hfov_rad, c))
        .collect();
    let row_pitch_down_rad: Vec<f64> = (0..spec.rows)
        .map(|r| spec.pitch_down_rad + spread(spec.rows, spec.vfov_rad, r))
        .collect();
    let z0 = floor_z_m + spec.mount_height_m;
    let mut depth_m = Vec::with_capacity((spec.rows * spec.cols) as usize);
    for &pitch in &row_pitch_down_rad {
        for &yaw in &col_yaw_rad {
            let (s, c) = (pose.theta + yaw).sin_cos();
            depth_m.push(
                match world.cast_3d(pose.position(), z0, c, s, pitch, spec.max_range_m) {
                    Some(d) => (d + gaussian(rng, spec.range_noise_sd_m)).max(0.0) as f32,
                    None => f32::INFINITY,
                },
            );
        }
    }
    DepthImage {
        pose,
        rows: spec.rows,
        cols: spec.cols,
        depth_m,
        col_yaw_rad,
        row_pitch_down_rad,
        sensor_z_m: z0,
    }
}

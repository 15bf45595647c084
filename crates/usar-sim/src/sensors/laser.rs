//! The horizontal 2-D laser range finder (paper 002: 360°, 1°, 20 m).

use super::{SensingWorld, gaussian};
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;
use usar_readings::LaserScan;
use usar_world::Pose2;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LaserSpec {
    pub beams: u32,
    /// Field of view, radians, centred on the heading (2π: all around).
    pub fov_rad: f64,
    pub max_range_m: f64,
    /// Standard deviation of the Gaussian range noise, metres.
    pub range_noise_sd_m: f64,
    /// Height of the scanning plane above the floor under the robot, metres.
    pub mount_height_m: f64,
}

impl Default for LaserSpec {
    /// Paper 002 §4.1: 360° field of view, 1° resolution, 20 m range; 1 cm noise (a typical
    /// SICK/Hokuyo figure) and a 0.3 m mount.
    fn default() -> Self {
        Self {
            beams: 360,
            fov_rad: TAU,
            max_range_m: 20.0,
            range_noise_sd_m: 0.01,
            mount_height_m: 0.3,
        }
    }
}

/// A laser ready to scan: its spec with the beams' direction table precomputed, so a scan costs
/// one `sin_cos` plus the ray walks.
#[derive(Clone, Debug)]
pub struct LaserModel {
    spec: LaserSpec,
    angle_min_rad: f64,
    angle_increment_rad: f64,
    /// (cos, sin) of each beam's angle relative to the heading.
    beam_dirs: Vec<(f64, f64)>,
}

impl LaserModel {
    pub fn new(spec: LaserSpec) -> Self {
        let n = spec.beams.max(1) as usize;
        let full_circle = spec.fov_rad >= TAU - 1e-9;
        let increment = if full_circle {
            TAU / n as f64
        } else if n > 1 {
            spec.fov_rad / (n - 1) as f64
        } else {
            0.0
        };
        let angle_min = if full_circle {
            -std::f64::consts::PI
        } else {
            -spec.fov_rad / 2.0
        };
        let beam_dirs = (0..n)
            .map(|i| (angle_min + i as f64 * increment).sin_cos())
            .map(|(s, c)| (c, s))
            .collect();
        Self {
            spec,
            angle_min_rad: angle_min,
            angle_increment_rad: increment,
            beam_dirs,
        }
    }

    pub fn spec(&self) -> &LaserSpec {
        &self.spec
    }

    /// Scans from `pose`, standing on a floor at `floor_z_m`, into `scan` (its buffer is reused).
    pub fn scan_into(
        &self,
        world: &SensingWorld,
        pose: Pose2,
        floor_z_m: f64,
        rng: &mut impl Rng,
        scan: &mut LaserScan,
    ) {
        let (s, c) = pose.theta.sin_cos();
        let z = (floor_z_m + self.spec.mount_height_m) as f32;
        let origin = pose.position();
        let max = self.spec.max_range_m;
        scan.pose = pose;
        scan.angle_min_rad = self.angle_min_rad;
        scan.angle_increment_rad = self.angle_increment_rad;
        scan.max_range_m = max;
        scan.ranges_m.clear();
        scan.ranges_m.extend(self.beam_dirs.iter().map(|&(bc, bs)| {
            // Rotate the beam direction by the heading.
            let (dc, ds) = (c * bc - s * bs, s * bc + c * bs);
            match world.cast_horizontal(origin, dc, ds, z, max) {
                Some(d) => (d + gaussian(rng, self.spec.range_noise_sd_m)).clamp(0.0, max) as f32,
                None => f32::INFINITY,
            }
        }));
    }

    /// Scans from `pose` into a new [`LaserScan`].
    pub fn scan(
        &self,
        world: &SensingWorld,
        pose: Pose2,
        floor_z_m: f64,
        rng: &mut impl Rng,
    ) -> LaserScan {
        let mut scan = LaserScan::default();
        self.scan_into(world, pose, floor_z_m, rng, &mut scan);
        scan
    }
}

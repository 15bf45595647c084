//! The horizontal 2-D laser range finder (paper 002: 360°, 1°, 20 m).

use super::{SensingWorld, gaussian};
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;
use usar_readings::LaserScan;
use usar_world::{Point2, Pose2};

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
        self.scan_among(world, &[], pose, floor_z_m, rng, scan);
    }

    /// [`LaserModel::scan_into`] among moving `bodies` (other robots): a beam ends at the
    /// nearer of the scene and the first body it meets.
    pub fn scan_among(
        &self,
        world: &SensingWorld,
        bodies: &[Body],
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
            let static_hit = world.cast_horizontal(origin, dc, ds, z, max);
            let hit = bodies
                .iter()
                .filter_map(|b| b.ray_hit(origin, dc, ds, max))
                .fold(static_hit, |a, d| Some(a.map_or(d, |a: f64| a.min(d))));
            match hit {
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

/// A rectangle standing on the floor that lasers see: another robot's footprint, taller than
/// any horizontal laser is mounted (robots have no height in their spec).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    pub pose: Pose2,
    pub half_length_m: f64,
    pub half_width_m: f64,
}

impl Body {
    /// Distance along the unit direction (dc, ds) from `origin` to where the ray enters the
    /// rectangle, if within `max_m` (slab method in the body's frame; a ray starting inside
    /// meets nothing).
    pub fn ray_hit(&self, origin: Point2, dc: f64, ds: f64, max_m: f64) -> Option<f64> {
        let reach = self.half_length_m.hypot(self.half_width_m);
        let to = Point2::new(self.pose.x - origin.x, self.pose.y - origin.y);
        let along = to.x * dc + to.y * ds;
        if along + reach < 0.0 || along - reach > max_m {
            return None;
        }
        let (s, c) = self.pose.theta.sin_cos();
        // Origin and direction in the body frame.
        let (ox, oy) = (-(to.x * c + to.y * s), -(-to.x * s + to.y * c));
        let (ux, uy) = (dc * c + ds * s, -dc * s + ds * c);
        let (mut t_in, mut t_out) = (f64::NEG_INFINITY, f64::INFINITY);
        for (o, u, half) in [(ox, ux, self.half_length_m), (oy, uy, self.half_width_m)] {
            if u.abs() < 1e-12 {
                if o.abs() > half {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((-half - o) / u, (half - o) / u);
            t_in = t_in.max(t0.min(t1));
            t_out = t_out.min(t0.max(t1));
        }
        (t_in <= t_out && t_in > 0.0 && t_in <= max_m).then_some(t_in)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_enters_a_body_at_its_near_face_and_misses_beside_it() {
        let body = Body {
            pose: Pose2::new(3.0, 0.0, std::f64::consts::FRAC_PI_2),
            half_length_m: 0.3,
            half_width_m: 0.2,
        };
        let o = Point2::new(0.0, 0.0);
        // Turned a quarter: its width lies along x, so the near face is at x = 2.8.
        assert!((body.ray_hit(o, 1.0, 0.0, 10.0).unwrap() - 2.8).abs() < 1e-12);
        assert_eq!(body.ray_hit(o, -1.0, 0.0, 10.0), None);
        assert_eq!(body.ray_hit(o, 1.0, 0.0, 2.5), None);
        let up = (0.35f64).atan2(3.0);
        assert_eq!(body.ray_hit(o, up.cos(), up.sin(), 10.0), None);
        // From inside it sees nothing of it.
        assert_eq!(body.ray_hit(Point2::new(3.0, 0.0), 1.0, 0.0, 10.0), None);
    }
}

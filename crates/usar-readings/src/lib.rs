//! `usar-readings`: what a robot's sensors give, as plain data — the types a controller, a map
//! or a log reader works with, whether the readings come from the simulator (`usar-sim`), a
//! recorded log or a real robot. They sit below both the simulator and the maps, so a map
//! (`usar-map`) needs no simulator to be fed.
//!
//! ```
//! use usar_readings::LaserScan;
//! use usar_world::Pose2;
//!
//! // Four beams a quarter turn apart, the second one returning nothing.
//! let scan = LaserScan {
//!     pose: Pose2::new(1.0, 2.0, 0.0),
//!     angle_min_rad: 0.0,
//!     angle_increment_rad: std::f64::consts::FRAC_PI_2,
//!     max_range_m: 20.0,
//!     ranges_m: vec![3.0, f32::INFINITY, 1.5, 2.0],
//! };
//! assert!((scan.beam_angle(2) - std::f64::consts::PI).abs() < 1e-12);
//! ```

use serde::{Deserialize, Serialize};
use usar_world::Pose2;

/// One scan. `ranges_m[i]` is the range of beam i at angle `angle_min_rad + i·angle_increment_rad`
/// relative to the robot heading, or +∞ when the beam met nothing within `max_range_m`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LaserScan {
    /// Pose of the sensor (the robot pose) when the scan was taken.
    pub pose: Pose2,
    pub angle_min_rad: f64,
    pub angle_increment_rad: f64,
    pub max_range_m: f64,
    pub ranges_m: Vec<f32>,
}

impl LaserScan {
    /// World angle of beam `i`.
    pub fn beam_angle(&self, i: usize) -> f64 {
        self.pose.theta + self.angle_min_rad + i as f64 * self.angle_increment_rad
    }
}

/// One sweep of the tilted laser: ranges along each beam (+∞ for no return), beam i at yaw
/// `yaw_min_rad + i·yaw_increment_rad` in the tilted plane.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TiltedScan {
    pub pose: Pose2,
    pub yaw_min_rad: f64,
    pub yaw_increment_rad: f64,
    pub ranges_m: Vec<f32>,
}

/// A depth image: `depth_m[row * cols + col]` is the range along that pixel's ray (+∞ when
/// nothing is within range), together with the pixel's ray angles so a consumer can rebuild the
/// 3-D points.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthImage {
    pub pose: Pose2,
    pub rows: u32,
    pub cols: u32,
    pub depth_m: Vec<f32>,
    /// Yaw of each column relative to the heading, radians (left positive).
    pub col_yaw_rad: Vec<f64>,
    /// Pitch below the horizon of each row, radians.
    pub row_pitch_down_rad: Vec<f64>,
    /// Sensor height above the world's zero level when the image was taken.
    pub sensor_z_m: f64,
}

impl DepthImage {
    /// The 3-D point seen by pixel (row, col) in the robot frame (x forward, y left, z up from
    /// the sensor), or `None` for no return.
    pub fn point_body(&self, row: u32, col: u32) -> Option<[f64; 3]> {
        let d = f64::from(*self.depth_m.get((row * self.cols + col) as usize)?);
        if !d.is_finite() {
            return None;
        }
        let (yaw, pitch) = (
            self.col_yaw_rad[col as usize],
            self.row_pitch_down_rad[row as usize],
        );
        let horizontal = d * pitch.cos();
        Some([
            horizontal * yaw.cos(),
            horizontal * yaw.sin(),
            -d * pitch.sin(),
        ])
    }
}

/// Ranges of each infrared sensor, in the order of the spec's directions (`None`: nothing seen).
#[derive(Clone, Debug, PartialEq)]
pub struct InfraredReading {
    pub ranges_m: Vec<Option<f64>>,
}

/// Pitch (nose up positive) and roll (left side up positive), radians.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Attitude {
    pub pitch_rad: f64,
    pub roll_rad: f64,
}

impl Attitude {
    /// Inclination of the body from the horizontal plane, radians.
    pub fn inclination_rad(&self) -> f64 {
        (self.pitch_rad.cos() * self.roll_rad.cos())
            .clamp(-1.0, 1.0)
            .acos()
    }
}

/// One warm region seen by the thermal camera, as a controller gets it: what was measured, and
/// an opaque number the host can later tell the evaluator about (which source caused it). The
/// number carries nothing a controller could use: it counts readings in the order they were
/// taken.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ThermalReading {
    pub id: DetectionId,
    /// Bearing relative to the heading, radians.
    pub bearing_rad: f64,
    pub range_m: f64,
    pub temperature_c: f64,
    /// h: the temperature lies in the human band.
    pub human_signature: bool,
    /// s: apparent size of the warm region, m².
    pub size_m2: f64,
}

impl ThermalReading {
    /// World position of the region seen from `pose`.
    pub fn position(&self, pose: Pose2) -> usar_world::Point2 {
        pose.position()
            .offset(pose.theta + self.bearing_rad, self.range_m)
    }
}

/// The number of one thermal reading (see [`ThermalReading::id`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct DetectionId(pub u64);

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

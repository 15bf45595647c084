//! The thermal camera (paper 000 §IV-A-3): reports heat regions in its field of view, each with a
//! measured temperature, whether it lies in the band of a human heat signature (h) and the size
//! of the visible region (s).

use super::{SensingWorld, gaussian};
use rand::Rng;
use serde::{Deserialize, Serialize};
use usar_world::{Point2, Pose2, Scene};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalSpec {
    pub hfov_rad: f64,
    pub max_range_m: f64,
    pub mount_height_m: f64,
    pub temperature_noise_sd_c: f64,
    /// Relative standard deviation of the measured region size.
    pub size_noise_fraction: f64,
    /// Temperatures read as a human heat signature (h = 1), °C.
    pub human_band_c: [f64; 2],
}

impl Default for ThermalSpec {
    fn default() -> Self {
        Self {
            hfov_rad: 60f64.to_radians(),
            max_range_m: 6.0,
            mount_height_m: 0.3,
            temperature_noise_sd_c: 0.5,
            size_noise_fraction: 0.1,
            human_band_c: [28.0, 40.0],
        }
    }
}

/// Which ground-truth object caused a detection. For scoring and the simulated operator only: a
/// controller must decide from the measured values, never from this.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", content = "id", rename_all = "snake_case")]
pub enum HeatTruth {
    Victim(u32),
    Other(u32),
}

/// One heat region seen by the camera.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeatDetection {
    /// Bearing relative to the heading, radians.
    pub bearing_rad: f64,
    pub range_m: f64,
    pub temperature_c: f64,
    /// h: the temperature lies in the human band.
    pub human_signature: bool,
    /// s: apparent size of the warm region, m².
    pub size_m2: f64,
    pub truth: HeatTruth,
}

impl HeatDetection {
    /// World position of the region seen from `pose`.
    pub fn position(&self, pose: Pose2) -> Point2 {
        pose.position()
            .offset(pose.theta + self.bearing_rad, self.range_m)
    }
}

/// Reads the thermal camera from `pose` on a floor at `floor_z_m`. A source is seen when it lies
/// in the field of view and range, the line of sight at the camera's height is clear, and part
/// of it is exposed. Detections are ordered by truth (victims by id, then other sources by id).
pub fn read_thermal(
    spec: &ThermalSpec,
    scene: &Scene,
    world: &SensingWorld,
    pose: Pose2,
    floor_z_m: f64,
    rng: &mut impl Rng,
) -> Vec<HeatDetection> {
    let z = (floor_z_m + spec.mount_height_m) as f32;
    let victims = scene.victims.iter().map(|v| {
        (
            v.position,
            v.heat_c,
            v.exposed_size_m2(),
            HeatTruth::Victim(v.id),
        )
    });
    let others = scene
        .heat_sources
        .iter()
        .map(|h| (h.position, h.heat_c, h.size_m2, HeatTruth::Other(h.id)));
    let mut out = Vec::new();
    for (position, heat_c, size_m2, truth) in victims.chain(others) {
        let range = pose.position().distance(position);
        let bearing =
            usar_world::normalize_angle(pose.position().bearing_to(position) - pose.theta);
        if size_m2 <= 0.0 || range > spec.max_range_m || bearing.abs() > spec.hfov_rad / 2.0 {
            continue;
        }
        let world_angle = pose.theta + bearing;
        // The source's own cell may be raised (a victim lying on rubble): allow half a cell.
        let clear = match world.cast_horizontal(
            pose.position(),
            world_angle.cos(),
            world_angle.sin(),
            z,
            range,
        ) {
            None => true,
            Some(d) => d >= range - world.geometry().resolution_m,
        };
        if !clear {
            continue;
        }
        let temperature_c = heat_c + gaussian(rng, spec.temperature_noise_sd_c);
        let size = (size_m2 * (1.0 + gaussian(rng, spec.size_noise_fraction))).max(0.0);
        out.push(HeatDetection {
            bearing_rad: bearing,
            range_m: range,
            temperature_c,
            human_signature: (spec.human_band_c[0]..=spec.human_band_c[1]).contains(&temperature_c),
            size_m2: size,
            truth,
        });
    }
    out
}

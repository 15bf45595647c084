//! Victims and the heat sources that are not victims (thermal false positives).

use crate::geometry::Point2;
use serde::{Deserialize, Serialize};

/// A person to be found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Victim {
    pub id: u32,
    pub position: Point2,
    /// Surface temperature of the exposed body, °C (a healthy person ≈ 33–36 °C at the skin).
    pub heat_c: f64,
    /// Area of the body a thermal camera could see if nothing covered it, m².
    pub visible_size_m2: f64,
    /// Fraction of that area covered by rubble, 0 (in the open) to 1 (invisible).
    pub buried_fraction: f64,
}

impl Victim {
    /// Area a thermal camera can actually see, m².
    pub fn exposed_size_m2(&self) -> f64 {
        self.visible_size_m2 * (1.0 - self.buried_fraction).clamp(0.0, 1.0)
    }
}

/// A heat source that is not a victim: a radiator, a small fire, a warm engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeatSource {
    pub id: u32,
    pub position: Point2,
    pub heat_c: f64,
    pub size_m2: f64,
    /// Free text: "radiator", "fire", ...
    pub kind: String,
}

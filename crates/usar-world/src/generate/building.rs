//! Paper 002 §4.1 building floors (`office`, `mall`).
use crate::scene::Scene;

/// Parameters of a building floor.
#[derive(Clone, Debug, PartialEq)]
pub struct BuildingParams {
    /// Floor width (x), metres.
    pub width_m: f64,
    /// Floor depth (y), metres.
    pub height_m: f64,
    /// Grid resolution, metres.
    pub resolution_m: f64,
}

impl BuildingParams {
    pub fn office() -> Self {
        todo!("building generator")
    }
    pub fn mall() -> Self {
        todo!("building generator")
    }
}

pub fn generate_office(_seed: u64, _params: &BuildingParams) -> Scene {
    todo!("building generator")
}

pub fn generate_mall(_seed: u64, _params: &BuildingParams) -> Scene {
    todo!("building generator")
}

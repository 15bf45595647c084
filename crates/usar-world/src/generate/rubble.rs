//! Paper 000 §VI rubble arenas.
use crate::scene::Scene;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct RubbleParams {}

pub fn generate_rubble(_seed: u64, _params: &RubbleParams) -> Scene {
    todo!("rubble generator")
}

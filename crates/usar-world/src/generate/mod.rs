//! Seeded, deterministic scene generators: the same kind, parameters and seed always give the same
//! scene (and the same file bytes).
//!
//! - [`SceneKind::Rubble`]: paper 000 §VI rubble arenas (20×20 coarse cells of 0.84 m²).
//! - [`SceneKind::Office`], [`SceneKind::Mall`]: paper 002 §4.1 building floors.
//! - [`SceneKind::Course`]: paper 004 Fig. 15 test course.

mod building;
mod course;
pub mod draw;
mod rubble;

pub use self::building::{
    AreaRange, BuildingParams, LabelShares, LengthRange, generate_mall, generate_office,
};
pub use self::course::{CourseParams, generate_course};
pub use self::rubble::{ClassShares, RubbleParams, RubbleStyle, RubbleTerrain, generate_rubble};

use crate::scene::Scene;

/// The scene generators, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneKind {
    Rubble,
    Office,
    Mall,
    Course,
}

impl SceneKind {
    pub const ALL: [SceneKind; 4] = [
        SceneKind::Rubble,
        SceneKind::Office,
        SceneKind::Mall,
        SceneKind::Course,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            SceneKind::Rubble => "rubble",
            SceneKind::Office => "office",
            SceneKind::Mall => "mall",
            SceneKind::Course => "course",
        }
    }
}

impl std::str::FromStr for SceneKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        SceneKind::ALL
            .into_iter()
            .find(|k| k.as_str() == s)
            .ok_or_else(|| {
                format!("unknown scene kind {s:?}, expected one of: rubble, office, mall, course")
            })
    }
}

impl std::fmt::Display for SceneKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Generates a scene of `kind` with default parameters.
pub fn generate(kind: SceneKind, seed: u64) -> Scene {
    match kind {
        SceneKind::Rubble => generate_rubble(seed, &RubbleParams::default()),
        SceneKind::Office => generate_office(seed, &BuildingParams::office()),
        SceneKind::Mall => generate_mall(seed, &BuildingParams::mall()),
        SceneKind::Course => generate_course(seed, &CourseParams::default()),
    }
}

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
pub use self::rubble::{
    ClassShares, RubbleParams, RubbleStyle, RubbleTerrain, RubbleZone, generate_rubble, lay_rubble,
};

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

/// Why [`generate_furnished`] refused.
#[derive(Debug, thiserror::Error)]
pub enum GenerateError {
    /// Only the building generators (office, mall) place furniture.
    #[error("the {0} generator has no furniture (only office and mall do)")]
    NoFurniture(SceneKind),
    /// The furniture share made the building parameters invalid ([`BuildingParams::check`]).
    #[error("{0}")]
    Params(crate::WorldError),
}

/// Generates a scene of `kind`, with default parameters except the share of the floor covered
/// by furniture when `furniture_fraction` is given (office and mall only; the parameters are
/// checked, not clamped). Without it this is [`generate`].
pub fn generate_furnished(
    kind: SceneKind,
    seed: u64,
    furniture_fraction: Option<f64>,
) -> Result<Scene, GenerateError> {
    let Some(share) = furniture_fraction else {
        return Ok(generate(kind, seed));
    };
    type Generator = fn(u64, &BuildingParams) -> Scene;
    let (defaults, generate): (BuildingParams, Generator) = match kind {
        SceneKind::Office => (BuildingParams::office(), generate_office),
        SceneKind::Mall => (BuildingParams::mall(), generate_mall),
        SceneKind::Rubble | SceneKind::Course => return Err(GenerateError::NoFurniture(kind)),
    };
    let params = BuildingParams {
        furniture_fraction: share,
        ..defaults
    };
    params.check().map_err(GenerateError::Params)?;
    Ok(generate(seed, &params))
}

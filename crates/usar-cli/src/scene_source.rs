//! Resolves a SCENE argument: a scene file, a ROS map, a map image, a MovingAI map or a
//! generator name.

use crate::cli::{GeneratorKind, ImageArgs, SceneSpec};
use crate::failure::{CmdResult, InputContext, bad_input};
use std::path::Path;
use usar_world::Scene;
use usar_world::generate::SceneKind;
use usar_world::io::source::{BareImage, load_scene};

pub fn kind(k: GeneratorKind) -> SceneKind {
    match k {
        GeneratorKind::Rubble => SceneKind::Rubble,
        GeneratorKind::Office => SceneKind::Office,
        GeneratorKind::Mall => SceneKind::Mall,
        GeneratorKind::Course => SceneKind::Course,
    }
}

impl ImageArgs {
    /// The library's options for a bare map image.
    pub fn bare(&self) -> BareImage {
        BareImage {
            resolution_m: self.resolution,
            negate: self.negate,
            occupied_thresh: self.occupied_thresh,
            free_thresh: self.free_thresh,
        }
    }
}

/// The scene a command's [`SceneSpec`] names.
pub fn load_spec(spec: &SceneSpec) -> CmdResult<Scene> {
    load(&spec.scene, spec.seed, &spec.image)
}

/// Refuses a scene output path that [`load`] could not read back
/// ([`usar_world::io::check_scene_output`]); `option` names the argument in the message.
pub fn check_scene_output(path: &Path, option: &str) -> CmdResult {
    usar_world::io::check_scene_output(path).map_err(|e| bad_input(anyhow::anyhow!("{option} {e}")))
}

/// Loads a scene from a path (by extension) or generates one by name
/// ([`usar_world::io::source::load_scene`]).
pub fn load(spec: &str, seed: u64, image: &ImageArgs) -> CmdResult<Scene> {
    load_scene(spec, seed, &image.bare()).input()
}

/// A robot model from a preset name or a robot TOML file ([`usar_sim::RobotSpec::load`]).
pub fn load_robot(spec: &str) -> CmdResult<usar_sim::RobotSpec> {
    usar_sim::RobotSpec::load(spec).input()
}

/// Reads a TOML settings file into `T`; a bad file is bad input naming the file and the line.
pub fn read_toml<T: serde::de::DeserializeOwned>(path: &Path) -> CmdResult<T> {
    let text = usar_world::limits::read_text(path).input()?;
    toml::from_str(&text).map_err(|e: toml::de::Error| {
        bad_input(anyhow::anyhow!(
            "{}: {}",
            path.display(),
            usar_world::toml_error_line(&text, &e)
        ))
    })
}

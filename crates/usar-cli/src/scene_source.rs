//! Resolves a SCENE argument: a scene file, a ROS map, a map image, a MovingAI map or a
//! generator name.

use crate::cli::{GeneratorKind, ImageArgs, SceneSpec};
use crate::failure::{CmdResult, InputContext, bad_input};
use std::path::Path;
use usar_world::generate::{SceneKind, generate};
use usar_world::io::image_map::{ImageMapOptions, read_image_map};
use usar_world::{Point2, Scene};

pub fn kind(k: GeneratorKind) -> SceneKind {
    match k {
        GeneratorKind::Rubble => SceneKind::Rubble,
        GeneratorKind::Office => SceneKind::Office,
        GeneratorKind::Mall => SceneKind::Mall,
        GeneratorKind::Course => SceneKind::Course,
    }
}

pub fn image_options(image: &ImageArgs, path: &Path) -> CmdResult<ImageMapOptions> {
    let resolution_m = image.resolution.ok_or_else(|| {
        bad_input(anyhow::anyhow!(
            "{}: a bare map image needs --resolution (metres per pixel), e.g. --resolution 0.05",
            path.display()
        ))
    })?;
    Ok(ImageMapOptions {
        resolution_m,
        origin: Point2::new(0.0, 0.0),
        negate: image.negate,
        occupied_thresh: image.occupied_thresh,
        free_thresh: image.free_thresh,
        ..ImageMapOptions::default()
    })
}

/// The scene a command's [`SceneSpec`] names.
pub fn load_spec(spec: &SceneSpec) -> CmdResult<Scene> {
    load(&spec.scene, spec.seed, &spec.image)
}

/// Refuses a scene output path that [`load`] could not read back: scene files are `.json`
/// (the extension chooses the format when a file is read).
pub fn check_scene_output(path: &Path, option: &str) -> CmdResult {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() == Some("json") {
        return Ok(());
    }
    Err(bad_input(anyhow::anyhow!(
        "{option} {}: a scene file must end in .json, found {}; the extension chooses the \
         format when the file is read back",
        path.display(),
        ext.map_or_else(|| "no extension".to_string(), |e| format!(".{e}"))
    )))
}

/// Loads a scene from a path (by extension) or generates one by name.
pub fn load(spec: &str, seed: u64, image: &ImageArgs) -> CmdResult<Scene> {
    if let Ok(kind) = spec.parse::<SceneKind>()
        && !Path::new(spec).exists()
    {
        return Ok(generate(kind, seed));
    }
    let path = Path::new(spec);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "json" => usar_world::read_scene(path).input(),
        "yaml" | "yml" => usar_world::io::ros::read_ros_map(path).input(),
        "pgm" | "png" => read_image_map(path, &image_options(image, path)?).input(),
        "map" => {
            let map = usar_world::io::movingai::read_movingai_map(path).input()?;
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            map.to_scene(&name, image.resolution.unwrap_or(1.0)).input()
        }
        _ if !path.exists() => Err(bad_input(anyhow::anyhow!(
            "{spec}: no such file, and not a generator name (expected rubble, office, mall or course)"
        ))),
        _ => Err(bad_input(anyhow::anyhow!(
            "{spec}: unknown scene format {ext:?}, expected .json (usar scene), .yaml (ROS map_server), .pgm/.png (map image) or .map (MovingAI)"
        ))),
    }
}

/// A robot model from a preset name (`crawler`, `wheeled`) or a robot TOML file.
pub fn load_robot(spec: &str) -> CmdResult<usar_sim::RobotSpec> {
    if let Some(preset) = usar_sim::RobotSpec::preset(spec) {
        return Ok(preset);
    }
    let path = Path::new(spec);
    if !path.exists() {
        return Err(bad_input(anyhow::anyhow!(
            "{spec}: not a robot preset (crawler, wheeled) and no such robot file"
        )));
    }
    usar_sim::RobotSpec::from_toml_file(path).input()
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

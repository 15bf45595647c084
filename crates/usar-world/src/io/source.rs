//! A scene named the way a user names one: a usar scene file (`.json`), a ROS `map_server`
//! map (`.yaml`), a bare map image (`.pgm`/`.png`, with a resolution), a MovingAI map (`.map`),
//! or the name of a generator (`rubble`, `office`, `mall`, `course`) with a seed. The format
//! is chosen by the file's extension; a generator name wins only when no file of that name
//! exists.
//!
//! ```
//! use usar_world::io::source::{BareImage, load_scene};
//!
//! let scene = load_scene("rubble", 3, &BareImage::default()).unwrap();
//! assert!(!scene.victims.is_empty());
//! let err = load_scene("no/such/map.yaml", 0, &BareImage::default()).unwrap_err();
//! assert!(err.to_string().starts_with("no/such/map.yaml"));
//! ```

use super::image_map::{ImageMapOptions, read_image_map};
use crate::error::{Result, WorldError};
use crate::generate::{SceneKind, generate};
use crate::scene::Scene;
use std::path::Path;

/// How to read a bare map image, which carries no metadata (and the cell side of a MovingAI
/// map, 1 m when absent).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BareImage {
    /// Metres per pixel; required for a bare image.
    pub resolution_m: Option<f64>,
    /// Dark pixels are free (ROS `negate: 1`).
    pub negate: bool,
    pub occupied_thresh: f64,
    pub free_thresh: f64,
}

impl Default for BareImage {
    /// No resolution; the ROS `map_server` thresholds (0.65, 0.196), not negated.
    fn default() -> Self {
        let ros = ImageMapOptions::default();
        Self {
            resolution_m: None,
            negate: ros.negate,
            occupied_thresh: ros.occupied_thresh,
            free_thresh: ros.free_thresh,
        }
    }
}

impl BareImage {
    /// The image options for the bare image at `path` (an error when no resolution is set).
    pub fn options(&self, path: &Path) -> Result<ImageMapOptions> {
        let resolution_m = self.resolution_m.ok_or_else(|| {
            WorldError::invalid(
                path,
                "resolution",
                "nothing (a bare image carries none)",
                "metres per pixel, e.g. --resolution 0.05",
            )
        })?;
        Ok(ImageMapOptions {
            resolution_m,
            negate: self.negate,
            occupied_thresh: self.occupied_thresh,
            free_thresh: self.free_thresh,
            ..ImageMapOptions::default()
        })
    }
}

/// Loads the scene `spec` names (see the module documentation); `seed` is the generator's.
pub fn load_scene(spec: &str, seed: u64, image: &BareImage) -> Result<Scene> {
    let path = Path::new(spec);
    if let Ok(kind) = spec.parse::<SceneKind>()
        && !path.exists()
    {
        return Ok(generate(kind, seed));
    }
    let ext = super::extension(path);
    match ext.as_str() {
        "json" => crate::scene::read_scene(path),
        "yaml" | "yml" => super::ros::read_ros_map(path),
        "pgm" | "png" => read_image_map(path, &image.options(path)?),
        "map" => {
            let map = super::movingai::read_movingai_map(path)?;
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            map.to_scene(&name, image.resolution_m.unwrap_or(1.0))
        }
        _ if !path.exists() => Err(WorldError::io(
            path,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "no such file, and not a generator name (expected rubble, office, mall or course)",
            ),
        )),
        _ => Err(WorldError::invalid(
            path,
            "extension",
            format!("{ext:?}"),
            ".json (usar scene), .yaml (ROS map_server), .pgm/.png (map image) or .map (MovingAI)",
        )),
    }
}

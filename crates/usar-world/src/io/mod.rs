//! Importers and exporters for maps made elsewhere: ROS `map_server` (YAML + PGM/PNG), bare
//! PGM/PNG images, MovingAI `.map` grids and `.scen` scenario files; rotated ROS maps turned
//! onto the axis-aligned grid; `source`: a scene named as a user names one (file or generator).

pub mod image_map;
pub mod movingai;
pub mod ros;
pub mod rotation;
pub mod source;

/// A file's extension in lower case, or "" when it has none: formats are chosen by it.
pub fn extension(path: &std::path::Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default()
}

/// A scene output path that could not be read back as a scene: scene files end in `.json`.
#[derive(Debug, thiserror::Error)]
#[error(
    "{}: a scene file must end in .json, found {found}; the extension chooses the format when the \
     file is read back",
    path.display()
)]
pub struct NotASceneFile {
    pub path: std::path::PathBuf,
    /// What the path ends in: `.EXT` or `no extension`.
    pub found: String,
}

/// Refuses a scene output path that [`source::load_scene`] could not read back: scene files are
/// `.json` (the extension chooses the format when a file is read).
pub fn check_scene_output(path: &std::path::Path) -> Result<(), NotASceneFile> {
    let ext = extension(path);
    if ext == "json" {
        return Ok(());
    }
    Err(NotASceneFile {
        path: path.to_path_buf(),
        found: if ext.is_empty() {
            "no extension".to_string()
        } else {
            format!(".{ext}")
        },
    })
}

/// The formats a scene is exported to, each when its file is given.
#[derive(Clone, Copy, Debug, Default)]
pub struct Exports<'a> {
    /// A ROS `map_server` map: this YAML file and its image ([`ros::write_ros_map`]).
    pub ros: Option<&'a std::path::Path>,
    /// The rendered scene as PNG ([`crate::render::render_scene`], default options).
    pub png: Option<&'a std::path::Path>,
    /// The scene file (`.json`, [`crate::write_scene`]).
    pub scene_file: Option<&'a std::path::Path>,
}

impl Exports<'_> {
    /// Whether no format is asked for.
    pub fn is_empty(&self) -> bool {
        self.ros.is_none() && self.png.is_none() && self.scene_file.is_none()
    }

    /// Checks the paths before any work: the scene file must be one a loader reads back
    /// ([`check_scene_output`]).
    pub fn check(&self) -> Result<(), NotASceneFile> {
        self.scene_file.map_or(Ok(()), check_scene_output)
    }

    /// Writes `scene` to every format given, in the order ROS map, PNG, scene file, stopping
    /// at the first failure; returns the files written (a ROS map's YAML file).
    pub fn write(&self, scene: &crate::Scene) -> crate::Result<Vec<std::path::PathBuf>> {
        let mut written = Vec::new();
        if let Some(yaml) = self.ros {
            ros::write_ros_map(scene, yaml)?;
            written.push(yaml.to_path_buf());
        }
        if let Some(png) = self.png {
            crate::render::render_scene(scene, &crate::render::RenderOptions::default())
                .save_png(png)?;
            written.push(png.to_path_buf());
        }
        if let Some(file) = self.scene_file {
            crate::write_scene(scene, file)?;
            written.push(file.to_path_buf());
        }
        Ok(written)
    }
}

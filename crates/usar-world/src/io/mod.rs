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

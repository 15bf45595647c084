//! ROS `map_server` maps: a YAML file of metadata beside an occupancy image (PGM or PNG).
//!
//! ```yaml
//! image: depot.pgm          # relative to the YAML's folder unless absolute
//! mode: trinary             # optional: trinary (default), scale or raw
//! resolution: 0.05          # metres per pixel
//! origin: [0.0, 0.0, 0]     # x, y of the lower-left corner of the lower-left pixel, yaw
//! negate: 0                 # 0/1 (or false/true)
//! occupied_thresh: 0.65
//! free_thresh: 0.25
//! ```
//!
//! The thresholds always come from the YAML: with `free_thresh: 0.25` (depot) the map_saver's
//! "unknown" grey 205 (occupancy 0.196) is free, with 0.196 it is unknown. Pixels are read as in
//! [`super::image_map`]; unknown space becomes wall. A rotated map (yaw ≠ 0, e.g. `3.14`) is
//! turned on import into an axis-aligned grid ([`super::rotation::rotate_obstacles`]).
//!
//! The YAML is parsed by `serde-saphyr` (pure Rust, panic-free) under a budget: nesting deeper
//! than 32 flow collections, more than 10 000 parser events or a file past the byte limit
//! ([`crate::limits`]) is refused at once.
//!
//! [`write_ros_map`] writes a scene back as a trinary P5 PGM (0 occupied, 254 free) and its YAML.
//! Walls and furniture both become occupied pixels, so the round trip keeps which cells are
//! blocked but not what blocks them; heights, rooms, victims and start poses are not part of the
//! format and are lost.

use super::image_map::{
    ImageMapOptions, ThresholdConvention, ThresholdMode, scene_from_image_bytes,
};
use crate::atomic::write_atomic;
use crate::error::{Result, WorldError};
use crate::geometry::Point2;
use crate::scene::{Scene, obstacle};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The metadata of a `map_server` YAML file.
#[derive(Clone, Debug, PartialEq)]
pub struct RosMapMetadata {
    /// The `image` field as written (relative to the YAML's folder unless absolute).
    pub image: PathBuf,
    pub resolution_m: f64,
    /// `origin` x, y, yaw.
    pub origin: [f64; 3],
    pub negate: bool,
    pub occupied_thresh: f64,
    pub free_thresh: f64,
    pub mode: ThresholdMode,
}

impl RosMapMetadata {
    /// The image options these fields describe (ROS 1 threshold convention).
    pub fn image_options(&self) -> ImageMapOptions {
        ImageMapOptions {
            resolution_m: self.resolution_m,
            origin: Point2::new(self.origin[0], self.origin[1]),
            yaw_rad: self.origin[2],
            negate: self.negate,
            occupied_thresh: self.occupied_thresh,
            free_thresh: self.free_thresh,
            mode: self.mode,
            convention: ThresholdConvention::Ros1,
        }
    }

    /// The image path, resolved against the folder of the YAML file at `yaml_path`.
    pub fn image_path(&self, yaml_path: &Path) -> PathBuf {
        if self.image.is_absolute() {
            return self.image.clone();
        }
        match yaml_path.parent() {
            Some(dir) => dir.join(&self.image),
            None => self.image.clone(),
        }
    }
}

/// Parses and checks the text of a `map_server` YAML file; `path` names it in errors.
///
/// Required: `image`, `resolution`, `origin` (x, y, yaw), `negate`,
/// `occupied_thresh`, `free_thresh`; optional: `mode`. Other keys are ignored, as ROS does.
pub fn parse_ros_yaml(text: &str, path: &Path) -> Result<RosMapMetadata> {
    if text.trim().is_empty() {
        return Err(WorldError::syntax(
            path,
            "line 1",
            "file is empty, expected map_server YAML",
        ));
    }
    let doc: Value = serde_saphyr::from_str_with_options(text, yaml_options()).map_err(|e| {
        let location = e.location().map_or_else(
            || "line 1".to_string(),
            |l| format!("line {}, column {}", l.line(), l.column()),
        );
        // The first line of the message: the rest is a snippet of the source.
        let message = e.without_snippet().to_string();
        let message = message.lines().next().unwrap_or("invalid YAML").trim();
        let message = message.split(" at line ").next().unwrap_or(message);
        WorldError::syntax(path, location, message.to_string())
    })?;
    let Value::Object(map) = &doc else {
        return Err(WorldError::syntax(
            path,
            "line 1",
            format!(
                "expected a mapping of map_server fields (image, resolution, origin, ...), found {}",
                describe(&doc)
            ),
        ));
    };
    let field = |name: &str| -> Result<&Value> {
        map.get(name).ok_or_else(|| {
            WorldError::invalid(
                path,
                name,
                "nothing (the field is missing)",
                expected_of(name),
            )
        })
    };
    let image = match field("image")? {
        Value::String(s) if !s.trim().is_empty() => PathBuf::from(s),
        other => {
            return Err(WorldError::invalid(
                path,
                "image",
                describe(other),
                expected_of("image"),
            ));
        }
    };
    let resolution_m = number(field("resolution")?, "resolution", path)?;
    let origin = match field("origin")? {
        Value::Array(items) if items.len() == 3 => {
            let mut xyz = [0.0; 3];
            for (i, item) in items.iter().enumerate() {
                xyz[i] = number(item, &format!("origin[{i}]"), path)?;
            }
            xyz
        }
        other => {
            return Err(WorldError::invalid(
                path,
                "origin",
                describe(other),
                expected_of("origin"),
            ));
        }
    };
    let negate = match field("negate")? {
        Value::Bool(b) => *b,
        Value::Number(n) if n.as_f64() == Some(0.0) => false,
        Value::Number(n) if n.as_f64() == Some(1.0) => true,
        other => {
            return Err(WorldError::invalid(
                path,
                "negate",
                describe(other),
                expected_of("negate"),
            ));
        }
    };
    let occupied_thresh = number(field("occupied_thresh")?, "occupied_thresh", path)?;
    let free_thresh = number(field("free_thresh")?, "free_thresh", path)?;
    let mode = match map.get("mode") {
        None => ThresholdMode::Trinary,
        Some(Value::String(s)) => ThresholdMode::from_name(s).ok_or_else(|| {
            WorldError::invalid(path, "mode", format!("{s:?}"), expected_of("mode"))
        })?,
        Some(other) => {
            return Err(WorldError::invalid(
                path,
                "mode",
                describe(other),
                expected_of("mode"),
            ));
        }
    };
    let meta = RosMapMetadata {
        image,
        resolution_m,
        origin,
        negate,
        occupied_thresh,
        free_thresh,
        mode,
    };
    meta.image_options().validate(path)?;
    Ok(meta)
}

fn expected_of(field: &str) -> &'static str {
    match field {
        "image" => "the image file name (PGM or PNG), relative to the YAML's folder or absolute",
        "resolution" => "a positive number of metres per pixel",
        "origin" => "[x, y, yaw] in metres and radians",
        "negate" => "0 or 1",
        "occupied_thresh" | "free_thresh" => "an occupancy in [0, 1]",
        "mode" => "trinary, scale or raw",
        _ => "a value",
    }
}

/// A number, or a string holding one (yaml-cpp, which ROS uses, accepts both).
fn number(v: &Value, field: &str, path: &Path) -> Result<f64> {
    let parsed = match v {
        Value::Number(n) => n.as_f64(),
        Value::String(s) => s.trim().parse::<f64>().ok(),
        _ => None,
    };
    match parsed {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(WorldError::invalid(
            path,
            field,
            describe(v),
            "a finite number",
        )),
    }
}

/// A short description of a YAML value for error messages.
fn describe(v: &Value) -> String {
    match v {
        Value::Null => "nothing".to_string(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => n.to_string(),
        Value::String(s) => format!("{s:?}"),
        Value::Array(items) => format!("a list of {} items", items.len()),
        Value::Object(_) => "a mapping".to_string(),
    }
}

/// The parser's budget: a map_server file is a dozen scalars, so anything deep or long is
/// refused at once rather than parsed (100 000 nested `[` took 29 s with the old parser).
fn yaml_options() -> serde_saphyr::Options {
    serde_saphyr::options! {
        budget: serde_saphyr::budget! {
            flow_nesting_limit: 32,
            max_depth: 32,
            max_events: 10_000,
            max_aliases: 100,
            max_anchors: 100,
        },
    }
}

/// Reads a ROS `map_server` map (YAML + image) as a ground-truth scene.
///
/// The scene is named after the YAML's stem; its provenance is `import` with the YAML and image
/// file names; it has one start pose (see [`super::image_map::deepest_free_cell`]). A missing or
/// unreadable image is [`WorldError::MissingReference`] naming the field `image` and the path;
/// errors in the image itself name the image file.
pub fn read_ros_map(yaml_path: &Path) -> Result<Scene> {
    let text = crate::limits::read_text(yaml_path)?;
    let meta = parse_ros_yaml(&text, yaml_path)?;
    let image_path = meta.image_path(yaml_path);
    let bytes = crate::limits::read_file(&image_path).map_err(|e| match e {
        WorldError::Io { io, .. } => WorldError::MissingReference {
            path: yaml_path.display().to_string(),
            field: "image".to_string(),
            target: image_path.display().to_string(),
            io,
        },
        other => other,
    })?;
    let file_name = |p: &Path| {
        p.file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let name = yaml_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let detail = format!(
        "{} (ROS map_server, image {}, mode {}, occupied_thresh {}, free_thresh {})",
        file_name(yaml_path),
        file_name(&image_path),
        meta.mode.as_str(),
        meta.occupied_thresh,
        meta.free_thresh
    );
    scene_from_image_bytes(&bytes, &image_path, &meta.image_options(), name, detail)
}

/// The grey values [`write_ros_map`] writes (those of ROS `map_saver`).
pub const PGM_OCCUPIED: u8 = 0;
/// See [`PGM_OCCUPIED`].
pub const PGM_FREE: u8 = 254;

/// The trinary P5 PGM of a scene's obstacle layer: 0 where any obstacle stands, 254 on open
/// floor, top row first.
pub fn encode_pgm(scene: &Scene) -> Vec<u8> {
    let g = scene.geometry();
    let (w, h) = (g.width as usize, g.height as usize);
    let header = format!("P5\n# usar-world scene export\n{w} {h}\n255\n");
    let mut bytes = Vec::with_capacity(header.len() + w * h);
    bytes.extend_from_slice(header.as_bytes());
    for row in scene.obstacle.as_slice().chunks_exact(w.max(1)).rev() {
        bytes.extend(row.iter().map(|&o| {
            if o == obstacle::NONE {
                PGM_FREE
            } else {
                PGM_OCCUPIED
            }
        }));
    }
    bytes
}

/// The YAML text for a scene whose image is `image_name`.
pub fn encode_ros_yaml(scene: &Scene, image_name: &str) -> String {
    let g = scene.geometry();
    // JSON strings are YAML double-quoted scalars; plain names stay unquoted.
    let plain = !image_name.is_empty()
        && image_name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"._-/".contains(&b));
    let image = if plain {
        image_name.to_string()
    } else {
        serde_json::to_string(image_name).expect("a string serialises")
    };
    // `{:?}` prints the shortest text that reads back as the same f64.
    format!(
        "image: {image}\nmode: trinary\nresolution: {:?}\norigin: [{:?}, {:?}, 0.0]\nnegate: 0\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n",
        g.resolution_m, g.origin.x, g.origin.y
    )
}

/// Writes a scene as a ROS `map_server` map: `<stem>.pgm` beside `yaml_path` (trinary P5: 0
/// occupied, 254 free) and the YAML (origin [x, y, 0], negate 0, thresholds 0.65 / 0.196), both
/// atomically. Walls and furniture both become occupied.
pub fn write_ros_map(scene: &Scene, yaml_path: &Path) -> Result<()> {
    let bad_name = |why: &str| {
        WorldError::io(
            yaml_path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, why.to_string()),
        )
    };
    let stem = yaml_path
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| bad_name("expected a UTF-8 file name such as map.yaml"))?;
    let image_name = format!("{stem}.pgm");
    let image_path = yaml_path.with_file_name(&image_name);
    if image_path == yaml_path {
        return Err(bad_name(
            "the YAML path must not end in .pgm: the image is written beside it",
        ));
    }
    write_atomic(&image_path, &encode_pgm(scene))?;
    write_atomic(yaml_path, encode_ros_yaml(scene, &image_name).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn yaml_accepts_bool_negate_string_numbers_and_default_mode() {
        let text = "image: a.pgm\nresolution: '0.05'\norigin: [1, -2.5, 0]\nnegate: true\n\
                    occupied_thresh: 0.7\nfree_thresh: 0.2\n";
        let meta = parse_ros_yaml(text, Path::new("a.yaml")).unwrap();
        assert_eq!(meta.resolution_m, 0.05);
        assert_eq!(meta.origin, [1.0, -2.5, 0.0]);
        assert!(meta.negate);
        assert_eq!(meta.mode, ThresholdMode::Trinary);
        assert_eq!(
            meta.image_path(Path::new("/maps/a.yaml")),
            PathBuf::from("/maps/a.pgm")
        );
    }

    #[test]
    fn yaml_errors_name_the_field() {
        let base = "image: a.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n\
                    occupied_thresh: 0.65\nfree_thresh: 0.196\n";
        let err = |text: &str| {
            parse_ros_yaml(text, Path::new("m.yaml"))
                .unwrap_err()
                .to_string()
        };
        assert!(err(&base.replace("negate: 0", "negate: 2")).contains("field `negate`"));
        assert!(err(&base.replace("[0, 0, 0]", "[0, 0]")).contains("field `origin`"));
        assert!(err(&format!("{base}mode: fancy\n")).contains("trinary, scale or raw"));
        assert!(err(&base.replace("0.196", "0.9")).contains("less than occupied_thresh"));
        assert!(err("- just\n- a list\n").contains("expected a mapping"));
        assert!(err("image: [unclosed\n").contains("m.yaml: line"));
    }

    #[test]
    fn yaml_writer_round_trips_awkward_numbers_and_names() {
        let g = crate::GridGeometry::new(2, 1, 0.030000000000000002, Point2::new(-15.1, 1e-7));
        let scene = Scene::empty("s", g);
        let text = encode_ros_yaml(&scene, "my map: \"v2\".pgm");
        let meta = parse_ros_yaml(&text, Path::new("s.yaml")).unwrap();
        assert_eq!(meta.resolution_m, 0.030000000000000002);
        assert_eq!(meta.origin, [-15.1, 1e-7, 0.0]);
        assert_eq!(meta.image, PathBuf::from("my map: \"v2\".pgm"));
    }
}

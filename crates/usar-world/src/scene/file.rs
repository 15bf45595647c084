//! The usar scene file, version 1 (documented in `docs/scene-format.md`).
//!
//! One JSON document: readable metadata (rooms, doors, victims, start poses, ground truth) and
//! three grid layers stored as little-endian arrays, zlib-compressed and base64-encoded. Writing is
//! deterministic (the same scene gives the same bytes) and reading is lossless.

use super::{GroundTruth, Provenance, Scene};
use crate::atomic::write_atomic;
use crate::error::{Result, WorldError};
use crate::geometry::Pose2;
use crate::grid::{Grid, GridGeometry};
use base64::Engine as _;
use flate2::Compression;
use flate2::read::ZlibDecoder;
use flate2::write::ZlibEncoder;
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};
use std::path::Path;

/// The value of the `format` field of every scene file.
pub const SCENE_FORMAT: &str = "usar-scene";
/// The scene file version this build writes and reads.
pub const SCENE_VERSION: u32 = 1;

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    format: String,
    version: u32,
    name: String,
    #[serde(default)]
    provenance: Provenance,
    grid: GridGeometry,
    #[serde(default)]
    coarse_cell_m: Option<f64>,
    layers: Layers,
    #[serde(default)]
    rooms: Vec<super::Room>,
    #[serde(default)]
    doors: Vec<super::Door>,
    #[serde(default)]
    victims: Vec<super::Victim>,
    #[serde(default)]
    heat_sources: Vec<super::HeatSource>,
    #[serde(default)]
    start_poses: Vec<Pose2>,
    #[serde(default)]
    ground_truth: GroundTruth,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Layers {
    obstacle: Layer,
    floor_height_m: Layer,
    room_id: Layer,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Layer {
    dtype: String,
    encoding: String,
    data: String,
}

const ENCODING: &str = "zlib+base64";

/// Only the fields needed to recognise the file, read before everything else so that a file of
/// another version gets a version error rather than a confusing field error.
#[derive(Deserialize)]
struct Header {
    format: Option<serde_json::Value>,
    version: Option<serde_json::Value>,
}

/// Reads and validates a scene file.
pub fn read_scene(path: &Path) -> Result<Scene> {
    let text = crate::limits::read_text(path)?;
    scene_from_json(&text, path)
}

/// Writes a scene file atomically.
pub fn write_scene(scene: &Scene, path: &Path) -> Result<()> {
    write_atomic(path, scene_to_json(scene).as_bytes())
}

/// Serialises a scene to the version-1 JSON text (deterministic).
pub fn scene_to_json(scene: &Scene) -> String {
    let file = SceneFile {
        format: SCENE_FORMAT.to_string(),
        version: SCENE_VERSION,
        name: scene.name.clone(),
        provenance: scene.provenance.clone(),
        grid: *scene.geometry(),
        coarse_cell_m: scene.coarse_cell_m,
        layers: Layers {
            obstacle: encode_layer("u8", scene.obstacle.as_slice()),
            floor_height_m: encode_layer(
                "f32le",
                &scene
                    .floor_height_m
                    .as_slice()
                    .iter()
                    .flat_map(|h| h.to_le_bytes())
                    .collect::<Vec<_>>(),
            ),
            room_id: encode_layer(
                "u16le",
                &scene
                    .room_id
                    .as_slice()
                    .iter()
                    .flat_map(|r| r.to_le_bytes())
                    .collect::<Vec<_>>(),
            ),
        },
        rooms: scene.rooms.clone(),
        doors: scene.doors.clone(),
        victims: scene.victims.clone(),
        heat_sources: scene.heat_sources.clone(),
        start_poses: scene.start_poses.clone(),
        ground_truth: scene.ground_truth.clone(),
    };
    let mut text = serde_json::to_string_pretty(&file).expect("scene serialises to JSON");
    text.push('\n');
    text
}

/// Parses and validates scene JSON; `path` is only used in error messages.
pub fn scene_from_json(text: &str, path: &Path) -> Result<Scene> {
    if text.trim().is_empty() {
        return Err(WorldError::syntax(
            path,
            "line 1",
            "file is empty, expected a usar-scene JSON document",
        ));
    }
    let header: Header = serde_json::from_str(text).map_err(|e| json_error(path, &e))?;
    match header.format.as_ref().and_then(|f| f.as_str()) {
        Some(SCENE_FORMAT) => {}
        Some(other) => {
            return Err(WorldError::invalid(
                path,
                "format",
                format!("{other:?}"),
                format!("{SCENE_FORMAT:?}"),
            ));
        }
        None => {
            return Err(WorldError::invalid(
                path,
                "format",
                "nothing",
                format!("{SCENE_FORMAT:?} (is this a usar scene file?)"),
            ));
        }
    }
    match header.version.as_ref().and_then(|v| v.as_u64()) {
        Some(v) if v == u64::from(SCENE_VERSION) => {}
        found => {
            return Err(WorldError::UnsupportedVersion {
                path: path.display().to_string(),
                format: SCENE_FORMAT.to_string(),
                found: found.map_or_else(|| format!("{:?}", header.version), |v| v.to_string()),
                expected: SCENE_VERSION.to_string(),
            });
        }
    }
    let file: SceneFile = serde_json::from_str(text).map_err(|e| json_error(path, &e))?;
    let g = file.grid;
    super::validate::check_geometry(&g, path)?;
    let n = g.len();
    let obstacle = decode_layer(&file.layers.obstacle, "obstacle", "u8", 1, n, path)?;
    let heights = decode_layer(
        &file.layers.floor_height_m,
        "floor_height_m",
        "f32le",
        4,
        n,
        path,
    )?;
    let rooms = decode_layer(&file.layers.room_id, "room_id", "u16le", 2, n, path)?;
    let scene = Scene {
        name: file.name,
        provenance: file.provenance,
        obstacle: Grid::from_vec(g, obstacle).expect("length checked"),
        floor_height_m: Grid::from_vec(
            g,
            heights
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect(),
        )
        .expect("length checked"),
        room_id: Grid::from_vec(
            g,
            rooms
                .chunks_exact(2)
                .map(|b| u16::from_le_bytes([b[0], b[1]]))
                .collect(),
        )
        .expect("length checked"),
        rooms: file.rooms,
        doors: file.doors,
        victims: file.victims,
        heat_sources: file.heat_sources,
        start_poses: file.start_poses,
        coarse_cell_m: file.coarse_cell_m,
        ground_truth: file.ground_truth,
    };
    super::validate::validate_scene(&scene, path)?;
    Ok(scene)
}

fn json_error(path: &Path, e: &serde_json::Error) -> WorldError {
    let message = e.to_string();
    // serde_json appends " at line L column C"; keep the message without it.
    let message = message
        .split(" at line ")
        .next()
        .unwrap_or(&message)
        .to_string();
    WorldError::syntax(
        path,
        format!("line {}, column {}", e.line(), e.column()),
        message,
    )
}

fn encode_layer(dtype: &str, bytes: &[u8]) -> Layer {
    let mut enc = ZlibEncoder::new(Vec::new(), Compression::new(6));
    enc.write_all(bytes).expect("writing to a Vec cannot fail");
    let compressed = enc.finish().expect("writing to a Vec cannot fail");
    Layer {
        dtype: dtype.to_string(),
        encoding: ENCODING.to_string(),
        data: base64::engine::general_purpose::STANDARD.encode(compressed),
    }
}

fn decode_layer(
    layer: &Layer,
    name: &str,
    dtype: &str,
    bytes_per_cell: usize,
    cells: usize,
    path: &Path,
) -> Result<Vec<u8>> {
    let field = |f: &str| format!("layers.{name}.{f}");
    if layer.dtype != dtype {
        return Err(WorldError::invalid(
            path,
            field("dtype"),
            format!("{:?}", layer.dtype),
            format!("{dtype:?}"),
        ));
    }
    if layer.encoding != ENCODING {
        return Err(WorldError::invalid(
            path,
            field("encoding"),
            format!("{:?}", layer.encoding),
            format!("{ENCODING:?}"),
        ));
    }
    let compressed = base64::engine::general_purpose::STANDARD
        .decode(layer.data.trim())
        .map_err(|e| {
            WorldError::invalid(
                path,
                field("data"),
                format!("invalid base64 ({e})"),
                "base64 text",
            )
        })?;
    // `cells` is within the cell limit (checked with the geometry), so this is bounded.
    let expected = cells * bytes_per_cell;
    let mut bytes = Vec::with_capacity(expected);
    ZlibDecoder::new(compressed.as_slice())
        .take(expected as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| {
            WorldError::invalid(
                path,
                field("data"),
                format!("corrupt zlib stream ({e})"),
                "zlib-compressed data",
            )
        })?;
    if bytes.len() != expected {
        return Err(WorldError::invalid(
            path,
            field("data"),
            format!("{} bytes", bytes.len()),
            format!("{expected} bytes (grid.width × grid.height × {bytes_per_cell})"),
        ));
    }
    Ok(bytes)
}

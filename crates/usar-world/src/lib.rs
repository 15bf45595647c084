//! `usar-world` is the ground truth of a USAR scene: the flat grids and geometry every other crate
//! uses, the 2.5-D scene model with its semantic layer, victims and ground-truth annotations, its
//! versioned file format, seeded scene generators, importers and exporters for ROS `map_server`
//! and MovingAI maps, a PNG renderer, and the coarse cell view of paper 000.
//!
//! Nothing here knows about robots, sensors or controllers.
//!
//! ```
//! use usar_world::{Grid, GridGeometry, Point2, Scene, scene_from_json, scene_to_json};
//!
//! let geometry = GridGeometry::new(40, 30, 0.1, Point2::new(0.0, 0.0));
//! let mut scene = Scene::empty("box", geometry);
//! scene.start_poses.push(usar_world::Pose2::new(2.0, 1.5, 0.0));
//! let text = scene_to_json(&scene);
//! let back = scene_from_json(&text, "box.json".as_ref()).unwrap();
//! assert_eq!(back, scene);
//! assert!((back.reachable_area_m2() - 12.0).abs() < 1e-9);
//! ```

mod atomic;
pub mod cellview;
mod error;
pub mod generate;
pub mod geometry;
pub mod grid;
pub mod io;
pub mod limits;
pub mod ray;
pub mod render;
pub mod scene;
mod toml_error;

pub use self::atomic::{partial_path, write_atomic};
pub use self::error::{Result, WorldError};
pub use self::geometry::{BodyToWorld, Point2, Pose2, Rect, normalize_angle};
pub use self::grid::{Cell, Grid, GridGeometry, NEIGHBORS8};
pub use self::ray::{CellRect, GridRay, RayVisitor, Visit};
pub use self::scene::{
    Door, GroundTruth, HeatSource, Junction, JunctionKind, Provenance, Room, RoomId, RoomLabel,
    RoomSizeThresholds, Scene, SceneInfo, TerrainFeature, Victim, obstacle, read_scene,
    scene_from_json, scene_to_json, write_scene,
};
pub use self::toml_error::toml_error_line;

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! What the `usar btm` commands write and show, for any program: a map built in place into its
//! SQLite file ([`build_to_file`]), its drawing by extension ([`save_drawing`]), the robot's
//! trajectory as CSV ([`trajectory_csv`]), the sizes of the map's forms beside the occupancy grid
//! ([`Sizes`]), the JSON view of a map ([`describe`]) and the kinds this version does not know
//! ([`unknown_kinds`]).

use crate::build::{BuildConfig, BuildError, BuildOutcome, TrajectorySample, build_btm_observed};
use crate::{Btm, BtmError, BtmStore, exchange, render, wire};
use serde::Serialize;
use serde_json::json;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use usar_sim::RobotSpec;
use usar_world::{Point2, Scene, WorldError};

/// Why a map could not be built into its file or drawn.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The map's database could not be created.
    #[error(transparent)]
    Store(#[from] BtmError),
    /// The build was refused (its configuration, the scene).
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The PNG drawing could not be saved.
    #[error(transparent)]
    Draw(WorldError),
    /// A file could not be written, renamed or measured.
    #[error(transparent)]
    Write(WorldError),
    /// The partial file could not be removed or renamed, or the output measured.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

impl ReportError {
    /// Whether the error comes from the input (the scene, the configuration, an output path
    /// the drawing cannot be saved to) rather than from the work itself.
    pub fn is_input(&self) -> bool {
        matches!(self, Self::Store(_) | Self::Build(_) | Self::Draw(_))
    }
}

/// The file a build writes while the robot drives: `out` with `.partial` appended.
pub use usar_world::partial_path;

/// Builds a BTM ([`build_btm_observed`]) into the SQLite file `out`: the map is written to
/// [`partial_path`] as the robot drives (one left by an earlier run is removed first), and
/// renamed to `out` when the build ends; a refused build leaves no file.
pub fn build_to_file(
    scene: Arc<Scene>,
    robot: RobotSpec,
    config: &BuildConfig,
    seed: u64,
    out: &Path,
    on_progress: &mut dyn FnMut(&crate::build::BuildProgress<'_>),
) -> Result<BuildOutcome, ReportError> {
    let partial = partial_path(out);
    if partial.exists() {
        std::fs::remove_file(&partial)?;
    }
    let store = BtmStore::create(&partial)?;
    let built = build_btm_observed(scene, robot, config, seed, Some(&store), on_progress);
    drop(store);
    let outcome = match built {
        Ok(o) => o,
        Err(e) => {
            let _ = std::fs::remove_file(&partial);
            return Err(e.into());
        }
    };
    std::fs::rename(&partial, out)?;
    Ok(outcome)
}

/// Draws the map to `path`: SVG (the map alone) when the extension says so, else PNG over the
/// scene if one is given, with the robot's `trace`.
pub fn save_drawing(
    btm: &Btm,
    scene: Option<&Scene>,
    trace: &[Point2],
    path: &Path,
) -> Result<(), ReportError> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
    {
        usar_world::write_atomic(path, render::to_svg(btm).as_bytes()).map_err(ReportError::Write)
    } else {
        render::draw_traced(btm, scene, trace)
            .save_png(path)
            .map_err(ReportError::Draw)
    }
}

/// The trajectory as CSV: time, estimated and true pose, locomotion mode, contact (0/1).
pub fn trajectory_csv(trajectory: &[TrajectorySample]) -> String {
    let mut csv = String::from(
        "time_s,est_x_m,est_y_m,est_theta_rad,true_x_m,true_y_m,true_theta_rad,mode,contact\n",
    );
    for t in trajectory {
        csv += &format!(
            "{:.2},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{},{}\n",
            t.time_s,
            t.estimated.x,
            t.estimated.y,
            t.estimated.theta,
            t.truth.x,
            t.truth.y,
            t.truth.theta,
            t.mode.as_str(),
            u8::from(t.contact)
        );
    }
    csv
}

/// The sizes in bytes of a map's three forms beside the occupancy grid of the same floor (one
/// byte per cell, a ROS map_server PGM's raster), and how many times smaller each form is.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sizes {
    pub btm_binary: u64,
    pub btm_json: u64,
    pub btm_sqlite: u64,
    pub grid_over_binary: f64,
    pub grid_over_json: f64,
    pub grid_over_sqlite: f64,
    pub occupancy_grid: u64,
}

impl Sizes {
    /// Measures `btm` as `.btmb` and JSON, its SQLite file at `sqlite`, against a grid of
    /// `grid_cells` cells.
    pub fn measure(btm: &Btm, sqlite: &Path, grid_cells: usize) -> Result<Self, ReportError> {
        let occupancy_grid = grid_cells as u64;
        let btm_sqlite = std::fs::metadata(sqlite)?.len();
        let btm_json = exchange::to_json_value(btm).to_string().len() as u64;
        let btm_binary = wire::encode(btm).len() as u64;
        let over = |n: u64| occupancy_grid as f64 / n as f64;
        Ok(Sizes {
            btm_binary,
            btm_json,
            btm_sqlite,
            grid_over_binary: over(btm_binary),
            grid_over_json: over(btm_json),
            grid_over_sqlite: over(btm_sqlite),
            occupancy_grid,
        })
    }
}

/// Every node with its Table I fields (links, angles) and every link, with the nodes counted by
/// kind and the links by whether they were searched.
pub fn describe(btm: &Btm) -> serde_json::Value {
    let by_kind = crate::build::count_nodes(btm);
    let searched = btm.links.iter().filter(|l| l.searched).count();
    json!({
        "nodes_by_kind": by_kind,
        "links_searched": searched,
        "links_unsearched": btm.links.len() - searched,
        "nodes": exchange::node_rows(btm),
        "links": btm.links,
    })
}

/// [`describe`] with the build's outcome: why and when it stopped, the distance driven, the
/// collisions, the largest position error and the [`Sizes`].
pub fn describe_build(outcome: &BuildOutcome, sizes: &Sizes) -> serde_json::Value {
    let mut v = describe(&outcome.btm);
    let extra = json!({
        "stop": outcome.stop,
        "time_s": outcome.time_s,
        "distance_m": outcome.distance_m,
        "collisions": outcome.collisions,
        "max_position_error_m": outcome.max_position_error_m,
        "bytes": sizes,
    });
    for (k, val) in extra.as_object().expect("object") {
        v[k] = val.clone();
    }
    v
}

/// Nodes of kinds this version does not know (kept as read), counted by kind.
pub fn unknown_kinds(btm: &Btm) -> BTreeMap<&str, usize> {
    let mut unknown = BTreeMap::new();
    for n in btm
        .nodes
        .iter()
        .filter(|n| !crate::model::kind::is_known(&n.kind))
    {
        *unknown.entry(n.kind.as_str()).or_default() += 1;
    }
    unknown
}

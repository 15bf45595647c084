//! A summary of a scene's ground truth, as printed by `usar scene info --json`.

use super::{Door, GroundTruth, HeatSource, Provenance, RoomId, RoomLabel, Scene, Victim};
use crate::geometry::Pose2;
use crate::grid::GridGeometry;
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Clone, Debug, Serialize)]
pub struct RoomInfo {
    pub id: RoomId,
    pub label: RoomLabel,
    pub area_m2: f64,
    pub doors: usize,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub intersecting_corridors: Vec<RoomId>,
}

/// Everything a test or a user may want to know about a scene without loading its layers.
#[derive(Clone, Debug, Serialize)]
pub struct SceneInfo {
    pub name: String,
    pub provenance: Provenance,
    pub grid: GridGeometry,
    pub width_m: f64,
    pub height_m: f64,
    pub coarse_cell_m: Option<f64>,
    /// Obstacle-free area, m².
    pub free_area_m2: f64,
    /// Area reachable from the first start pose through obstacle-free cells, m².
    pub reachable_area_m2: f64,
    pub rooms: Vec<RoomInfo>,
    /// Per label: number of rooms, area and share of the labelled area (paper 002 Tables 2–3).
    pub labels: BTreeMap<RoomLabel, LabelShare>,
    pub doors: Vec<Door>,
    pub victims: Vec<Victim>,
    pub heat_sources: Vec<HeatSource>,
    pub start_poses: Vec<Pose2>,
    pub junctions: Vec<super::Junction>,
    pub features: Vec<super::TerrainFeature>,
    pub min_floor_height_m: f32,
    pub max_floor_height_m: f32,
}

#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct LabelShare {
    pub rooms: usize,
    pub area_m2: f64,
    pub share: f64,
}

impl Scene {
    pub fn info(&self) -> SceneInfo {
        let g = *self.geometry();
        let cell_area = g.cell_area_m2();
        let mut room_cells: BTreeMap<RoomId, usize> = BTreeMap::new();
        for (&r, &o) in self.room_id.as_slice().iter().zip(self.obstacle.as_slice()) {
            if r != 0 && o == super::obstacle::NONE {
                *room_cells.entry(r).or_default() += 1;
            }
        }
        let rooms: Vec<RoomInfo> = self
            .rooms
            .iter()
            .map(|r| RoomInfo {
                id: r.id,
                label: r.label,
                area_m2: room_cells.get(&r.id).copied().unwrap_or(0) as f64 * cell_area,
                doors: r.door_ids.len(),
                intersecting_corridors: r.intersecting_corridors.clone(),
            })
            .collect();
        let mut labels: BTreeMap<RoomLabel, LabelShare> = BTreeMap::new();
        for r in &rooms {
            let e = labels.entry(r.label).or_default();
            e.rooms += 1;
            e.area_m2 += r.area_m2;
        }
        let labelled: f64 = labels.values().map(|l| l.area_m2).sum();
        for l in labels.values_mut() {
            l.share = if labelled > 0.0 {
                l.area_m2 / labelled
            } else {
                0.0
            };
        }
        let free = self
            .obstacle
            .as_slice()
            .iter()
            .filter(|&&o| o == super::obstacle::NONE)
            .count();
        let heights = self.floor_height_m.as_slice();
        let GroundTruth {
            junctions,
            features,
        } = self.ground_truth.clone();
        let (width_m, height_m) = g.extent_m();
        SceneInfo {
            name: self.name.clone(),
            provenance: self.provenance.clone(),
            grid: g,
            width_m,
            height_m,
            coarse_cell_m: self.coarse_cell_m,
            free_area_m2: free as f64 * cell_area,
            reachable_area_m2: self.reachable_area_m2(),
            rooms,
            labels,
            doors: self.doors.clone(),
            victims: self.victims.clone(),
            heat_sources: self.heat_sources.clone(),
            start_poses: self.start_poses.clone(),
            junctions,
            features,
            min_floor_height_m: heights.iter().copied().fold(f32::INFINITY, f32::min),
            max_floor_height_m: heights.iter().copied().fold(f32::NEG_INFINITY, f32::max),
        }
    }
}

/// A scene in a few numbers, as `usar scene gen|import --json` prints it for the file it wrote.
/// Fields are in alphabetical order, as that output has always had them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// The file the scene was written to (or read from).
    pub file: String,
    /// Grid rows.
    pub height: u32,
    pub name: String,
    pub resolution_m: f64,
    pub rooms: usize,
    pub start_poses: usize,
    pub victims: usize,
    /// Grid columns.
    pub width: u32,
}

impl Scene {
    /// The scene's [`Summary`], naming `file` (the file it was written to or read from).
    pub fn summary(&self, file: &std::path::Path) -> Summary {
        let g = self.geometry();
        Summary {
            file: file.display().to_string(),
            height: g.height,
            name: self.name.clone(),
            resolution_m: g.resolution_m,
            rooms: self.rooms.len(),
            start_poses: self.start_poses.len(),
            victims: self.victims.len(),
            width: g.width,
        }
    }
}

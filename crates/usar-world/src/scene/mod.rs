//! The ground-truth scene: a 2.5-D grid world with a semantic layer, victims and start poses.

mod file;
mod ground_truth;
mod info;
mod refine;
mod semantic;
mod validate;
mod victim;

pub use self::file::{
    SCENE_FORMAT, SCENE_VERSION, read_scene, scene_from_json, scene_to_json, write_scene,
};
pub use self::ground_truth::{GroundTruth, Junction, JunctionKind, TerrainFeature};
pub use self::info::{RoomInfo, SceneInfo, Summary};
pub use self::semantic::{Door, Room, RoomId, RoomLabel, RoomSizeThresholds};
pub use self::validate::{MAX_ABS_COORD_M, MAX_GRID_SIDE, RESOLUTION_RANGE_M};
pub(crate) use self::validate::{check_extent, check_resolution};
pub use self::victim::{HeatSource, Victim};

use crate::geometry::Pose2;
use crate::grid::{Cell, Grid, GridGeometry};
use serde::{Deserialize, Serialize};

/// What stands on a fine cell of the obstacle layer.
pub mod obstacle {
    /// Nothing: the floor (whatever its height) is exposed.
    pub const NONE: u8 = 0;
    /// A structural wall: full height, blocks motion and every sensor.
    pub const WALL: u8 = 1;
    /// Furniture or a fallen slab: full height for the robots' purposes, like a wall.
    pub const FURNITURE: u8 = 2;
}

/// Where a scene came from, kept in the file so that a scene can be regenerated.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Provenance {
    /// Generator kind (`office`, `rubble`, ...) or `import`.
    pub source: String,
    /// Seed of the generator, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Free text (imported file name, generator parameters).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub detail: String,
}

/// The ground truth of a disaster scene.
///
/// Three layers share one [`GridGeometry`] (default 0.1 m cells): `obstacle` (see [`obstacle`]),
/// `floor_height_m` (floor height of each cell; slopes, steps, rubble piles and drops live here)
/// and `room_id` (0 outside rooms, otherwise an id of `rooms`).
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub name: String,
    pub provenance: Provenance,
    pub obstacle: Grid<u8>,
    pub floor_height_m: Grid<f32>,
    pub room_id: Grid<RoomId>,
    pub rooms: Vec<Room>,
    pub doors: Vec<Door>,
    pub victims: Vec<Victim>,
    pub heat_sources: Vec<HeatSource>,
    pub start_poses: Vec<Pose2>,
    /// Side of the coarse cells of the paper-000 cell view, metres, if the scene defines one.
    pub coarse_cell_m: Option<f64>,
    pub ground_truth: GroundTruth,
}

impl Scene {
    /// An empty, flat, wall-less scene of the given geometry.
    pub fn empty(name: impl Into<String>, geometry: GridGeometry) -> Self {
        Self {
            name: name.into(),
            provenance: Provenance::default(),
            obstacle: Grid::filled(geometry, obstacle::NONE),
            floor_height_m: Grid::filled(geometry, 0.0),
            room_id: Grid::filled(geometry, 0),
            rooms: Vec::new(),
            doors: Vec::new(),
            victims: Vec::new(),
            heat_sources: Vec::new(),
            start_poses: Vec::new(),
            coarse_cell_m: None,
            ground_truth: GroundTruth::default(),
        }
    }

    pub fn geometry(&self) -> &GridGeometry {
        self.obstacle.geometry()
    }

    /// True where a wall or furniture stands (or outside the grid).
    #[inline]
    pub fn is_obstacle(&self, cell: Cell) -> bool {
        self.obstacle.get(cell).is_none_or(|&o| o != obstacle::NONE)
    }

    pub fn room(&self, id: RoomId) -> Option<&Room> {
        self.rooms.iter().find(|r| r.id == id)
    }

    /// Label of the room a cell belongs to, if any.
    pub fn label_at(&self, cell: Cell) -> Option<RoomLabel> {
        let id = *self.room_id.get(cell)?;
        (id != 0).then(|| self.room(id).map(|r| r.label)).flatten()
    }

    /// Cells reachable from `start` through obstacle-free cells (4-connected flood fill), as a
    /// mask. This is the scene's *reachable area*, independent of any robot's size or climbing
    /// ability.
    pub fn reachable_mask(&self, start: Cell) -> Grid<bool> {
        let g = *self.geometry();
        let mut mask = Grid::filled(g, false);
        if self.is_obstacle(start) {
            return mask;
        }
        let mut stack = vec![start];
        mask[start] = true;
        while let Some(c) = stack.pop() {
            for (dc, dr) in crate::grid::NEIGHBORS8[..4].iter().copied() {
                let n = Cell::new(c.col + dc, c.row + dr);
                if g.contains(n) && !mask[n] && !self.is_obstacle(n) {
                    mask[n] = true;
                    stack.push(n);
                }
            }
        }
        mask
    }

    /// Reachable area from the first start pose, m² (0 when the scene has no start pose).
    pub fn reachable_area_m2(&self) -> f64 {
        let Some(start) = self.start_poses.first() else {
            return 0.0;
        };
        let g = self.geometry();
        let mask = self.reachable_mask(g.world_to_cell(start.position()));
        mask.as_slice().iter().filter(|&&m| m).count() as f64 * g.cell_area_m2()
    }
}

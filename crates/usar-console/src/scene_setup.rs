//! The mission's scene: a generated rubble floor by default. Paper 002's team needs a room
//! layer (semantic labels); a scene without one gets four zones, its quadrants, labelled by
//! their floor area as the generators label rooms.

use usar_world::generate::{RubbleParams, generate_rubble};
use usar_world::{Grid, Room, RoomId, RoomLabel, RoomSizeThresholds, Scene};

/// The default scene: a rubble floor of paper 000 §VI (20 × 20 cells, victims, heat sources).
pub fn default_scene(seed: u64) -> Scene {
    generate_rubble(seed, &RubbleParams::default())
}

/// Adds the quadrant zones when `scene` has no labelled room.
pub fn with_zones(mut scene: Scene) -> Scene {
    if !scene.rooms.is_empty() {
        return scene;
    }
    let g = *scene.geometry();
    let (w, h) = (g.width, g.height);
    let zone = |c: u32, r: u32| -> RoomId { 1 + u16::from(c >= w / 2) + 2 * u16::from(r >= h / 2) };
    let mut ids = Vec::with_capacity(g.len());
    for r in 0..h {
        for c in 0..w {
            ids.push(zone(c, r));
        }
    }
    let mut area = [0.0f64; 4];
    for (k, &id) in ids.iter().enumerate() {
        if scene.obstacle.as_slice()[k] == 0 {
            area[usize::from(id - 1)] += g.cell_area_m2();
        }
    }
    if let Some(grid) = Grid::from_vec(g, ids) {
        scene.room_id = grid;
        scene.rooms = (1..=4u16)
            .map(|id| Room {
                id,
                label: RoomLabel::for_room_area(
                    area[usize::from(id - 1)],
                    RoomSizeThresholds::default(),
                ),
                door_ids: Vec::new(),
                intersecting_corridors: Vec::new(),
            })
            .collect();
    }
    scene
}

/// The scene with its start poses rotated so that pose `k` comes first.
pub fn starting_at(scene: &Scene, k: usize) -> Scene {
    let mut s = scene.clone();
    if k < s.start_poses.len() {
        s.start_poses.rotate_left(k);
    }
    s
}

/// The display code of a room label (see [`crate::snapshot::MapView::labels`]).
pub fn label_code(label: Option<RoomLabel>) -> u8 {
    match label {
        None => 0,
        Some(RoomLabel::Corridor) => 1,
        Some(RoomLabel::SmallRoom) => 2,
        Some(RoomLabel::MediumRoom) => 3,
        Some(RoomLabel::BigRoom) => 4,
    }
}

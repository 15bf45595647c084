//! The mission's scene: a generated rubble floor by default. Paper 002's team needs a room
//! layer (semantic labels); a scene without one gets four zones, its quadrants, labelled by
//! their floor area as the generators label rooms.

use usar_sim::{compute_blocked, footprint_cells};
use usar_team::TeamConfig;
use usar_world::generate::{RubbleParams, generate_rubble};
use usar_world::{Grid, Pose2, Room, RoomId, RoomLabel, RoomSizeThresholds, Scene};

/// The default scene: a rubble floor of paper 000 §VI (20 × 20 cells, victims, heat sources)
/// with cells of `cell_area_m2` (see [`crate::MissionConfig::floor_cell_m2`]).
pub fn default_scene(seed: u64, cell_area_m2: f64) -> Scene {
    generate_rubble(
        seed,
        &RubbleParams {
            cell_area_m2,
            ..RubbleParams::default()
        },
    )
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

/// The scene with start poses for the team: those of the scene its robot fits on (the MAXQ
/// robot's, the first, last), then, if the team is larger, free poses on a 1 m lattice nearest
/// to the first start.
pub fn with_team_starts(scene: &Scene, config: &TeamConfig) -> Scene {
    // Free for the robot: every cell under its footprint inside the grid and not blocked for
    // it (the test a simulation makes when a robot is added, with no other robot about).
    let spec = &config.robot;
    let blocked = compute_blocked(scene, spec);
    let g = *scene.geometry();
    let fits = |pose: Pose2| {
        footprint_cells(&g, pose, spec.length_m, spec.width_m, |c| {
            blocked.get(c).is_some_and(|&b| !b)
        })
    };
    let mut poses: Vec<Pose2> = scene
        .start_poses
        .iter()
        .skip(1)
        .chain(scene.start_poses.first())
        .copied()
        .filter(|&p| fits(p))
        .collect();
    if poses.len() < config.robots {
        let (w, h) = g.extent_m();
        let anchor = scene.start_poses.first().map_or(g.origin, |p| p.position());
        let mut lattice = Vec::new();
        let mut y = g.origin.y + 0.5;
        while y < g.origin.y + h {
            let mut x = g.origin.x + 0.5;
            while x < g.origin.x + w {
                lattice.push(Pose2::new(x, y, 0.0));
                x += 1.0;
            }
            y += 1.0;
        }
        lattice.sort_by(|a, b| {
            a.position()
                .distance(anchor)
                .total_cmp(&b.position().distance(anchor))
        });
        for p in lattice {
            if poses.len() >= config.robots {
                break;
            }
            if poses
                .iter()
                .all(|q| q.position().distance(p.position()) > 0.9)
                && fits(p)
            {
                poses.push(p);
            }
        }
    }
    let mut s = scene.clone();
    s.start_poses = poses;
    s
}

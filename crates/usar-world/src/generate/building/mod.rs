//! Paper 002 §4.1 building floors: the `office` (mostly small and medium rooms, Table 2) and the
//! `mall` (few very big rooms and shops along wide galleries, Table 3).
//!
//! A floor is generated in five steps, all in whole grid cells so that areas are exact:
//!
//! 1. [`layout`]: the corridor skeleton — east–west corridors across the whole floor, north–south
//!    pieces joining them (T junctions, crossings), optional ring corridors along the end walls
//!    (corners) and stubs to the exterior walls (dead ends). The corridor width is tuned inside
//!    [`BuildingParams::corridor_width_m`] to give the corridor share of the label table.
//! 2. [`rooms`]: rooms in the rows between the corridors, sized so that the room labels take the
//!    table's area shares, and their doors (≥ 1 m wide; through rooms, big halls and rooms by a
//!    cross corridor get two or more).
//! 3. Painting: every cell is a wall (0.2 m) unless it is a corridor, a room or a door opening.
//! 4. [`furniture`]: desks, shelves and partitions that never block a door or split a room.
//! 5. [`occupants`]: victims, heat sources that are not victims, start poses.
//!
//! Semantic layer: every free cell of the floor belongs to a room or a corridor. Each straight
//! corridor is one corridor room: every east–west corridor, and every north–south piece between
//! two east–west corridors (or between one and an exterior wall). The square where two corridors
//! meet belongs to the east–west corridor. Door openings (the cells cut through the wall) belong
//! to `rooms[0]` of the door, which is always a room, never a corridor: for a door between a
//! room and a corridor it is the room; between two rooms it is the back room (the one reached
//! through the other) or the western one of two neighbours. Room labels come from the free floor
//! area after furniture, door openings included, through [`RoomLabel::for_room_area`] with
//! [`BuildingParams::thresholds`].

mod furniture;
mod layout;
mod occupants;
mod params;
mod rooms;

// `AreaRange`, `LabelShares` and `LengthRange` are the types of public fields of
// `BuildingParams`; `generate/mod.rs` re-exports them next to it.
pub use self::params::{AreaRange, BuildingParams, LabelShares, LengthRange};

use self::layout::{CellRect, CellScale, Skeleton};
use self::rooms::{DoorPlan, Opening, RoomPlan};
use crate::geometry::Point2;
use crate::grid::{Cell, GridGeometry};
use crate::scene::{Door, Junction, Provenance, Room, RoomId, RoomLabel, Scene, obstacle};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;

/// Generates a paper-002 office floor (provenance source `office`).
pub fn generate_office(seed: u64, params: &BuildingParams) -> Scene {
    generate_floor("office", seed, params)
}

/// Generates a paper-002 mall floor (provenance source `mall`).
pub fn generate_mall(seed: u64, params: &BuildingParams) -> Scene {
    generate_floor("mall", seed, params)
}

/// Expected room area of a skeleton: the rows minus the walls between rooms and the furniture.
struct RoomAreaEstimate {
    mean_room_cells: f64,
    furniture_fraction: f64,
    wall: f64,
}

impl RoomAreaEstimate {
    fn new(p: &BuildingParams, scale: &CellScale) -> Self {
        let f = p.label_shares.room_fractions();
        let means = [
            p.small_room_m2.mean_m2(),
            p.medium_room_m2.mean_m2(),
            p.big_room_m2.mean_m2(),
        ];
        // Area-weighted shares → mean area of a room drawn by count.
        let per_area: f64 = f.iter().zip(means).map(|(f, m)| f / m).sum();
        let mean_m2 = if per_area > 0.0 {
            1.0 / per_area
        } else {
            means[1]
        };
        Self {
            mean_room_cells: mean_m2 / scale.cell_area_m2(),
            furniture_fraction: p.furniture_fraction,
            wall: f64::from(scale.wall),
        }
    }

    /// Room cells before furniture.
    fn room_cells(&self, s: &Skeleton) -> f64 {
        s.segments
            .iter()
            .map(|g| {
                let area = g.rect.area() as f64;
                let depth = f64::from(g.rect.height());
                let walls = (area / self.mean_room_cells - 1.0).max(0.0) * self.wall * depth;
                area - walls
            })
            .sum()
    }

    fn corridor_share(&self, s: &Skeleton) -> f64 {
        let corridor = s.corridor_area_cells() as f64;
        let rooms = self.room_cells(s) * (1.0 - self.furniture_fraction);
        corridor / (corridor + rooms).max(1.0)
    }
}

fn generate_floor(source: &str, seed: u64, params: &BuildingParams) -> Scene {
    let p = params.sanitized();
    let scale = CellScale::new(&p);
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let estimate = RoomAreaEstimate::new(&p, &scale);
    let sk = layout::plan_skeleton(&p, &scale, &mut rng, |s| estimate.corridor_share(s));
    let room_plans = rooms::plan_rooms(&sk, &p, &scale, estimate.room_cells(&sk), &mut rng);
    let door_plans = rooms::plan_doors(&sk, &room_plans, &p, &scale, &mut rng);

    let geometry = GridGeometry::new(
        scale.width as u32,
        scale.height as u32,
        p.resolution_m,
        Point2::new(0.0, 0.0),
    );
    let mut scene = Scene::empty(format!("{source}-{seed}"), geometry);
    let corridor_id = |i: usize| (i + 1) as RoomId;
    let room_id = |i: usize| (sk.corridors.len() + i + 1) as RoomId;
    paint(
        &mut scene,
        &sk,
        &room_plans,
        &door_plans,
        corridor_id,
        room_id,
    );
    furniture::furnish(
        &mut scene,
        &room_plans,
        &door_plans,
        sk.wall,
        &p,
        &scale,
        &mut rng,
    );

    // Labels from the free area of each room.
    let total_ids = sk.corridors.len() + room_plans.len() + 1;
    let mut free_cells = vec![0u64; total_ids];
    for (&id, &o) in scene
        .room_id
        .as_slice()
        .iter()
        .zip(scene.obstacle.as_slice())
    {
        if o == obstacle::NONE {
            free_cells[usize::from(id)] += 1;
        }
    }
    let cell_area = scale.cell_area_m2();
    let room_labels: Vec<RoomLabel> = (0..room_plans.len())
        .map(|i| {
            let area = free_cells[usize::from(room_id(i))] as f64 * cell_area;
            RoomLabel::for_room_area(area, p.thresholds)
        })
        .collect();
    semantic_layer(
        &mut scene,
        &sk,
        &room_plans,
        &door_plans,
        &room_labels,
        corridor_id,
        room_id,
    );

    let labelled_m2 = free_cells[1..].iter().sum::<u64>() as f64 * cell_area;
    let rooms_with_labels: Vec<(CellRect, RoomLabel)> = room_plans
        .iter()
        .map(|r| r.rect)
        .zip(room_labels.iter().copied())
        .collect();
    scene.victims = occupants::place_victims(&scene, &rooms_with_labels, labelled_m2, &p, &mut rng);
    scene.heat_sources = occupants::place_heat_sources(
        &scene,
        &sk,
        &rooms_with_labels,
        &scene.victims,
        &p,
        &mut rng,
    );
    scene.start_poses = occupants::place_start_poses(&scene, &sk, &p, &mut rng);
    scene.ground_truth.junctions = sk
        .junctions
        .iter()
        .map(|j| Junction {
            kind: j.kind,
            position: Point2::new(j.x * p.resolution_m, j.y * p.resolution_m),
        })
        .collect();
    scene.provenance = Provenance {
        source: source.to_string(),
        seed: Some(seed),
        detail: format!(
            "{} m × {} m at {} m; {} east-west corridors and {} cross-corridor pieces {:.2} m \
             wide; {} rooms; walls {:.2} m; target shares corridor/small/medium/big \
             {:.3}/{:.3}/{:.3}/{:.3}",
            p.width_m,
            p.height_m,
            p.resolution_m,
            sk.east_west_count,
            sk.corridors.len() - sk.east_west_count,
            f64::from(sk.corridor_width) * p.resolution_m,
            room_plans.len(),
            f64::from(sk.wall) * p.resolution_m,
            p.label_shares.corridor,
            p.label_shares.small_room,
            p.label_shares.medium_room,
            p.label_shares.big_room,
        ),
    };
    scene
}

/// Paints walls everywhere, then carves corridors, rooms and door openings.
fn paint(
    scene: &mut Scene,
    sk: &Skeleton,
    rooms: &[RoomPlan],
    doors: &[DoorPlan],
    corridor_id: impl Fn(usize) -> RoomId,
    room_id: impl Fn(usize) -> RoomId,
) {
    scene.obstacle.as_mut_slice().fill(obstacle::WALL);
    let mut carve = |rect: &CellRect, id: RoomId| {
        for row in rect.y0..rect.y1 {
            for col in rect.x0..rect.x1 {
                let c = Cell::new(col, row);
                scene.obstacle[c] = obstacle::NONE;
                scene.room_id[c] = id;
            }
        }
    };
    for (i, c) in sk.corridors.iter().enumerate() {
        carve(&c.rect, corridor_id(i));
    }
    for (i, r) in rooms.iter().enumerate() {
        carve(&r.rect, room_id(i));
    }
    for d in doors {
        carve(&d.rect, room_id(d.owner));
    }
}

/// Fills `rooms` and `doors` of the scene from the plan.
fn semantic_layer(
    scene: &mut Scene,
    sk: &Skeleton,
    rooms: &[RoomPlan],
    doors: &[DoorPlan],
    labels: &[RoomLabel],
    corridor_id: impl Fn(usize) -> RoomId,
    room_id: impl Fn(usize) -> RoomId,
) {
    let res = scene.geometry().resolution_m;
    let other_id = |o: Opening| match o {
        Opening::Room(i) => room_id(i),
        Opening::Corridor(i) => corridor_id(i),
    };
    scene.doors = doors
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let (cx, cy) = d.rect.centre();
            let along = match d.side_of(&rooms[d.owner].rect) {
                Some(layout::Side::West | layout::Side::East) => d.rect.height(),
                _ => d.rect.width(),
            };
            Door {
                id: i as u32,
                position: Point2::new(cx * res, cy * res),
                width_m: f64::from(along) * res,
                rooms: [room_id(d.owner), other_id(d.other)],
            }
        })
        .collect();
    let mut all: Vec<Room> = Vec::with_capacity(sk.corridors.len() + rooms.len());
    for (i, c) in sk.corridors.iter().enumerate() {
        let id = corridor_id(i);
        let mut intersecting: Vec<RoomId> = c.meets.iter().map(|&j| corridor_id(j)).collect();
        intersecting.sort_unstable();
        intersecting.dedup();
        all.push(Room {
            id,
            label: RoomLabel::Corridor,
            door_ids: door_ids_of(&scene.doors, id),
            intersecting_corridors: intersecting,
        });
    }
    for (i, label) in labels.iter().enumerate() {
        let id = room_id(i);
        all.push(Room {
            id,
            label: *label,
            door_ids: door_ids_of(&scene.doors, id),
            intersecting_corridors: Vec::new(),
        });
    }
    scene.rooms = all;
}

fn door_ids_of(doors: &[Door], id: RoomId) -> Vec<u32> {
    doors
        .iter()
        .filter(|d| d.rooms.contains(&id))
        .map(|d| d.id)
        .collect()
}

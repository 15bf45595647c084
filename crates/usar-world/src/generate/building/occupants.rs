//! Who and what is on the floor: victims spread over the room labels, heat sources that are not
//! victims (radiators on exterior walls, a small fire), and the robots' start poses in a
//! corridor at the west end.

use super::layout::{CellRect, Skeleton};
use super::params::BuildingParams;
use crate::geometry::{Point2, Pose2};
use crate::grid::Cell;
use crate::scene::{HeatSource, RoomLabel, Scene, Victim};
use rand::Rng;
use rand::seq::SliceRandom;
use rand_pcg::Pcg64Mcg;

/// Skin temperature range of a victim, °C (paper 000 §IV-A-3 uses the heat signature of exposed
/// skin; 30–37 °C covers a cooled, partly covered body to a healthy one).
const VICTIM_HEAT_C: (f64, f64) = (30.0, 37.0);
/// Body area a thermal camera could see, m² (a curled-up person ≈ 0.2, lying flat ≈ 0.7).
const VICTIM_SIZE_M2: (f64, f64) = (0.2, 0.7);
/// Largest share of a victim covered by debris on an intact building floor.
const VICTIM_MAX_BURIED: f64 = 0.6;
/// Least distance between two victims (and between a victim and a fire), metres.
const VICTIM_SPACING_M: f64 = 2.0;
/// Surface temperature of a hot-water radiator, °C, and its front area, m².
const RADIATOR_HEAT_C: (f64, f64) = (45.0, 65.0);
const RADIATOR_SIZE_M2: (f64, f64) = (0.4, 0.8);
/// A small fire (a waste bin, a cable fire), °C and m².
const FIRE_HEAT_C: (f64, f64) = (300.0, 600.0);
const FIRE_SIZE_M2: (f64, f64) = (0.3, 1.0);

/// Distance from `p` to the nearest obstacle cell (as a square), capped at `cap_m`.
pub(super) fn obstacle_distance_m(scene: &Scene, p: Point2, cap_m: f64) -> f64 {
    let g = scene.geometry();
    let r = g.resolution_m;
    let centre = g.world_to_cell(p);
    let k = (cap_m / r).ceil() as i32 + 1;
    let mut best = cap_m;
    for dy in -k..=k {
        for dx in -k..=k {
            let c = Cell::new(centre.col + dx, centre.row + dy);
            if !scene.is_obstacle(c) {
                continue;
            }
            let q = g.cell_center(c);
            let ex = ((p.x - q.x).abs() - r / 2.0).max(0.0);
            let ey = ((p.y - q.y).abs() - r / 2.0).max(0.0);
            best = best.min(ex.hypot(ey));
        }
    }
    best
}

fn cell_in(rect: &CellRect, rng: &mut Pcg64Mcg) -> Cell {
    Cell::new(
        rng.random_range(rect.x0..rect.x1),
        rng.random_range(rect.y0..rect.y1),
    )
}

/// Victims: one per `area_per_victim_m2` of labelled area within `victims`, in rooms (never
/// corridors), taking the small, medium and big labels in turn, each at least
/// `robot_clearance_m` from any obstacle and `VICTIM_SPACING_M` from the others.
pub(super) fn place_victims(
    scene: &Scene,
    rooms: &[(CellRect, RoomLabel)],
    labelled_area_m2: f64,
    p: &BuildingParams,
    rng: &mut Pcg64Mcg,
) -> Vec<Victim> {
    let wanted = ((labelled_area_m2 / p.area_per_victim_m2).round() as usize)
        .clamp(p.victims.0, p.victims.1);
    let mut labels: Vec<RoomLabel> = [
        RoomLabel::SmallRoom,
        RoomLabel::MediumRoom,
        RoomLabel::BigRoom,
    ]
    .into_iter()
    .filter(|l| rooms.iter().any(|r| r.1 == *l))
    .collect();
    if labels.is_empty() {
        return Vec::new();
    }
    let turn = rng.random_range(0..labels.len());
    labels.rotate_left(turn);
    let g = *scene.geometry();
    let mut victims: Vec<Victim> = Vec::new();
    let mut used_rooms: Vec<usize> = Vec::new();
    let mut label_turn = 0;
    let mut failures = 0;
    while victims.len() < wanted && failures < labels.len() {
        let label = labels[label_turn % labels.len()];
        label_turn += 1;
        let mut candidates: Vec<usize> =
            (0..rooms.len()).filter(|&i| rooms[i].1 == label).collect();
        candidates.shuffle(rng);
        // Rooms without a victim first.
        candidates.sort_by_key(|i| used_rooms.contains(i));
        let mut found = None;
        'rooms: for &i in &candidates {
            for _ in 0..60 {
                let q = g.cell_center(cell_in(&rooms[i].0, rng));
                if obstacle_distance_m(scene, q, p.robot_clearance_m) >= p.robot_clearance_m
                    && victims
                        .iter()
                        .all(|v| v.position.distance(q) >= VICTIM_SPACING_M)
                {
                    found = Some((i, q));
                    break 'rooms;
                }
            }
        }
        let Some((i, position)) = found else {
            failures += 1;
            continue;
        };
        failures = 0;
        used_rooms.push(i);
        let buried_fraction = if rng.random_bool(0.4) {
            0.0
        } else {
            rng.random_range(0.0..=VICTIM_MAX_BURIED)
        };
        victims.push(Victim {
            id: victims.len() as u32,
            position,
            heat_c: rng.random_range(VICTIM_HEAT_C.0..=VICTIM_HEAT_C.1),
            visible_size_m2: rng.random_range(VICTIM_SIZE_M2.0..=VICTIM_SIZE_M2.1),
            buried_fraction,
        });
    }
    victims
}

/// Heat sources that are not victims: with even odds one small fire in a room, the rest
/// radiators under the exterior walls of rooms.
pub(super) fn place_heat_sources(
    scene: &Scene,
    sk: &Skeleton,
    rooms: &[(CellRect, RoomLabel)],
    victims: &[Victim],
    p: &BuildingParams,
    rng: &mut Pcg64Mcg,
) -> Vec<HeatSource> {
    let wanted = rng.random_range(p.heat_sources.0..=p.heat_sources.1);
    let g = *scene.geometry();
    let mut out: Vec<HeatSource> = Vec::new();
    if rooms.is_empty() {
        return out;
    }
    if wanted > 0 && rng.random_bool(0.5) {
        for _ in 0..200 {
            let room = &rooms[rng.random_range(0..rooms.len())].0;
            let q = g.cell_center(cell_in(room, rng));
            if obstacle_distance_m(scene, q, p.robot_clearance_m) >= p.robot_clearance_m
                && victims
                    .iter()
                    .all(|v| v.position.distance(q) >= VICTIM_SPACING_M)
            {
                out.push(HeatSource {
                    id: 0,
                    position: q,
                    heat_c: rng.random_range(FIRE_HEAT_C.0..=FIRE_HEAT_C.1),
                    size_m2: rng.random_range(FIRE_SIZE_M2.0..=FIRE_SIZE_M2.1),
                    kind: "fire".to_string(),
                });
                break;
            }
        }
    }
    // Rooms along an exterior wall, with the free row of cells just inside that wall.
    let (w, h, tw) = (sk.width, sk.height, sk.wall);
    let mut exterior: Vec<CellRect> = Vec::new();
    for (r, _) in rooms {
        if r.y0 == tw {
            exterior.push(CellRect::new(r.x0, r.y0, r.x1, r.y0 + 1));
        }
        if r.y1 == h - tw {
            exterior.push(CellRect::new(r.x0, r.y1 - 1, r.x1, r.y1));
        }
        if r.x0 == tw {
            exterior.push(CellRect::new(r.x0, r.y0, r.x0 + 1, r.y1));
        }
        if r.x1 == w - tw {
            exterior.push(CellRect::new(r.x1 - 1, r.y0, r.x1, r.y1));
        }
    }
    let mut attempts = 0;
    while out.len() < wanted && !exterior.is_empty() && attempts < 500 {
        attempts += 1;
        let strip = exterior[rng.random_range(0..exterior.len())];
        let c = cell_in(&strip, rng);
        let q = g.cell_center(c);
        if scene.is_obstacle(c) || out.iter().any(|s| s.position.distance(q) < 3.0) {
            continue;
        }
        out.push(HeatSource {
            id: out.len() as u32,
            position: q,
            heat_c: rng.random_range(RADIATOR_HEAT_C.0..=RADIATOR_HEAT_C.1),
            size_m2: rng.random_range(RADIATOR_SIZE_M2.0..=RADIATOR_SIZE_M2.1),
            kind: "radiator".to_string(),
        });
    }
    out
}

/// `p.start_poses` poses in lanes along an east–west corridor, starting just past its west end
/// and heading east, `start_pose_spacing_m` apart and `start_pose_clearance_m` from obstacles.
/// The corridor is drawn at random; if it is too short, the next ones are used too.
pub(super) fn place_start_poses(
    scene: &Scene,
    sk: &Skeleton,
    p: &BuildingParams,
    rng: &mut Pcg64Mcg,
) -> Vec<Pose2> {
    let res = p.resolution_m;
    let spacing = p.start_pose_spacing_m;
    let clearance = p.start_pose_clearance_m;
    let count = sk.east_west_count.max(1).min(sk.corridors.len());
    let mut poses: Vec<Pose2> = Vec::new();
    if count == 0 {
        return poses;
    }
    let first = rng.random_range(0..count);
    for k in (0..count).map(|i| (first + i) % count) {
        let r = sk.corridors[k].rect;
        let width_m = f64::from(r.height()) * res;
        let lane_room = width_m - 2.0 * (clearance + res);
        let lanes = if lane_room <= 0.0 {
            1
        } else {
            ((lane_room / spacing).floor() as usize + 1).min(3)
        };
        let (_, yc) = r.centre();
        let yc = yc * res;
        let mut x = f64::from(r.x0) * res + f64::from(sk.corridor_width) * res + 0.6;
        let x_end = f64::from(r.x1) * res - 0.5;
        while poses.len() < p.start_poses && x < x_end {
            for lane in 0..lanes {
                if poses.len() >= p.start_poses {
                    break;
                }
                let offset = (lane as f64 - (lanes as f64 - 1.0) / 2.0) * spacing;
                let q = Point2::new(x, yc + offset);
                let free = !scene.is_obstacle(scene.geometry().world_to_cell(q));
                if free
                    && obstacle_distance_m(scene, q, clearance) >= clearance
                    && poses
                        .iter()
                        .all(|s| s.position().distance(q) >= spacing - 1e-9)
                {
                    poses.push(Pose2::new(q.x, q.y, 0.0));
                }
            }
            x += spacing;
        }
        if poses.len() >= p.start_poses {
            break;
        }
    }
    poses
}

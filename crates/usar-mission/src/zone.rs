//! The rescuer's zone: a square of the scene's cell grid (paper 000's 0.914 m cells) in the
//! floor's largest room or around its start pose; with `rubble`, the room gets a rubble arena
//! laid on its free floor; and where the rescue team puts the robot down in it.

use crate::MissionError;
use crate::RescuerPart;
use crate::rescuer::bad;
use usar_sim::RobotSpec;
use usar_world::cellview::{CellView, CellViewParams};
use usar_world::generate::lay_rubble;
use usar_world::{Cell, GridGeometry, Point2, Pose2, RoomId, RoomLabel, Scene};

/// Where the rescuer's zone is (`[rescuer] zone`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ZoneAt {
    LargestRoom,
    Start,
}

/// Where the robot is put down in a rubble zone (`[rescuer] put_down`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PutDown {
    /// The paper's: the rubble arena's own start cell (the default).
    ArenaStart,
    /// The variant developed while looking at report floors.
    OpenTurnable,
}

impl ZoneAt {
    pub(crate) fn of(part: &RescuerPart) -> Result<Self, MissionError> {
        match part.zone.as_str() {
            "largest-room" => Ok(Self::LargestRoom),
            "start" => Ok(Self::Start),
            other => Err(bad(
                "zone",
                format!("found `{other}`, expected largest-room or start"),
            )),
        }
    }
}

impl PutDown {
    pub(crate) fn of(part: &RescuerPart) -> Result<Self, MissionError> {
        match part.put_down.as_str() {
            "arena-start" => Ok(Self::ArenaStart),
            "open-turnable" => Ok(Self::OpenTurnable),
            other => Err(bad(
                "put_down",
                format!("found `{other}`, expected arena-start or open-turnable"),
            )),
        }
    }
}

/// The zone: `cells` × `cells` of the scene's cell grid `view` centred on `start`'s cell
/// (clipped to the floor), and the pose the robot is put down at — its cell's centre, facing
/// the nearest quarter heading.
pub(crate) fn zone(view: &CellView, start: Pose2, cells: u32) -> (GridGeometry, Pose2) {
    let g = &view.geometry;
    let at = g.world_to_cell(start.position());
    let half = i64::from(cells / 2);
    let clamp = |v: i64, len: u32| v.clamp(0, i64::from(len.saturating_sub(cells)).max(0));
    let c0 = clamp(i64::from(at.col) - half, g.width);
    let r0 = clamp(i64::from(at.row) - half, g.height);
    let (w, h) = (cells.min(g.width), cells.min(g.height));
    let origin = Point2::new(
        g.origin.x + c0 as f64 * g.resolution_m,
        g.origin.y + r0 as f64 * g.resolution_m,
    );
    let zone = GridGeometry::new(w, h, g.resolution_m, origin);
    let centre = g.cell_center(Cell::new(at.col, at.row));
    let quarter = (start.theta / std::f64::consts::FRAC_PI_2).round();
    (
        zone,
        Pose2::new(centre.x, centre.y, quarter * std::f64::consts::FRAC_PI_2),
    )
}

/// The largest room of `scene` that is not a corridor, and its cells' centroid.
fn largest_room(scene: &Scene) -> Option<(RoomId, Point2)> {
    let g = scene.geometry();
    let mut cells = vec![(0usize, 0.0, 0.0); scene.rooms.len() + 1];
    for (i, &id) in scene.room_id.as_slice().iter().enumerate() {
        if let Some(e) = cells.get_mut(usize::from(id)) {
            let p = g.cell_center(g.cell_of_index(i));
            *e = (e.0 + 1, e.1 + p.x, e.2 + p.y);
        }
    }
    scene
        .rooms
        .iter()
        .filter(|r| r.label != RoomLabel::Corridor)
        .filter_map(|r| {
            let &(n, x, y) = cells.get(usize::from(r.id))?;
            (n > 0).then(|| (n, r.id, Point2::new(x / n as f64, y / n as f64)))
        })
        .max_by_key(|&(n, id, _)| (n, std::cmp::Reverse(id)))
        .map(|(_, id, c)| (id, c))
}

/// The rescuer's zone on `scene` (cells of the scene's cell grid `view`) and where it is put
/// down, as `part` says; with `rubble`, the zone's room gets its rubble arena (generated from
/// `seed`) first. `start` is the scene's start pose for it.
pub(crate) fn place(
    scene: &mut Scene,
    view: &CellView,
    part: &RescuerPart,
    spec: &RobotSpec,
    start: Pose2,
    seed: u64,
) -> Result<(GridGeometry, Pose2), MissionError> {
    let put_down_rule = PutDown::of(part)?;
    match ZoneAt::of(part)? {
        ZoneAt::Start => Ok(zone(view, start, part.zone_cells)),
        ZoneAt::LargestRoom => {
            let Some((room, centre)) = largest_room(scene) else {
                return Err(bad(
                    "zone",
                    "found `largest-room`, but the floor has no room that is not a corridor".into(),
                ));
            };
            let (zone, put_down) = zone(view, Pose2::new(centre.x, centre.y, 0.0), part.zone_cells);
            if !part.rubble {
                return Ok((zone, put_down));
            }
            // Piles and ramps are painted on a tenth of a cell (as in paper 000's arenas); a
            // coarser floor is refined first, or its grid would square them into walls.
            let factor = (scene.geometry().resolution_m / (zone.resolution_m / 10.0)).round();
            if factor > 1.0 {
                *scene = scene.refined(factor as u32);
            }
            let g = *scene.geometry();
            let allowed: Vec<bool> = (0..g.len())
                .map(|i| scene.room_id.as_slice()[i] == room && scene.obstacle.as_slice()[i] == 0)
                .collect();
            let laid = lay_rubble(
                scene,
                zone.origin,
                (zone.width, zone.height),
                zone.resolution_m,
                seed ^ 0x2B_B1E,
                |c| allowed[g.index(c)],
            );
            let view = CellView::from_scene(scene, &CellViewParams::default());
            let chosen = match put_down_rule {
                PutDown::ArenaStart => laid.start,
                PutDown::OpenTurnable => put_down_in(&view, scene, &zone, spec),
            };
            Ok((zone, chosen.unwrap_or(put_down)))
        }
    }
}

/// The variant `open-turnable` of where the robot is put down in its zone, looking at the scene
/// as people on site do: on open floor where it can turn (no fine cell its body could not stand on within
/// its circumscribed radius of the cell's centre), in the largest part of the zone a climbing
/// robot can reach from there (nearest the zone's centre among equals), facing east. The robot
/// is told nothing of it.
fn put_down_in(
    view: &CellView,
    scene: &Scene,
    zone: &GridGeometry,
    spec: &RobotSpec,
) -> Option<Pose2> {
    let g = *scene.geometry();
    let blocked = usar_sim::compute_blocked(scene, spec);
    let radius_m = spec.circumscribed_radius_m();
    let turns_freely = |c: Cell| {
        let p = zone.cell_center(c);
        let (lo, hi) = (
            g.world_to_cell(Point2::new(p.x - radius_m, p.y - radius_m)),
            g.world_to_cell(Point2::new(p.x + radius_m, p.y + radius_m)),
        );
        (lo.row..=hi.row).all(|row| {
            (lo.col..=hi.col).all(|col| {
                let f = Cell::new(col, row);
                g.cell_center(f).distance(p) > radius_m || blocked.get(f) == Some(&false)
            })
        })
    };
    let (w, h) = (zone.width as i32, zone.height as i32);
    let in_view = |c: Cell| view.cell_of(zone.cell_center(c));
    let victim_at: Vec<Cell> = scene
        .victims
        .iter()
        .filter_map(|v| view.cell_of(v.position))
        .collect();
    let passable = |c: Cell| {
        in_view(c).is_some_and(|v| {
            view.terrain_class(v).is_passable_terrain(true) && !victim_at.contains(&v)
        })
    };
    let mut component = vec![usize::MAX; (w * h) as usize];
    let mut sizes = Vec::new();
    for start in (0..w * h).map(|i| Cell::new(i % w, i / w)) {
        if component[(start.row * w + start.col) as usize] != usize::MAX || !passable(start) {
            continue;
        }
        let id = sizes.len();
        let mut stack = vec![start];
        component[(start.row * w + start.col) as usize] = id;
        let mut size = 0;
        while let Some(c) = stack.pop() {
            size += 1;
            for (dc, dr) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let n = Cell::new(c.col + dc, c.row + dr);
                if n.col >= 0 && n.row >= 0 && n.col < w && n.row < h {
                    let k = (n.row * w + n.col) as usize;
                    if component[k] == usize::MAX && passable(n) {
                        component[k] = id;
                        stack.push(n);
                    }
                }
            }
        }
        sizes.push(size);
    }
    let centre = Point2::new(f64::from(w) / 2.0, f64::from(h) / 2.0);
    (0..w * h)
        .map(|i| Cell::new(i % w, i / w))
        .filter(|&c| {
            component[(c.row * w + c.col) as usize] != usize::MAX
                && in_view(c)
                    .is_some_and(|v| view.terrain_class(v) == usar_world::cellview::CellClass::Open)
                && turns_freely(c)
        })
        .min_by(|&a, &b| {
            let size = |c: Cell| sizes[component[(c.row * w + c.col) as usize]];
            let off = |c: Cell| {
                Point2::new(f64::from(c.col) + 0.5, f64::from(c.row) + 0.5).distance(centre)
            };
            size(b).cmp(&size(a)).then(off(a).total_cmp(&off(b)))
        })
        .map(|c| {
            let p = zone.cell_center(c);
            Pose2::new(p.x, p.y, 0.0)
        })
}

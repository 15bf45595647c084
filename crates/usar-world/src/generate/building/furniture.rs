//! Furniture: desks, shelves along the walls and free-standing partitions (the "short line
//! segments" of paper 002 Fig. 4), placed so that no door is blocked and no room is cut in two
//! for a robot of radius `robot_clearance_m`.
//!
//! Every piece is checked before it is kept: the obstacles around the room are inflated by the
//! robot radius and the room's free cells (with its door openings) must still form a single
//! connected region, so that every free cell a robot fits on can be reached from every door.
//! No furniture stands in a keep-out zone `door_clearance_m` deep behind each door.

use super::layout::{CellRect, CellScale, Side};
use super::params::BuildingParams;
use super::rooms::{DoorPlan, Opening, RoomPlan};
use crate::grid::Cell;
use crate::scene::{RoomLabel, Scene, obstacle};
use rand::Rng;
use rand_pcg::Pcg64Mcg;

/// Scratch buffers reused across rooms (no allocation per cell or per piece).
struct Scratch {
    blocked: Vec<u16>,
    seen: Vec<u32>,
    stamp: u32,
    stack: Vec<usize>,
}

/// The inflation disc: offsets whose centre lies within the robot radius of a cell centre.
fn disc(radius_cells: f64) -> Vec<(i32, i32)> {
    let k = radius_cells.floor() as i32;
    let r2 = radius_cells * radius_cells + 1e-9;
    let mut out = Vec::new();
    for dy in -k..=k {
        for dx in -k..=k {
            if f64::from(dx * dx + dy * dy) <= r2 {
                out.push((dx, dy));
            }
        }
    }
    out
}

/// The local window of one room: its rectangle grown by the wall and the inflation radius.
struct Window {
    rect: CellRect,
}

impl Window {
    fn index(&self, col: i32, row: i32) -> Option<usize> {
        self.rect
            .contains(col, row)
            .then(|| ((row - self.rect.y0) * self.rect.width() + (col - self.rect.x0)) as usize)
    }
}

/// Furnishes every room of the plan. Returns the number of furniture cells placed.
pub(super) fn furnish(
    scene: &mut Scene,
    rooms: &[RoomPlan],
    doors: &[DoorPlan],
    wall: i32,
    p: &BuildingParams,
    scale: &CellScale,
    rng: &mut Pcg64Mcg,
) -> usize {
    let offsets = disc(p.robot_clearance_m / scale.resolution_m);
    let reach = offsets.iter().map(|o| o.0.abs()).max().unwrap_or(0);
    let mut scratch = Scratch {
        blocked: Vec::new(),
        seen: Vec::new(),
        stamp: 0,
        stack: Vec::new(),
    };
    let mut placed = 0;
    let (gw, gh) = (
        scene.geometry().width as i32,
        scene.geometry().height as i32,
    );
    for (i, room) in rooms.iter().enumerate() {
        // The furniture never moves a room into a smaller label: it leaves at least the area of
        // the label's lower threshold free (door openings only add to that).
        let area_m2 = room.rect.area() as f64 * scale.cell_area_m2();
        let lower_m2 = match RoomLabel::for_room_area(area_m2, p.thresholds) {
            RoomLabel::BigRoom => p.thresholds.medium_below_m2,
            RoomLabel::MediumRoom => p.thresholds.small_below_m2,
            _ => 0.0,
        };
        let spare = ((area_m2 - lower_m2) / scale.cell_area_m2()).floor() as i64 - 1;
        let budget =
            ((room.rect.area() as f64 * p.furniture_fraction).floor() as i64).min(spare * 4 / 5);
        if budget <= 0 {
            continue;
        }
        let my_doors: Vec<&DoorPlan> = doors
            .iter()
            .filter(|d| d.owner == i || d.other == Opening::Room(i))
            .collect();
        let keep_out: Vec<CellRect> = my_doors
            .iter()
            .filter_map(|d| keep_out_zone(d, &room.rect, p, scale, reach))
            .collect();
        let window = Window {
            rect: room.rect.expanded(wall + reach).clipped(gw, gh),
        };
        let n = window.rect.area() as usize;
        scratch.blocked.clear();
        scratch.blocked.resize(n, 0);
        if scratch.seen.len() < n {
            scratch.seen.resize(n, 0);
        }
        for row in window.rect.y0..window.rect.y1 {
            for col in window.rect.x0..window.rect.x1 {
                if scene.obstacle[Cell::new(col, row)] != obstacle::NONE {
                    stamp(&mut scratch.blocked, &window, &offsets, col, row, 1);
                }
            }
        }
        let walkable = |scene: &Scene, col: i32, row: i32| {
            let inside =
                room.rect.contains(col, row) || my_doors.iter().any(|d| d.rect.contains(col, row));
            inside && scene.obstacle[Cell::new(col, row)] == obstacle::NONE
        };
        if !connected(scene, &window, &mut scratch, &walkable) {
            continue; // cannot happen for an empty rectangular room; never make it worse
        }
        let mut used: i64 = 0;
        let attempts = 12 + (budget / 10).min(200) as usize;
        for _ in 0..attempts {
            if used >= budget {
                break;
            }
            let Some(piece) = draw_piece(&room.rect, p, scale, rng) else {
                continue;
            };
            if piece.area() + used > budget + budget / 4
                || keep_out.iter().any(|k| k.intersects(&piece))
                || cells(&piece).any(|(c, r)| scene.obstacle[Cell::new(c, r)] != obstacle::NONE)
            {
                continue;
            }
            for (c, r) in cells(&piece) {
                scene.obstacle[Cell::new(c, r)] = obstacle::FURNITURE;
                stamp(&mut scratch.blocked, &window, &offsets, c, r, 1);
            }
            if connected(scene, &window, &mut scratch, &walkable) {
                used += piece.area();
                placed += piece.area() as usize;
            } else {
                for (c, r) in cells(&piece) {
                    scene.obstacle[Cell::new(c, r)] = obstacle::NONE;
                    stamp(&mut scratch.blocked, &window, &offsets, c, r, -1);
                }
            }
        }
    }
    placed
}

fn cells(r: &CellRect) -> impl Iterator<Item = (i32, i32)> + use<> {
    let r = *r;
    (r.y0..r.y1).flat_map(move |row| (r.x0..r.x1).map(move |col| (col, row)))
}

/// Adds `delta` to the blocked count of every window cell within the disc around (col, row).
fn stamp(blocked: &mut [u16], w: &Window, offsets: &[(i32, i32)], col: i32, row: i32, delta: i32) {
    for &(dx, dy) in offsets {
        if let Some(i) = w.index(col + dx, row + dy) {
            blocked[i] = (i32::from(blocked[i]) + delta).max(0) as u16;
        }
    }
}

/// True when the walkable, unblocked cells of the window form one 4-connected region.
fn connected(
    scene: &Scene,
    w: &Window,
    s: &mut Scratch,
    walkable: &impl Fn(&Scene, i32, i32) -> bool,
) -> bool {
    s.stamp = s.stamp.wrapping_add(1);
    if s.stamp == 0 {
        s.seen.iter_mut().for_each(|v| *v = 0);
        s.stamp = 1;
    }
    let open = |s: &Scratch, col: i32, row: i32| {
        w.index(col, row).is_some_and(|i| s.blocked[i] == 0) && walkable(scene, col, row)
    };
    let mut total = 0usize;
    let mut first = None;
    for row in w.rect.y0..w.rect.y1 {
        for col in w.rect.x0..w.rect.x1 {
            if open(s, col, row) {
                total += 1;
                first.get_or_insert((col, row));
            }
        }
    }
    let Some((c0, r0)) = first else { return false };
    let width = w.rect.width();
    let start = w.index(c0, r0).unwrap_or(0);
    s.seen[start] = s.stamp;
    s.stack.clear();
    s.stack.push(start);
    let mut reached = 0usize;
    while let Some(i) = s.stack.pop() {
        reached += 1;
        let (col, row) = (w.rect.x0 + i as i32 % width, w.rect.y0 + i as i32 / width);
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (nc, nr) = (col + dx, row + dy);
            if let Some(j) = w.index(nc, nr)
                && s.seen[j] != s.stamp
                && open(s, nc, nr)
            {
                s.seen[j] = s.stamp;
                s.stack.push(j);
            }
        }
    }
    reached == total
}

/// The furniture-free zone inside `room` behind door `d`: `door_clearance_m` deep, wider than
/// the door by the inflation radius and a margin on each side.
fn keep_out_zone(
    d: &DoorPlan,
    room: &CellRect,
    p: &BuildingParams,
    scale: &CellScale,
    reach: i32,
) -> Option<CellRect> {
    let depth = scale.cells(p.door_clearance_m);
    let pad = reach + scale.cells(0.3);
    let r = &d.rect;
    let zone = match d.side_of(room)? {
        Side::North => CellRect::new(r.x0 - pad, room.y1 - depth, r.x1 + pad, room.y1),
        Side::South => CellRect::new(r.x0 - pad, room.y0, r.x1 + pad, room.y0 + depth),
        Side::West => CellRect::new(room.x0, r.y0 - pad, room.x0 + depth, r.y1 + pad),
        Side::East => CellRect::new(room.x1 - depth, r.y0 - pad, room.x1, r.y1 + pad),
    };
    Some(zone)
}

/// A random piece of furniture inside `room`: a shelf against a wall (0.3–0.5 m deep), a
/// free-standing partition (one cell thin) or a desk (0.6–0.8 m deep).
fn draw_piece(
    room: &CellRect,
    p: &BuildingParams,
    scale: &CellScale,
    rng: &mut Pcg64Mcg,
) -> Option<CellRect> {
    let len_lo = scale.cells(p.furniture_length_m.min_m);
    let len_hi = scale.cells(p.furniture_length_m.max_m).max(len_lo);
    let kind = rng.random_range(0..10);
    let (thick, along_wall) = match kind {
        0..=4 => (rng.random_range(scale.cells(0.3)..=scale.cells(0.5)), true),
        5..=7 => (1, false),
        _ => (rng.random_range(scale.cells(0.6)..=scale.cells(0.8)), false),
    };
    let len = rng.random_range(len_lo..=len_hi);
    let horizontal = rng.random_bool(0.5);
    let (pw, ph) = if horizontal {
        (len, thick)
    } else {
        (thick, len)
    };
    if pw >= room.width() || ph >= room.height() {
        return None;
    }
    let x = rng.random_range(room.x0..=room.x1 - pw);
    let y = rng.random_range(room.y0..=room.y1 - ph);
    let rect = if along_wall {
        // Push the shelf against the nearer wall across its thickness.
        if horizontal {
            let y = if y - room.y0 < room.y1 - (y + ph) {
                room.y0
            } else {
                room.y1 - ph
            };
            CellRect::new(x, y, x + pw, y + ph)
        } else {
            let x = if x - room.x0 < room.x1 - (x + pw) {
                room.x0
            } else {
                room.x1 - pw
            };
            CellRect::new(x, y, x + pw, y + ph)
        }
    } else {
        CellRect::new(x, y, x + pw, y + ph)
    };
    Some(rect)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_of_three_cells_has_29_offsets() {
        assert_eq!(disc(3.0).len(), 29);
        assert_eq!(disc(3.5).len(), 37);
        assert_eq!(disc(0.0), vec![(0, 0)]);
    }
}

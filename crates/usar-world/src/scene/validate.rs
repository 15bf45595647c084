//! Checks a scene's values; every error names the field and says what was expected.

use super::{Scene, obstacle};
use crate::error::{Result, WorldError};
use crate::geometry::Point2;
use crate::grid::GridGeometry;
use std::collections::BTreeSet;
use std::path::Path;

/// Largest grid side accepted (cells): 50 km at 0.1 m, far beyond any building.
pub const MAX_GRID_SIDE: u32 = 500_000;

/// Cell sides accepted, metres: 1 mm to 100 m. Outside it areas overflow to infinity or
/// vanish, so a mistyped `1e300` would give `null` areas far downstream.
pub const RESOLUTION_RANGE_M: std::ops::RangeInclusive<f64> = 0.001..=100.0;
/// Largest |x| or |y| of a map's origin and far corner, metres (1 000 km): beyond it a cell's
/// position is lost to rounding and coverage comes out wrong without an error.
pub const MAX_ABS_COORD_M: f64 = 1.0e6;

/// Checks a cell side against [`RESOLUTION_RANGE_M`].
pub(crate) fn check_resolution(resolution_m: f64, field: &str, path: &Path) -> Result<()> {
    if !RESOLUTION_RANGE_M.contains(&resolution_m) {
        return Err(WorldError::invalid(
            path,
            field,
            // `{:?}` writes 1e300 as `1e300`, not as 301 digits.
            format!("{resolution_m:?}"),
            format!(
                "metres per cell from {} to {}",
                RESOLUTION_RANGE_M.start(),
                RESOLUTION_RANGE_M.end()
            ),
        ));
    }
    Ok(())
}

/// Checks that a map with this origin and extent lies within ±[`MAX_ABS_COORD_M`].
pub(crate) fn check_extent(
    origin: Point2,
    extent_m: (f64, f64),
    field: &str,
    path: &Path,
) -> Result<()> {
    let far = Point2::new(origin.x + extent_m.0, origin.y + extent_m.1);
    let inside = |v: f64| v.is_finite() && v.abs() <= MAX_ABS_COORD_M;
    if !(inside(origin.x) && inside(origin.y) && inside(far.x) && inside(far.y)) {
        return Err(WorldError::invalid(
            path,
            field,
            format!("[{:?}, {:?}]", origin.x, origin.y),
            format!("coordinates within ±{MAX_ABS_COORD_M} m, the far corner included"),
        ));
    }
    Ok(())
}

pub(crate) fn check_geometry(g: &GridGeometry, path: &Path) -> Result<()> {
    check_resolution(g.resolution_m, "grid.resolution_m", path)?;
    for (field, v) in [("grid.width", g.width), ("grid.height", g.height)] {
        if v == 0 || v > MAX_GRID_SIDE {
            return Err(WorldError::invalid(
                path,
                field,
                v,
                format!("1..={MAX_GRID_SIDE} cells"),
            ));
        }
    }
    crate::limits::check_cells(path, "grid", g.width.into(), g.height.into())?;
    check_extent(g.origin, g.extent_m(), "grid.origin", path)
}

fn check_point(p: Point2, g: &GridGeometry, field: &str, path: &Path) -> Result<()> {
    let inside = p.x.is_finite() && p.y.is_finite() && g.contains(g.world_to_cell(p));
    if !inside {
        let (w, h) = g.extent_m();
        return Err(WorldError::invalid(
            path,
            field,
            format!("({}, {})", p.x, p.y),
            format!(
                "a point inside the grid, x in [{}, {}) and y in [{}, {})",
                g.origin.x,
                g.origin.x + w,
                g.origin.y,
                g.origin.y + h
            ),
        ));
    }
    Ok(())
}

fn check_fraction(v: f64, field: &str, path: &Path) -> Result<()> {
    if !(0.0..=1.0).contains(&v) {
        return Err(WorldError::invalid(path, field, v, "a fraction in [0, 1]"));
    }
    Ok(())
}

fn check_positive(v: f64, field: &str, path: &Path) -> Result<()> {
    if !(v.is_finite() && v > 0.0) {
        return Err(WorldError::invalid(path, field, v, "a positive number"));
    }
    Ok(())
}

/// Validates everything but the geometry (checked before the layers are decoded).
pub(crate) fn validate_scene(scene: &Scene, path: &Path) -> Result<()> {
    let g = scene.geometry();
    if let Some(i) = scene
        .obstacle
        .as_slice()
        .iter()
        .position(|&o| o > obstacle::FURNITURE)
    {
        let c = g.cell_of_index(i);
        return Err(WorldError::invalid(
            path,
            format!("layers.obstacle (cell {}, {})", c.col, c.row),
            scene.obstacle.as_slice()[i],
            "0 (none), 1 (wall) or 2 (furniture)",
        ));
    }
    if let Some(i) = scene
        .floor_height_m
        .as_slice()
        .iter()
        .position(|h| !h.is_finite())
    {
        let c = g.cell_of_index(i);
        return Err(WorldError::invalid(
            path,
            format!("layers.floor_height_m (cell {}, {})", c.col, c.row),
            scene.floor_height_m.as_slice()[i],
            "a finite height in metres",
        ));
    }
    let mut room_ids = BTreeSet::new();
    for (i, room) in scene.rooms.iter().enumerate() {
        if room.id == 0 || !room_ids.insert(room.id) {
            return Err(WorldError::invalid(
                path,
                format!("rooms[{i}].id"),
                room.id,
                "a unique id ≥ 1",
            ));
        }
    }
    if let Some(i) = scene
        .room_id
        .as_slice()
        .iter()
        .position(|&r| r != 0 && !room_ids.contains(&r))
    {
        let c = g.cell_of_index(i);
        return Err(WorldError::invalid(
            path,
            format!("layers.room_id (cell {}, {})", c.col, c.row),
            scene.room_id.as_slice()[i],
            "0 or the id of a room listed in `rooms`",
        ));
    }
    let mut door_ids = BTreeSet::new();
    for (i, door) in scene.doors.iter().enumerate() {
        if !door_ids.insert(door.id) {
            return Err(WorldError::invalid(
                path,
                format!("doors[{i}].id"),
                door.id,
                "a unique id",
            ));
        }
        check_point(door.position, g, &format!("doors[{i}].position"), path)?;
        check_positive(door.width_m, &format!("doors[{i}].width_m"), path)?;
        for r in door.rooms {
            if r != 0 && !room_ids.contains(&r) {
                return Err(WorldError::invalid(
                    path,
                    format!("doors[{i}].rooms"),
                    r,
                    "0 or the id of a listed room",
                ));
            }
        }
    }
    for (i, room) in scene.rooms.iter().enumerate() {
        if let Some(d) = room.door_ids.iter().find(|d| !door_ids.contains(d)) {
            return Err(WorldError::invalid(
                path,
                format!("rooms[{i}].door_ids"),
                d,
                "ids of listed doors",
            ));
        }
        if let Some(c) = room
            .intersecting_corridors
            .iter()
            .find(|c| !room_ids.contains(c))
        {
            return Err(WorldError::invalid(
                path,
                format!("rooms[{i}].intersecting_corridors"),
                c,
                "ids of listed rooms",
            ));
        }
    }
    let mut victim_ids = BTreeSet::new();
    for (i, v) in scene.victims.iter().enumerate() {
        if !victim_ids.insert(v.id) {
            return Err(WorldError::invalid(
                path,
                format!("victims[{i}].id"),
                v.id,
                "a unique id (another victim has it)",
            ));
        }
        check_point(v.position, g, &format!("victims[{i}].position"), path)?;
        check_positive(
            v.visible_size_m2,
            &format!("victims[{i}].visible_size_m2"),
            path,
        )?;
        check_fraction(
            v.buried_fraction,
            &format!("victims[{i}].buried_fraction"),
            path,
        )?;
        if !v.heat_c.is_finite() {
            return Err(WorldError::invalid(
                path,
                format!("victims[{i}].heat_c"),
                v.heat_c,
                "a temperature in °C",
            ));
        }
    }
    let mut heat_ids = BTreeSet::new();
    for (i, h) in scene.heat_sources.iter().enumerate() {
        if !heat_ids.insert(h.id) {
            return Err(WorldError::invalid(
                path,
                format!("heat_sources[{i}].id"),
                h.id,
                "a unique id (another heat source has it)",
            ));
        }
        check_point(h.position, g, &format!("heat_sources[{i}].position"), path)?;
        check_positive(h.size_m2, &format!("heat_sources[{i}].size_m2"), path)?;
        if !h.heat_c.is_finite() {
            return Err(WorldError::invalid(
                path,
                format!("heat_sources[{i}].heat_c"),
                h.heat_c,
                "a temperature in °C",
            ));
        }
    }
    for (i, p) in scene.start_poses.iter().enumerate() {
        let field = format!("start_poses[{i}]");
        check_point(p.position(), g, &field, path)?;
        if !p.theta.is_finite() {
            return Err(WorldError::invalid(
                path,
                format!("{field}.theta"),
                p.theta,
                "a finite angle in radians",
            ));
        }
        if scene.is_obstacle(g.world_to_cell(p.position())) {
            return Err(WorldError::invalid(
                path,
                field,
                format!("({}, {}) inside an obstacle", p.x, p.y),
                "a pose on a free cell",
            ));
        }
    }
    if let Some(c) = scene.coarse_cell_m {
        check_positive(c, "coarse_cell_m", path)?;
        if c < g.resolution_m {
            return Err(WorldError::invalid(
                path,
                "coarse_cell_m",
                c,
                format!("at least grid.resolution_m ({})", g.resolution_m),
            ));
        }
    }
    Ok(())
}

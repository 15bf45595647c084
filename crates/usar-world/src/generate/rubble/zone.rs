//! A rubble zone laid into a floor: an arena generated as paper 000's (climbable ramps and
//! layers, non-climbable piles and slabs, drops, buried victims, other heat sources), its
//! coarse cells on a grid the caller gives, painted onto the floor's own fine cells where the
//! caller allows (the free floor of one room, say) — the collapsed part of a building.

use super::{RubbleParams, generate_rubble};
use crate::scene::{HeatSource, Scene, Victim};
use crate::{Cell, Point2, Pose2};

/// What [`lay_rubble`] added.
#[derive(Clone, Debug, PartialEq)]
pub struct RubbleZone {
    /// Ids of the victims and heat sources it added to the scene.
    pub victims: Vec<u32>,
    pub heat_sources: Vec<u32>,
    /// The arena's start pose, where it fell on an allowed cell (an open cell of the arena).
    pub start: Option<Pose2>,
}

/// Lays a rubble arena (`generate_rubble(seed)` with `cols` × `rows` cells of `cell_m`) onto
/// `scene` with its cells' lower-left corner at `origin`. Each fine cell of the scene whose
/// centre falls inside the arena and that `allowed` accepts takes the arena's floor height
/// (added to its own) and its obstacles (the arena's outer wall is left out); the arena's
/// victims and heat sources on allowed, unobstructed cells join the scene's, numbered after
/// its own.
pub fn lay_rubble(
    scene: &mut Scene,
    origin: Point2,
    (cols, rows): (u32, u32),
    cell_m: f64,
    seed: u64,
    allowed: impl Fn(Cell) -> bool,
) -> RubbleZone {
    let arena = generate_rubble(
        seed,
        &RubbleParams {
            cols,
            rows,
            cell_area_m2: cell_m * cell_m,
            ..RubbleParams::default()
        },
    );
    let a = *arena.geometry();
    let g = *scene.geometry();
    // The arena's coarse cells start at its world origin (its fine grid has a wall ring
    // around them).
    let to_arena = |p: Point2| Point2::new(p.x - origin.x, p.y - origin.y);
    let inside = |p: Point2| {
        let q = to_arena(p);
        q.x >= 0.0 && q.y >= 0.0 && q.x < f64::from(cols) * cell_m && q.y < f64::from(rows) * cell_m
    };
    let (c0, c1) = (
        g.world_to_cell(origin),
        g.world_to_cell(Point2::new(
            origin.x + f64::from(cols) * cell_m,
            origin.y + f64::from(rows) * cell_m,
        )),
    );
    for row in c0.row.max(0)..=c1.row.min(g.height as i32 - 1) {
        for col in c0.col.max(0)..=c1.col.min(g.width as i32 - 1) {
            let c = Cell::new(col, row);
            let p = g.cell_center(c);
            if !inside(p) || !allowed(c) {
                continue;
            }
            let ac = a.world_to_cell(to_arena(p));
            if !a.contains(ac) {
                continue;
            }
            let ring = ac.col == 0
                || ac.row == 0
                || ac.col == a.width as i32 - 1
                || ac.row == a.height as i32 - 1;
            scene.floor_height_m[c] += arena.floor_height_m[ac];
            if !ring {
                scene.obstacle[c] = scene.obstacle[c].max(arena.obstacle[ac]);
            }
        }
    }
    let lands = |scene: &Scene, p: Point2| {
        let c = g.world_to_cell(p);
        g.contains(c) && inside(p) && allowed(c) && scene.obstacle[c] == 0
    };
    let shift = |p: Point2| Point2::new(p.x + origin.x, p.y + origin.y);
    let mut added = RubbleZone {
        victims: Vec::new(),
        heat_sources: Vec::new(),
        start: None,
    };
    let mut next = scene.victims.iter().map(|v| v.id + 1).max().unwrap_or(0);
    for v in &arena.victims {
        let position = shift(v.position);
        if lands(scene, position) {
            scene.victims.push(Victim {
                id: next,
                position,
                ..v.clone()
            });
            added.victims.push(next);
            next += 1;
        }
    }
    let mut next = scene
        .heat_sources
        .iter()
        .map(|h| h.id + 1)
        .max()
        .unwrap_or(0);
    for h in &arena.heat_sources {
        let position = shift(h.position);
        if lands(scene, position) {
            scene.heat_sources.push(HeatSource {
                id: next,
                position,
                ..h.clone()
            });
            added.heat_sources.push(next);
            next += 1;
        }
    }
    added.start = arena.start_poses.first().and_then(|s| {
        let p = shift(s.position());
        lands(scene, p).then(|| Pose2::new(p.x, p.y, s.theta))
    });
    added
}

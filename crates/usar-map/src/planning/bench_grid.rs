//! Synthetic building floors for measuring the planners: rooms of 4–12 m on a 0.1 m grid,
//! 0.2 m walls, 1 m doors, 2 m corridors and furniture, all inflated by 0.3 m (a robot of
//! 0.3 m radius). Used by the speed measurements (`examples/planning_speed.rs`) and meant for the
//! project's `usar bench`.
//!
//! The floor is cut into blocks by a network of corridors; each block is cut into rows of rooms
//! and each row into rooms. Every room has a door to its neighbour in the row, each pair of
//! adjacent rows has a door, and every block has at least one door to a corridor, so the whole
//! floor is one connected region (checked by the tests).

use super::inflate::inflate;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use usar_world::{Cell, Grid, GridGeometry, Point2};

/// Cell side of the synthetic floor, metres.
pub const BENCH_RESOLUTION_M: f64 = 0.1;
/// Wall thickness, metres.
pub const BENCH_WALL_M: f64 = 0.2;
/// Door width, metres.
pub const BENCH_DOOR_M: f64 = 1.0;
/// Corridor width, metres.
pub const BENCH_CORRIDOR_M: f64 = 2.0;
/// Smallest and largest room side, metres.
pub const BENCH_ROOM_M: (f64, f64) = (4.0, 12.0);
/// Smallest and largest side of a block of rooms between corridors, metres.
pub const BENCH_BLOCK_M: (f64, f64) = (15.0, 30.0);
/// Inflation radius (robot radius), metres.
pub const BENCH_INFLATION_M: f64 = 0.3;
/// Clearance between furniture and a room's walls, metres (keeps every door reachable after
/// inflation).
pub const BENCH_FURNITURE_CLEARANCE_M: f64 = 1.0;

fn cells(m: f64) -> usize {
    (m / BENCH_RESOLUTION_M).round() as usize
}

/// A seeded synthetic building floor of `width` × `height` cells at [`BENCH_RESOLUTION_M`],
/// already inflated by [`BENCH_INFLATION_M`]: `true` = blocked.
///
/// The same arguments always give the same grid. Floors below ~5 m a side hold a single room.
pub fn synthetic_building(width: u32, height: u32, seed: u64) -> Grid<bool> {
    inflate(
        &synthetic_building_walls(width, height, seed),
        BENCH_INFLATION_M,
    )
}

/// The floor of [`synthetic_building`] before inflation: walls and furniture only.
pub fn synthetic_building_walls(width: u32, height: u32, seed: u64) -> Grid<bool> {
    let geometry = GridGeometry::new(width, height, BENCH_RESOLUTION_M, Point2::new(0.0, 0.0));
    let mut floor = Floor {
        grid: Grid::filled(geometry, false),
        width,
        height,
    };
    if geometry.is_empty() {
        return floor.grid;
    }
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let wall = cells(BENCH_WALL_M);
    // Outer wall.
    floor.fill(0, 0, width as usize, wall, true);
    floor.fill(
        0,
        height as usize - wall.min(height as usize),
        width as usize,
        height as usize,
        true,
    );
    floor.fill(0, 0, wall, height as usize, true);
    floor.fill(
        width as usize - wall.min(width as usize),
        0,
        width as usize,
        height as usize,
        true,
    );

    let xs = split_with_corridors(&mut rng, wall, width as usize - wall.min(width as usize));
    let ys = split_with_corridors(&mut rng, wall, height as usize - wall.min(height as usize));
    for &(x0, x1) in &xs {
        for &(y0, y1) in &ys {
            let block = Block {
                x0,
                x1,
                y0,
                y1,
                // A side faces a corridor unless it lies on the outer wall.
                corridor_west: x0 > wall,
                corridor_east: x1 + wall < width as usize,
                corridor_south: y0 > wall,
                corridor_north: y1 + wall < height as usize,
            };
            floor.block(&mut rng, &block);
        }
    }
    floor.grid
}

/// The free cells nearest to the lower-left and the upper-right corners (by col + row), the
/// corner-to-corner query of the speed measurements; `None` when no cell is free.
pub fn corner_cells(blocked: &Grid<bool>) -> Option<(Cell, Cell)> {
    let mut free = blocked.iter_cells().filter(|(_, b)| !**b).map(|(c, _)| c);
    let first = free.next()?;
    let key = |c: Cell| (c.col + c.row, c.col);
    let (mut low, mut high) = (first, first);
    for c in free {
        if key(c) < key(low) {
            low = c;
        }
        if key(c) > key(high) {
            high = c;
        }
    }
    Some((low, high))
}

/// Cuts the interior span [lo, hi) into blocks separated by corridors; returns the blocks.
fn split_with_corridors(rng: &mut Pcg64Mcg, lo: usize, hi: usize) -> Vec<(usize, usize)> {
    let (min_block, max_block) = (cells(BENCH_BLOCK_M.0), cells(BENCH_BLOCK_M.1));
    let corridor = cells(BENCH_CORRIDOR_M);
    let mut blocks = Vec::new();
    let mut at = lo;
    while hi > at {
        let remaining = hi - at;
        if remaining <= max_block + corridor + min_block {
            if remaining > 2 * min_block + corridor && remaining > max_block {
                let len = (remaining - corridor) / 2;
                blocks.push((at, at + len));
                blocks.push((at + len + corridor, hi));
            } else {
                blocks.push((at, hi));
            }
            break;
        }
        let len = rng.random_range(min_block..=max_block);
        blocks.push((at, at + len));
        at += len + corridor;
    }
    blocks
}

/// A block of rooms; `corridor_*` tell which sides open on a corridor.
struct Block {
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
    corridor_west: bool,
    corridor_east: bool,
    corridor_south: bool,
    corridor_north: bool,
}

struct Floor {
    grid: Grid<bool>,
    width: u32,
    height: u32,
}

impl Floor {
    /// Sets cells [x0, x1) × [y0, y1), clipped to the grid.
    fn fill(&mut self, x0: usize, y0: usize, x1: usize, y1: usize, value: bool) {
        let (w, h) = (self.width as usize, self.height as usize);
        let (x1, y1) = (x1.min(w), y1.min(h));
        for row in y0..y1 {
            for col in x0..x1 {
                self.grid.as_mut_slice()[row * w + col] = value;
            }
        }
    }

    fn block(&mut self, rng: &mut Pcg64Mcg, b: &Block) {
        let wall = cells(BENCH_WALL_M);
        let door = cells(BENCH_DOOR_M);
        // Doors keep 0.3 m from the walls they meet, beyond their half width.
        let door_margin = door / 2 + cells(0.3);
        // Block outline walls, inside the block.
        self.fill(b.x0, b.y0, b.x1, b.y0 + wall, true);
        self.fill(b.x0, b.y1 - wall, b.x1, b.y1, true);
        self.fill(b.x0, b.y0, b.x0 + wall, b.y1, true);
        self.fill(b.x1 - wall, b.y0, b.x1, b.y1, true);

        let rows = partition(rng, b.y0, b.y1);
        let mut previous_bounds: Option<Vec<usize>> = None;
        // (room, vertical side, low side) of every room side that faces a corridor.
        let mut corridor_sides = Vec::new();
        for (r, &(ry0, ry1)) in rows.iter().enumerate() {
            let columns = partition(rng, b.x0, b.x1);
            let bounds: Vec<usize> = columns.iter().skip(1).map(|&(c0, _)| c0).collect();
            // Walls between rooms of the row, each with a door.
            for &x in &bounds {
                self.fill(x - wall / 2, ry0, x + wall - wall / 2, ry1, true);
                let lo = ry0 + wall + door_margin;
                let hi = (ry1 - wall).saturating_sub(door_margin).max(lo);
                let c = rng.random_range(lo..=hi);
                self.fill(
                    x - wall / 2,
                    c - door / 2,
                    x + wall - wall / 2,
                    c + door - door / 2,
                    false,
                );
            }
            // Wall below the row (between it and the previous one) with one door in the longest
            // stretch free of junctions with the walls of either row.
            if let Some(prev) = &previous_bounds {
                self.fill(b.x0, ry0 - wall / 2, b.x1, ry0 + wall - wall / 2, true);
                let mut junctions: Vec<usize> = prev.iter().chain(&bounds).copied().collect();
                junctions.push(b.x0);
                junctions.push(b.x1);
                junctions.sort_unstable();
                let (s0, s1) = junctions
                    .windows(2)
                    .map(|p| (p[0], p[1]))
                    .max_by_key(|&(a, z)| (z - a, std::cmp::Reverse(a)))
                    .unwrap_or((b.x0, b.x1));
                let lo = s0 + wall + door_margin;
                let hi = s1.saturating_sub(wall + door_margin).max(lo);
                let c = rng.random_range(lo..=hi);
                self.fill(
                    c - door / 2,
                    ry0 - wall / 2,
                    c + door - door / 2,
                    ry0 + wall - wall / 2,
                    false,
                );
            }
            for &(cx0, cx1) in &columns {
                let room = (cx0, cx1, ry0, ry1);
                let sides = [
                    (b.corridor_south && r == 0, false, true),
                    (b.corridor_north && r + 1 == rows.len(), false, false),
                    (b.corridor_west && cx0 == b.x0, true, true),
                    (b.corridor_east && cx1 == b.x1, true, false),
                ];
                for (faces_corridor, vertical, low_side) in sides {
                    if faces_corridor {
                        corridor_sides.push((room, vertical, low_side));
                    }
                }
                self.furniture(rng, room);
            }
            previous_bounds = Some(bounds);
        }
        // Each corridor-facing side gets a door with probability 1/2, and every block gets one.
        let mut doors = 0;
        for &(room, vertical, low_side) in &corridor_sides {
            if rng.random_bool(0.5) {
                self.corridor_door(rng, b, room, vertical, low_side);
                doors += 1;
            }
        }
        if doors == 0 && !corridor_sides.is_empty() {
            let (room, vertical, low_side) =
                corridor_sides[rng.random_range(0..corridor_sides.len())];
            self.corridor_door(rng, b, room, vertical, low_side);
        }
    }

    /// A 1 m door in the block wall on one side of `room` = (x0, x1, y0, y1).
    fn corridor_door(
        &mut self,
        rng: &mut Pcg64Mcg,
        b: &Block,
        room: (usize, usize, usize, usize),
        vertical: bool,
        low_side: bool,
    ) {
        let wall = cells(BENCH_WALL_M);
        let door = cells(BENCH_DOOR_M);
        let margin = wall + door / 2 + cells(0.3);
        let (x0, x1, y0, y1) = room;
        if vertical {
            let c = rng.random_range(y0 + margin..=(y1.saturating_sub(margin)).max(y0 + margin));
            let x = if low_side { b.x0 } else { b.x1 - wall };
            self.fill(x, c - door / 2, x + wall, c + door - door / 2, false);
        } else {
            let c = rng.random_range(x0 + margin..=(x1.saturating_sub(margin)).max(x0 + margin));
            let y = if low_side { b.y0 } else { b.y1 - wall };
            self.fill(c - door / 2, y, c + door - door / 2, y + wall, false);
        }
    }

    /// Zero to two pieces of furniture, kept [`BENCH_FURNITURE_CLEARANCE_M`] from the walls.
    fn furniture(&mut self, rng: &mut Pcg64Mcg, room: (usize, usize, usize, usize)) {
        let clearance = cells(BENCH_FURNITURE_CLEARANCE_M);
        let (x0, x1) = (room.0 + clearance, room.1.saturating_sub(clearance));
        let (y0, y1) = (room.2 + clearance, room.3.saturating_sub(clearance));
        let (min_side, max_side) = (cells(0.4), cells(1.5));
        if x1 <= x0 + min_side || y1 <= y0 + min_side {
            return;
        }
        for _ in 0..rng.random_range(0..=2) {
            let w = rng.random_range(min_side..=max_side.min(x1 - x0));
            let h = rng.random_range(min_side..=max_side.min(y1 - y0));
            let fx = rng.random_range(x0..=x1 - w);
            let fy = rng.random_range(y0..=y1 - h);
            self.fill(fx, fy, fx + w, fy + h, true);
        }
    }
}

/// Cuts [lo, hi) into parts of [`BENCH_ROOM_M`] (a span shorter than the smallest room stays one
/// part); returns the parts in order.
fn partition(rng: &mut Pcg64Mcg, lo: usize, hi: usize) -> Vec<(usize, usize)> {
    let (min_room, max_room) = (cells(BENCH_ROOM_M.0), cells(BENCH_ROOM_M.1));
    let mut parts = Vec::new();
    let mut at = lo;
    while hi - at > max_room {
        // Leave at least one smallest room behind.
        let len = rng.random_range(min_room..=max_room.min(hi - at - min_room));
        parts.push((at, at + len));
        at += len;
    }
    parts.push((at, hi));
    parts
}

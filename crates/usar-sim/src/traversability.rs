//! Which fine cells a robot can stand on: not an obstacle, no step to a neighbour higher than it
//! can climb, and a floor no steeper than its inclination limit over its own length.

use crate::robot::RobotSpec;
use usar_world::{Cell, Grid, Scene, obstacle};

/// The ground truth of where a robot of `spec` can be: `true` = blocked.
///
/// - step: |h(c) − h(n)| > `max_step_m` for a 4-neighbour n (both sides of a step are blocked);
/// - inclination: atan(‖∇h‖) > `max_inclination_rad`, the gradient taken by central differences
///   over ±k cells with k·resolution ≈ half the robot's length, because a robot body bridges
///   features shorter than itself (a staircase of 0.15 m steps 0.3 m deep reads as its 26.6°
///   pitch, not as a series of vertical faces).
pub fn compute_blocked(scene: &Scene, spec: &RobotSpec) -> Grid<bool> {
    let g = *scene.geometry();
    let (w, h) = (g.width as i32, g.height as i32);
    let heights = scene.floor_height_m.as_slice();
    let obstacles = scene.obstacle.as_slice();
    let k = ((spec.length_m / 2.0 / g.resolution_m).round() as i32).max(1);
    let tan_max = spec.max_inclination_rad.tan() + 1e-9;
    let max_step = spec.max_step_m as f32 + 1e-6;
    let idx = |c: i32, r: i32| r as usize * w as usize + c as usize;
    let mut blocked = Grid::filled(g, false);
    let out = blocked.as_mut_slice();
    for r in 0..h {
        for c in 0..w {
            let i = idx(c, r);
            if obstacles[i] != obstacle::NONE {
                out[i] = true;
                continue;
            }
            let hc = heights[i];
            // Height of a cell for the gradient: its own floor, or ours when it is an obstacle.
            let hh = |cc: i32, rr: i32| {
                let j = idx(cc.clamp(0, w - 1), rr.clamp(0, h - 1));
                if obstacles[j] != obstacle::NONE {
                    hc
                } else {
                    heights[j]
                }
            };
            let step = [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|&(dc, dr)| {
                let (cc, rr) = (c + dc, r + dr);
                cc >= 0 && rr >= 0 && cc < w && rr < h && {
                    let j = idx(cc, rr);
                    obstacles[j] == obstacle::NONE && (heights[j] - hc).abs() > max_step
                }
            });
            let (c0, c1) = ((c - k).max(0), (c + k).min(w - 1));
            let (r0, r1) = ((r - k).max(0), (r + k).min(h - 1));
            let gx = if c1 > c0 {
                f64::from(hh(c1, r) - hh(c0, r)) / (f64::from(c1 - c0) * g.resolution_m)
            } else {
                0.0
            };
            let gy = if r1 > r0 {
                f64::from(hh(c, r1) - hh(c, r0)) / (f64::from(r1 - r0) * g.resolution_m)
            } else {
                0.0
            };
            out[i] = step || gx.hypot(gy) > tan_max;
        }
    }
    blocked
}

/// The cells whose centres lie under a `length_m` × `width_m` rectangle centred at `pose`.
pub fn footprint_cells(
    geometry: &usar_world::GridGeometry,
    pose: usar_world::Pose2,
    length_m: f64,
    width_m: f64,
    mut visit: impl FnMut(Cell) -> bool,
) -> bool {
    let (hl, hw) = (length_m / 2.0, width_m / 2.0);
    let (s, c) = pose.theta.sin_cos();
    let ex = hl * c.abs() + hw * s.abs();
    let ey = hl * s.abs() + hw * c.abs();
    let lo = geometry.world_to_cell(usar_world::Point2::new(pose.x - ex, pose.y - ey));
    let hi = geometry.world_to_cell(usar_world::Point2::new(pose.x + ex, pose.y + ey));
    for row in lo.row..=hi.row {
        for col in lo.col..=hi.col {
            let cell = Cell::new(col, row);
            let p = geometry.cell_center(cell);
            let (dx, dy) = (p.x - pose.x, p.y - pose.y);
            let (bx, by) = (c * dx + s * dy, -s * dx + c * dy);
            if bx.abs() <= hl && by.abs() <= hw && !visit(cell) {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::{GridGeometry, Point2};

    fn ramp(incline_deg: f64) -> Scene {
        let g = GridGeometry::new(60, 20, 0.1, Point2::new(0.0, 0.0));
        let mut s = Scene::empty("ramp", g);
        let t = incline_deg.to_radians().tan();
        for (cell, h) in s.clone().floor_height_m.iter_cells() {
            let _ = h;
            let x = g.cell_center(cell).x;
            s.floor_height_m[cell] = (t * (x - 2.0).clamp(0.0, 2.0)) as f32;
        }
        s
    }

    #[test]
    fn a_20_degree_ramp_blocks_the_wheeled_robot_but_not_the_crawler() {
        let s = ramp(20.0);
        let mid = Cell::new(30, 10);
        assert!(compute_blocked(&s, &RobotSpec::wheeled())[mid]);
        assert!(!compute_blocked(&s, &RobotSpec::crawler())[mid]);
        assert!(!compute_blocked(&s, &RobotSpec::wheeled())[Cell::new(5, 10)]);
    }

    #[test]
    fn footprint_covers_the_rectangle() {
        let g = GridGeometry::new(20, 20, 0.1, Point2::new(0.0, 0.0));
        let mut n = 0;
        footprint_cells(&g, usar_world::Pose2::new(1.0, 1.0, 0.0), 0.6, 0.4, |_| {
            n += 1;
            true
        });
        assert_eq!(n, 6 * 4);
    }
}

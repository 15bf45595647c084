//! The frontier explorer on your own scans: feed poses and laser ranges (from your robot, a log
//! or a simulator) into an occupancy grid, find the frontier clusters, and plan a path to the
//! nearest one — the loop of a frontier-based explorer, without the usar simulator.
//!
//! ```sh
//! cargo run -p usar-map --example frontiers_from_scans
//! ```
//!
//! The scans here come from a small built-in floor (a 10 × 6 m room with a door into a
//! corridor) so that the example runs anywhere; replace `your_scans` with your data.

use usar_map::planning::{Connectivity, GridAStar, NavGrid, inflate};
use usar_map::{CellClass, FrontierTracker, OccupancyGrid, OccupancyParams};
use usar_readings::LaserScan;
use usar_world::{GridGeometry, Point2, Pose2};

/// Your data: a robot pose and the ranges of one 360° scan (beam 0 pointing behind the robot,
/// counter-clockwise, 1° apart), here ray-cast on a built-in floor plan.
fn your_scans() -> Vec<(Pose2, Vec<f32>)> {
    let walls = |p: Point2| -> bool {
        let in_room = p.x > 0.0 && p.x < 10.0 && p.y > 0.0 && p.y < 6.0;
        let in_corridor = p.x > 10.0 && p.x < 20.0 && p.y > 2.0 && p.y < 4.0;
        let in_door = p.x >= 9.9 && p.x <= 10.1 && p.y > 2.5 && p.y < 3.5;
        !(in_room || in_corridor || in_door)
    };
    let poses = [
        Pose2::new(2.0, 3.0, 0.0),
        Pose2::new(5.0, 3.0, 0.0),
        Pose2::new(8.0, 3.0, 0.0),
    ];
    poses
        .iter()
        .map(|&pose| {
            let ranges = (0..360)
                .map(|i| {
                    let a = pose.theta - std::f64::consts::PI + (i as f64).to_radians();
                    let mut r = 0.0;
                    while r < 8.0 && !walls(pose.position().offset(a, r)) {
                        r += 0.02;
                    }
                    if r >= 8.0 { f32::INFINITY } else { r as f32 }
                })
                .collect();
            (pose, ranges)
        })
        .collect()
}

fn main() {
    let geometry = GridGeometry::new(220, 80, 0.1, Point2::new(-1.0, -1.0));
    let mut grid = OccupancyGrid::new(geometry, OccupancyParams::default());
    let mut frontiers = FrontierTracker::new(&grid);
    for (pose, ranges) in your_scans() {
        let scan = LaserScan {
            pose,
            angle_min_rad: -std::f64::consts::PI,
            angle_increment_rad: std::f64::consts::TAU / 360.0,
            max_range_m: 8.0,
            ranges_m: ranges,
        };
        grid.integrate_scan(&scan);
        frontiers.update(&mut grid);
    }
    let clusters = frontiers.clusters(&grid, 3);
    println!(
        "known {:.1} m², {} frontier clusters",
        grid.known_area_m2(),
        clusters.len()
    );
    // Plan around what is known to be occupied, kept 0.3 m from it (a frontier borders unknown
    // space by definition, so unknown cells cannot all be walls).
    let nav = NavGrid::from_blocked(&inflate(&grid.mask(CellClass::Occupied), 0.3));
    let here = geometry.world_to_cell(Point2::new(8.0, 3.0));
    let mut astar = GridAStar::new();
    let nearest = clusters
        .iter()
        .filter_map(|c| {
            let path = astar.plan(&nav, here, c.candidate, Connectivity::Eight)?;
            Some((path.length_m(geometry.resolution_m), c))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0));
    match nearest {
        Some((length, c)) => println!(
            "nearest frontier: {} cells around ({:.1}, {:.1}), {length:.1} m away",
            c.len(),
            c.centroid.x,
            c.centroid.y
        ),
        None => println!("no reachable frontier: the floor is explored"),
    }
    assert!(
        !clusters.is_empty(),
        "the corridor beyond the door is still unknown"
    );
}

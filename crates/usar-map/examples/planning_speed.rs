//! Times the grid planners corner to corner on two 1000×1000 floors (100 m × 100 m at 0.1 m):
//! the synthetic building of `bench_grid` (inflated by 0.3 m) and the generated office of
//! `usar bench` (inflated by the wheeled robot's circumscribed radius); then, optionally, checks
//! the MovingAI scenario files.
//!
//! `cargo run --release -p usar-map --example planning_speed [-- SEED [MOVINGAI_DIR]]`
//! (the scenario files are checked only when MOVINGAI_DIR is given).

use std::path::PathBuf;
use std::time::{Duration, Instant};
use usar_map::planning::bench_grid::{BENCH_INFLATION_M, corner_cells, synthetic_building_walls};
use usar_map::planning::{
    Connectivity, DistanceField, GridAStar, GridAlgorithm, NavGrid, check_scenarios, inflate,
};
use usar_sim::RobotSpec;
use usar_world::Grid;
use usar_world::generate::{BuildingParams, generate_office};

/// Timed runs of each step (`PLANNING_SPEED_RUNS` overrides).
const RUNS: usize = 15;

/// Median and minimum of the timings of `f`, milliseconds.
fn time<T>(mut f: impl FnMut() -> T) -> (f64, f64, T) {
    let runs: usize = std::env::var("PLANNING_SPEED_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&n| n > 0)
        .unwrap_or(RUNS);
    let mut times: Vec<Duration> = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let t = Instant::now();
        let out = f();
        times.push(t.elapsed());
        last = Some(out);
    }
    times.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    (
        ms(times[runs / 2]),
        ms(times[0]),
        last.expect("at least one run"),
    )
}

/// Times A*, jump point search and both distance fields corner to corner on `blocked`.
fn time_planners(blocked: &Grid<bool>) {
    let blocked_share = blocked.as_slice().iter().filter(|&&b| b).count() as f64
        / blocked.as_slice().len().max(1) as f64;
    let (median, min, grid) = time(|| NavGrid::from_blocked(blocked));
    println!(
        "  {:.1}% blocked; NavGrid::from_blocked: median {median:7.2} ms  min {min:7.2} ms",
        100.0 * blocked_share
    );
    let (start, goal) = corner_cells(blocked).expect("a free cell");
    println!("  corner to corner: {start:?} -> {goal:?}");
    let mut astar = GridAStar::new();
    for (connectivity, algorithm) in [
        (Connectivity::Four, GridAlgorithm::AStar),
        (Connectivity::Eight, GridAlgorithm::AStar),
        (Connectivity::Eight, GridAlgorithm::JumpPoint),
    ] {
        let (median, min, path) =
            time(|| astar.plan_with(&grid, start, goal, connectivity, algorithm));
        let path = path.expect("the floor is connected");
        println!(
            "  {algorithm:?} {connectivity:?}: median {median:7.2} ms  min {min:7.2} ms  expanded {:>7}  scanned {:>8}  length {:.6} cells",
            astar.expanded(),
            astar.scanned(),
            path.length_cells
        );
    }
    // A fresh grid packs its cells in bits on the first jump point search.
    let (median, min, _) = time(|| {
        let fresh = NavGrid::from_blocked(blocked);
        astar.plan(&fresh, start, goal, Connectivity::Eight)
    });
    println!(
        "  NavGrid::from_blocked + first JumpPoint Eight (packs bits): median {median:7.2} ms  min {min:7.2} ms"
    );
    let mut field = DistanceField::new();
    for connectivity in [Connectivity::Four, Connectivity::Eight] {
        let (median, min, _) = time(|| field.compute(&grid, &[start], connectivity));
        let mut check = GridAStar::new();
        let a = check
            .plan_with(&grid, start, goal, connectivity, GridAlgorithm::AStar)
            .map(|p| p.length_cells);
        println!(
            "  DistanceField {connectivity:?}: median {median:7.2} ms  min {min:7.2} ms  reached {:>7}  to goal {:.9} (A* {:.9})",
            field.reached_count(),
            field.distance_cells(goal).unwrap_or(f64::NAN),
            a.unwrap_or(f64::NAN)
        );
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let seed: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let dir = args.next().map(PathBuf::from);

    let walls = synthetic_building_walls(1000, 1000, seed);
    println!("synthetic building 1000x1000, seed {seed}");
    let (median, min, blocked) = time(|| inflate(&walls, BENCH_INFLATION_M));
    println!("  inflate 0.3 m (3 cells):  median {median:7.2} ms  min {min:7.2} ms");
    time_planners(&blocked);

    let office = generate_office(
        seed,
        &BuildingParams {
            width_m: 100.0,
            height_m: 100.0,
            resolution_m: 0.1,
            ..BuildingParams::office()
        },
    );
    let radius_m = RobotSpec::wheeled().circumscribed_radius_m();
    println!("office 100 m x 100 m (usar bench), seed {seed}, inflated by {radius_m:.3} m");
    time_planners(&inflate(&office.obstacle.map(|&o| o != 0), radius_m));

    let Some(dir) = dir else { return };
    let mut scen: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    scen.retain(|p| p.extension().is_some_and(|e| e == "scen"));
    scen.sort();
    for path in scen {
        let t = Instant::now();
        match check_scenarios(&path) {
            Ok(r) => println!(
                "{}: {}/{} matched, max error {:.2e}, {} expanded, {:.0} ms",
                path.display(),
                r.matched,
                r.scenarios,
                r.max_abs_error,
                r.total_expanded,
                t.elapsed().as_secs_f64() * 1e3
            ),
            Err(e) => println!("{e}"),
        }
    }
}

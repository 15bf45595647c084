//! usar-bench's integration tests.

use usar_bench::{corners, free_poses, median, time_ms};
use usar_world::generate::{SceneKind, generate};

#[test]
fn median_takes_the_middle_value() {
    assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
    assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), 3.0);
    assert!(time_ms(|| {}) >= 0.0);
}

#[test]
fn free_poses_are_seeded_and_free() {
    let scene = generate(SceneKind::Office, 1);
    let a = free_poses(&scene, 50);
    assert_eq!(a, free_poses(&scene, 50));
    let g = scene.geometry();
    for p in &a {
        assert!(!scene.is_obstacle(g.world_to_cell(p.position())));
    }
}

#[test]
fn corners_are_passable_and_apart() {
    use usar_map::planning::{NavGrid, inflate};
    let scene = generate(SceneKind::Office, 1);
    let nav = NavGrid::from_blocked(&inflate(&scene.obstacle.map(|&o| o != 0), 0.3));
    let (a, b) = corners(&nav);
    assert!(nav.is_passable(a) && nav.is_passable(b));
    assert!(a.col < b.col && a.row < b.row);
}

#[test]
fn laser_rate_is_positive() {
    let scene = generate(SceneKind::Rubble, 1);
    assert!(usar_bench::laser_scans_per_s(&scene, 1, 50) > 0.0);
}

#[test]
fn a_scaling_cell_runs_the_team_it_names_for_the_time_asked() {
    use usar_bench::scaling::{PIPELINES, scaling};
    let mut seen = 0;
    let report = scaling(&[3], &PIPELINES, 5.0, |_| seen += 1).unwrap();
    assert_eq!(seen, 2);
    assert!(report.floor.starts_with("mall"));
    for (row, pipeline) in report.rows.iter().zip(PIPELINES) {
        assert_eq!((row.pipeline.as_str(), row.robots), (pipeline, 3));
        // The run's simulated time is the time asked (paper 002's step of 0.1 s).
        assert!((row.simulated_s - 5.0).abs() < 0.11, "{row:?}");
        assert!(row.realtime_factor > 0.0 && row.robot_s_per_s > 0.0);
        assert!((row.robot_s_per_s - 3.0 * row.realtime_factor).abs() < 1e-6 * row.robot_s_per_s);
    }
}

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

/// The Python laser reference of `usar bench --laser-reference` does the work usar's laser does:
/// cast from the same cells at the same beam angles on the same floor, raycast2D's beams end
/// where usar's do (within the difference of Bresenham's cells and an exact traversal's, and
/// of a cell's centre and its near side). `./test.sh` installs raycast2D and OpenCV.
#[test]
fn the_python_reference_casts_the_beams_usar_casts() {
    use rand::SeedableRng;
    use usar_bench::laser_reference::write_inputs;
    use usar_sim::sensors::{LaserModel, LaserSpec, SensingWorld};
    let python = std::env::var("USAR_PYTHON")
        .expect("USAR_PYTHON: a Python with raycast2D and opencv; ./test.sh sets one up");
    let scene = usar_bench::bench_scene();
    let g = *scene.geometry();
    let poses = free_poses(&scene, 40);
    let dir = tempfile::tempdir().unwrap();
    let script = write_inputs(&scene, &poses, dir.path()).unwrap();
    let range_cells = (LaserSpec::default().max_range_m / g.resolution_m).round() as u32;
    let out = std::process::Command::new(&python)
        .arg(&script)
        .args(["ends", "floor.pgm", "poses.csv", &range_cells.to_string()])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let laser = LaserModel::new(LaserSpec {
        range_noise_sd_m: 0.0,
        ..LaserSpec::default()
    });
    let world = SensingWorld::new(&scene);
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(1);
    let mut errors_cells = Vec::new();
    let lines = String::from_utf8(out.stdout).unwrap();
    assert_eq!(lines.lines().count(), poses.len());
    for (line, &pose) in lines.lines().zip(&poses) {
        let c = g.world_to_cell(pose.position());
        // At the cell's centre, as the reference casts.
        let at = usar_world::Pose2::new(g.cell_center(c).x, g.cell_center(c).y, pose.theta);
        let scan = laser.scan(&world, at, 0.0, &mut rng);
        let ends: Vec<i64> = line.split(' ').map(|v| v.parse().unwrap()).collect();
        assert_eq!(ends.len(), 3 * scan.ranges_m.len());
        for (end, &range) in ends.chunks(3).zip(&scan.ranges_m) {
            if end[2] == 1 && range.is_finite() {
                let (dc, dr) = (
                    (end[0] - i64::from(c.col)) as f64,
                    (end[1] - i64::from(c.row)) as f64,
                );
                errors_cells.push((dc.hypot(dr) - f64::from(range) / g.resolution_m).abs());
            }
        }
    }
    assert!(
        errors_cells.len() > 40 * 300,
        "{} beams hit on both",
        errors_cells.len()
    );
    errors_cells.sort_by(f64::total_cmp);
    let quantile = |q: f64| errors_cells[(q * (errors_cells.len() - 1) as f64) as usize];
    assert!(quantile(0.5) <= 1.0, "median {} cells", quantile(0.5));
    assert!(
        quantile(0.9) <= 2.0,
        "90th percentile {} cells",
        quantile(0.9)
    );
}

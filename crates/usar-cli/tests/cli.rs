//! End-to-end tests of the `usar` binary: exit codes, error lines, determinism, round trips.

mod btm;
mod campaign;
mod console;
mod golden;
mod inputs;
mod logs;
mod maxq;
mod mission;
mod record;
mod segment;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn usar(args: &[&str]) -> Output {
    usar_env(args, &[])
}

fn usar_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_usar"));
    cmd.args(args);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("usar runs")
}

/// Runs `usar args`, which must succeed, and reads its standard output as JSON.
fn usar_json(args: &[&str]) -> serde_json::Value {
    let out = usar(args);
    assert!(
        out.status.success(),
        "usar {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn shared(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/maps")
        .join(rel)
}

/// Bad input: exit code 2 and exactly one line on stderr that contains `needle`.
fn assert_bad_input(out: &Output, needle: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "one line expected, got: {stderr}"
    );
    assert!(stderr.contains(needle), "{needle:?} not in: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn empty_scene_file_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("empty.json");
    std::fs::write(&f, "").unwrap();
    assert_bad_input(&usar(&["scene", "info", f.to_str().unwrap()]), "empty");
}

#[test]
fn truncated_pgm_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("cut.pgm");
    std::fs::write(&f, b"P5\n100 100\n255\n\x00\x00\x00").unwrap();
    assert_bad_input(
        &usar(&[
            "scene",
            "import",
            f.to_str().unwrap(),
            "--resolution",
            "0.1",
            "-o",
            dir.path().join("o.json").to_str().unwrap(),
        ]),
        "cut.pgm",
    );
    assert!(!dir.path().join("o.json").exists(), "no output on failure");
}

#[test]
fn yaml_pointing_to_a_missing_image_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("map.yaml");
    std::fs::write(&f, "image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n").unwrap();
    assert_bad_input(
        &usar(&["scene", "info", f.to_str().unwrap()]),
        "nowhere.pgm",
    );
}

#[test]
fn scene_with_a_wrong_version_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("v9.json");
    std::fs::write(&f, r#"{"format": "usar-scene", "version": 9, "name": "x"}"#).unwrap();
    assert_bad_input(&usar(&["scene", "info", f.to_str().unwrap()]), "version 9");
}

#[test]
fn negative_resolution_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("neg.yaml");
    std::fs::copy(shared("ros/depot.pgm"), dir.path().join("depot.pgm")).unwrap();
    std::fs::write(&f, "image: depot.pgm\nresolution: -0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.25\n").unwrap();
    assert_bad_input(&usar(&["scene", "info", f.to_str().unwrap()]), "resolution");
    let pgm = shared("ros/willow-full.pgm");
    assert_bad_input(
        &usar(&[
            "scene",
            "info",
            pgm.to_str().unwrap(),
            "--resolution",
            "-0.1",
        ]),
        "resolution",
    );
}

#[test]
fn unknown_scene_name_and_missing_file_are_bad_input() {
    assert_bad_input(
        &usar(&["scene", "info", "warehouse-of-dreams"]),
        "warehouse-of-dreams",
    );
    assert_bad_input(
        &usar(&[
            "explore",
            "--scene",
            "office",
            "--robots",
            "40",
            "--minutes",
            "1",
        ]),
        "start poses",
    );
}

#[test]
fn generating_twice_gives_identical_bytes_and_the_file_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, c) = (
        dir.path().join("a.json"),
        dir.path().join("b.json"),
        dir.path().join("c.json"),
    );
    for f in [&a, &b] {
        let out = usar(&[
            "scene",
            "gen",
            "course",
            "--seed",
            "4",
            "-o",
            f.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let out = usar(&[
        "scene",
        "export",
        a.to_str().unwrap(),
        "--scene-file",
        c.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&c).unwrap());
}

#[test]
fn furniture_share_shapes_the_office_and_bad_shares_are_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let generate = |extra: &[&str], out: &str| {
        let mut args = vec!["scene", "gen", "office", "--seed", "2", "-o", out];
        args.extend_from_slice(extra);
        usar(&args)
    };
    for (extra, out) in [
        (&[][..], path("default.json")),
        (&["--furniture", "0.05"][..], path("five.json")),
        (&["--furniture", "0.02"][..], path("two.json")),
    ] {
        let o = generate(extra, &out);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    // 0.05 is the office's own share; 0.02 furnishes the same floor plan more sparsely.
    assert_eq!(read("default.json"), read("five.json"));
    assert_ne!(read("default.json"), read("two.json"));

    assert_bad_input(
        &generate(&["--furniture", "0.5"], &path("bad.json")),
        "found 0.5, expected a number in [0, 0.3]",
    );
    let rubble = usar(&[
        "scene",
        "gen",
        "rubble",
        "--furniture",
        "0.1",
        "-o",
        &path("bad.json"),
    ]);
    assert_bad_input(&rubble, "only office and mall");
    assert!(!dir.path().join("bad.json").exists());
}

#[test]
fn scene_info_json_reports_ground_truth() {
    let out = usar(&["scene", "info", "course", "--seed", "1", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["junctions"].as_array().unwrap().len() >= 4);
    assert!(v["reachable_area_m2"].as_f64().unwrap() > 50.0);
}

#[test]
fn movingai_scenarios_match_their_optimal_lengths() {
    let scen = shared("movingai/room-32-32-4-random-1.scen");
    let out = usar(&["plan", "--scen", scen.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["scenarios"], v["matched"]);
    assert!(v["max_abs_error"].as_f64().unwrap() < 1e-3);
}

#[test]
fn plan_without_a_route_exits_3_with_the_reason() {
    // Above the course's stairs: the crawler climbs them, the wheeled robot cannot.
    let above_stairs = "30.5,13";
    let plan = |robot: &str| {
        usar(&[
            "plan",
            "--scene",
            "course",
            "--from",
            "2,5",
            "--to",
            above_stairs,
            "--robot",
            robot,
        ])
    };
    let crawler = plan("crawler");
    assert_eq!(
        crawler.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&crawler.stderr)
    );
    let wheeled = plan("wheeled");
    let stderr = String::from_utf8_lossy(&wheeled.stderr);
    assert_eq!(wheeled.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("no route for robot wheeled"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
}

#[test]
fn plan_outside_the_scene_is_bad_input() {
    let out = usar(&[
        "plan", "--scene", "course", "--from", "2,5", "--to", "-5,-5",
    ]);
    assert_bad_input(&out, "--to -5,-5 lies outside the scene");
}

#[test]
fn explore_is_deterministic_across_runs_and_thread_counts() {
    let args = [
        "explore",
        "--scene",
        "office",
        "--robots",
        "3",
        "--seed",
        "5",
        "--minutes",
        "2",
        "--json",
    ];
    let one = usar_env(&args, &[("RAYON_NUM_THREADS", "1")]);
    let two = usar_env(&args, &[("RAYON_NUM_THREADS", "2")]);
    let again = usar_env(&args, &[("RAYON_NUM_THREADS", "2")]);
    assert!(
        one.status.success(),
        "{}",
        String::from_utf8_lossy(&one.stderr)
    );
    assert_eq!(one.stdout, two.stdout);
    assert_eq!(two.stdout, again.stdout);
    let v: serde_json::Value = serde_json::from_slice(&one.stdout).unwrap();
    assert!(v["coverage"].as_f64().unwrap() > 0.05);
}

#[test]
fn help_explains_the_commands() {
    let out = usar(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for word in ["scene", "plan", "explore", "demo", "bench", "Exit codes"] {
        assert!(text.contains(word), "{word} missing from --help");
    }
}

#[test]
fn maxq_taxi_reaches_the_optimal_return() {
    let out = usar(&["maxq", "taxi", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let optimal = v["optimal_return"].as_f64().unwrap();
    assert!(v["maxq_return"].as_f64().unwrap() >= optimal - 0.5);
    assert!(v["flat_return"].as_f64().is_some());
    assert!(
        v["maxq_episodes_to_optimal"].as_u64().unwrap()
            < v["flat_episodes_to_optimal"].as_u64().unwrap_or(u64::MAX)
    );
}

#[test]
fn team_run_prints_relevant_and_total_area_every_minute() {
    let args = [
        "team",
        "run",
        "--scene",
        "office",
        "--robots",
        "3",
        "--strategy",
        "s-mcdm",
        "--coordination",
        "mrv2",
        "--hypothesis",
        "small",
        "--minutes",
        "2",
        "--seed",
        "4",
        "--json",
    ];
    let out = usar(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.stdout, usar(&args).stdout, "a run is deterministic");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in ["relevant_area_m2", "total_area_m2", "distance_m"] {
        assert!(v[key].as_f64().is_some(), "{key} missing");
    }
    assert!(v["total_area_m2"].as_f64().unwrap() > 100.0);
    let series = v["series"].as_array().unwrap();
    assert_eq!(series.len(), 3, "minutes 0, 1, 2");
    assert!(series[2]["relevant_area_m2"].as_f64().is_some());
    // The allocation trace: one row per allocation, each room's known fraction in [0, 1].
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("trace.csv");
    let traced = usar(&[&args[..], &["--trace", trace.to_str().unwrap()]].concat());
    assert_eq!(traced.stdout, out.stdout, "tracing changes nothing");
    let csv = std::fs::read_to_string(&trace).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let known = header.iter().position(|&h| h == "room_known").unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.len() >= 3, "every robot is allocated a target");
    for row in &rows {
        assert_eq!(row.len(), header.len());
        if !row[known].is_empty() {
            let f: f64 = row[known].parse().unwrap();
            assert!((0.0..=1.0).contains(&f), "room_known {f}");
        }
    }
    assert!(rows.iter().any(|r| !r[known].is_empty()));
    assert_bad_input(
        &usar(&["team", "run", "--strategy", "greedy", "--json"]),
        "expected random, distance, d-mcdm, s-mcdm",
    );
    assert_bad_input(
        &usar(&["team", "run", "--label-errors", "random:2", "--json"]),
        "expected a fraction in [0, 1]",
    );
    assert_bad_input(
        &usar(&["team", "run", "--candidates", "rooms", "--json"]),
        "--candidates: found \"rooms\", expected room or cluster",
    );
}

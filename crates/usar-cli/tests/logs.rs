//! `usar log import` and `usar map build --from-log` on a real log, and bad logs refused.

use super::{assert_bad_input, usar, usar_json};
use std::path::{Path, PathBuf};

fn duke() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/datasets/duke_dpslam_loop5/loop5.log")
}

#[test]
fn a_real_log_imports_to_mcap_and_maps_with_its_pictures() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("duke.mcap");
    let log = duke();
    let v = usar_json(&[
        "log",
        "import",
        log.to_str().unwrap(),
        "--out",
        mcap.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["format"], "dpslam");
    assert_eq!(v["scans"], 551);
    assert_eq!(v["messages"], 1 + 4 * 551);
    // The MCAP file reads back as a rosbag2 log.
    let back = usar_json(&["log", "import", mcap.to_str().unwrap(), "--json"]);
    assert_eq!(
        (back["format"].as_str(), back["scans"].as_u64()),
        (Some("rosbag2"), Some(551))
    );

    let out = dir.path().join("map");
    let s = usar_json(&[
        "map",
        "build",
        "--from-log",
        log.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(s["matcher"], "correlative");
    assert_eq!(s["scans_drawn"], 551);
    assert!(s["known_area_m2"].as_f64().unwrap() > 100.0, "{s}");
    for file in [
        "map.yaml",
        "map.pgm",
        "map.png",
        "rooms.png",
        "trajectory.csv",
        "summary.json",
    ] {
        assert!(out.join(file).is_file(), "{file}");
    }
    // The map reads back as a scene, its free cells free (unknown ones blocked).
    let scene = usar_json(&[
        "scene",
        "info",
        out.join("map.yaml").to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(scene["grid"]["width"], s["width_cells"]);
    let free = scene["free_area_m2"].as_f64().unwrap();
    assert!(
        (free - s["free_area_m2"].as_f64().unwrap()).abs() < 1e-6,
        "{scene}"
    );
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    assert_eq!(csv.lines().count(), 552);
}

/// A BTM built passively along the Duke loop: a start and an end, divergence nodes at the
/// loop's corners, every link searched between them; the map file reads back and validates.
#[test]
fn a_passive_btm_follows_a_real_log() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("duke.sqlite");
    let png = dir.path().join("duke.png");
    let log = duke();
    let v = usar_json(&[
        "btm",
        "build",
        "--from-log",
        log.to_str().unwrap(),
        "--robot",
        "wheeled",
        "--out",
        out.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["scans"], 551);
    let nodes = v["nodes"].as_array().unwrap();
    let kinds = |k: &str| nodes.iter().filter(|n| n["kind"] == k).count();
    assert_eq!(kinds("terminal"), 2, "{v}");
    // The loop turns four corners; side doors and halls add more.
    assert!(kinds("divergence") >= 4, "{v}");
    assert!(png.is_file());
    let back = usar_json(&["btm", "export", out.to_str().unwrap(), "--json"]);
    assert_eq!(back["nodes"].as_array().unwrap().len(), nodes.len());
    // The searched links chain the nodes along the path: one fewer than the nodes passed,
    // or more where a loop closed onto a known node.
    let searched = back["links"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|l| l["searched"] == true)
        .count();
    assert!(
        searched + 1 >= nodes.len(),
        "{searched} links for {} nodes",
        nodes.len()
    );
}

#[test]
fn bad_logs_and_parameters_are_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.log");
    std::fs::write(&bad, "Odometry 0 0 0\nLaser 181 1.0 2.0\n").unwrap();
    let out = usar(&["log", "import", bad.to_str().unwrap()]);
    assert_bad_input(
        &out,
        "bad.log:2: Laser: the record ends before its reading 3 of 181",
    );
    let out = usar(&[
        "map",
        "build",
        "--from-log",
        duke().to_str().unwrap(),
        "--matcher",
        "magic",
    ]);
    assert_bad_input(&out, "--matcher magic: expected correlative, icp, odometry");
    let out = usar(&[
        "map",
        "build",
        "--from-log",
        duke().to_str().unwrap(),
        "--resolution",
        "0",
    ]);
    assert_bad_input(&out, "resolution 0 m (expected 0.005 to 1 m)");
    let out = usar(&["log", "import", duke().to_str().unwrap(), "--format", "bag"]);
    assert_bad_input(
        &out,
        "--format bag: expected carmen, dpslam, thrun, rosbag2",
    );
    let out = usar(&[
        "log",
        "import",
        dir.path().join("missing.log").to_str().unwrap(),
    ]);
    assert_bad_input(&out, "missing.log");
}

/// A log larger than the input limit is refused before it fills memory.
#[test]
fn a_log_past_the_file_size_limit_is_refused() {
    let out = usar(&[
        "log",
        "import",
        duke().to_str().unwrap(),
        "--max-file-mb",
        "0",
    ]);
    assert_bad_input(&out, "raise the limit with --max-file-mb");
}

//! `usar scene segment` and `usar team run` on maps without a room layer.

use super::{assert_bad_input, shared, usar};

fn intel(name: &str) -> String {
    shared("segmentation").join(name).display().to_string()
}

#[test]
fn scene_segment_scores_the_intel_lab_and_draws_the_rooms() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("rooms.png");
    let out = usar(&[
        "scene",
        "segment",
        &intel("lab_intel.png"),
        "--resolution",
        "0.05",
        "--free-thresh",
        "0.02",
        "--truth-rooms",
        &intel("lab_intel_gt_segmentation.png"),
        "--truth-classes",
        &intel("training_intel.png"),
        "--png",
        png.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["truth_rooms"]["truth_rooms"], 26);
    // The same bounds as usar-map's Intel test (measured 0.975 / 0.923 / 0.727 / 0.897).
    assert!(v["truth_rooms"]["recall"].as_f64().unwrap() >= 0.93, "{v}");
    assert!(
        v["truth_rooms"]["precision"].as_f64().unwrap() >= 0.88,
        "{v}"
    );
    assert!(v["truth_rooms"]["jaccard"].as_f64().unwrap() >= 0.68, "{v}");
    assert!(
        v["truth_classes"]["accuracy"].as_f64().unwrap() >= 0.85,
        "{v}"
    );
    assert!(v["labels"]["corridor"]["segments"].as_u64().unwrap() >= 1);
    assert!(
        std::fs::metadata(&png).unwrap().len() > 1000,
        "a PNG was written"
    );
    // A ground truth of another size is bad input.
    assert_bad_input(
        &usar(&[
            "scene",
            "segment",
            "office",
            "--truth-rooms",
            &intel("training_intel.png"),
        ]),
        "expected the map's",
    );
    let bad = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(bad.path(), "door_ratio = 0.7\ndoor_width = 2\n").unwrap();
    assert_bad_input(
        &usar(&[
            "scene",
            "segment",
            "office",
            "--params",
            bad.path().to_str().unwrap(),
        ]),
        "line 2, column 1: unknown field `door_width`",
    );
}

fn team_json(scene: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "team",
        "run",
        "--scene",
        scene,
        "--robots",
        "3",
        "--strategy",
        "s-mcdm",
        "--hypothesis",
        "small",
        "--minutes",
        "1",
        "--seed",
        "2",
        "--json",
    ];
    args.extend_from_slice(extra);
    let out = usar(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.stdout, usar(&args).stdout, "a run is deterministic");
    serde_json::from_slice(&out.stdout).unwrap()
}

fn assert_explored(v: &serde_json::Value) {
    assert!(
        v["relevant_total_m2"].as_f64().unwrap() > 100.0,
        "small rooms found: {v}"
    );
    assert!(v["relevant_area_m2"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["total_area_m2"].as_f64().unwrap() > 100.0, "{v}");
    assert!(v["distance_m"].as_f64().unwrap() > 10.0, "{v}");
    assert_eq!(v["series"].as_array().unwrap().len(), 2, "minutes 0 and 1");
}

#[test]
fn team_run_segments_a_real_map_and_a_scene_file_without_rooms() {
    let willow = shared("ros/willow-full.pgm").display().to_string();
    let from_map = team_json(&willow, &["--resolution", "0.1"]);
    assert_explored(&from_map);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("willow.json");
    let out = usar(&[
        "scene",
        "import",
        &willow,
        "--resolution",
        "0.1",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let from_file = team_json(file.to_str().unwrap(), &[]);
    assert_explored(&from_file);
    assert_eq!(
        from_map["relevant_area_m2"], from_file["relevant_area_m2"],
        "the map and its scene file are the same scene"
    );
}

//! `usar mission run`: the whole mission in one world.

use super::{assert_bad_input, usar, usar_json};

#[test]
fn the_built_in_mission_writes_its_report_and_prints_every_system() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("report");
    let v = usar_json(&[
        "mission",
        "run",
        "--minutes",
        "1",
        "--out",
        out_dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["team"]["robots"], 4);
    assert!(v["crawler"]["nodes"].as_u64().unwrap() > 0);
    assert!(v["radio"]["delivered"].as_u64().unwrap() > 0);
    assert_eq!(v["rescuer"]["zone_cells"], 100);
    let victims = &v["victim_figures"];
    let count = |k: &str| victims[k].as_u64().unwrap();
    assert_eq!(count("detected") + count("missed"), count("total"));
    assert!(v["operator"]["answered"].as_u64() <= v["operator"]["asked"].as_u64());
    assert!(v["wall_time_s"].as_f64().unwrap() > 0.0);
    for f in [
        "map.png",
        "victims.csv",
        "handoffs.csv",
        "coverage.csv",
        "summary.json",
    ] {
        assert!(out_dir.join(f).is_file(), "{f}");
    }
    let table = std::fs::read_to_string(out_dir.join("victims.csv")).unwrap();
    assert!(
        table.starts_with("id,x_m,y_m,detected_by,detected_at_s,confirmed_by,confirmed_at_s\n")
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["team"], v["team"]);
}

#[test]
fn a_mission_file_with_an_unknown_field_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("m.toml");
    std::fs::write(&f, "minutes = 1\n[crawler]\nshare_every = 3\n").unwrap();
    assert_bad_input(
        &usar(&["mission", "run", f.to_str().unwrap()]),
        "share_every",
    );
    std::fs::write(&f, "minutes = 1\n[team]\nstrategy = \"best\"\n").unwrap();
    assert_bad_input(&usar(&["mission", "run", f.to_str().unwrap()]), "strategy");
}

#[test]
fn a_bad_rescuer_or_operator_field_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("m.toml");
    std::fs::write(&f, "minutes = 1\n[rescuer]\nzone = \"attic\"\n").unwrap();
    assert_bad_input(
        &usar(&["mission", "run", f.to_str().unwrap()]),
        "rescuer.zone",
    );
    std::fs::write(&f, "minutes = 1\n[operator]\ndelay = 3\n").unwrap();
    assert_bad_input(
        &usar(&["mission", "run", f.to_str().unwrap()]),
        "unknown field `delay`",
    );
}

#[test]
fn a_recorded_mission_is_the_same_mission_and_leaves_one_complete_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.mcap");
    let args = ["mission", "run", "--minutes", "0.3", "--json"];
    let plain = usar_json(&args);
    let mut with = args.to_vec();
    with.extend(["--record", file.to_str().unwrap()]);
    let recorded = usar_json(&with);
    // Recording watches the mission; it changes nothing in it.
    let strip = |mut v: serde_json::Value| {
        v.as_object_mut().unwrap().remove("wall_time_s");
        v
    };
    assert_eq!(strip(plain), strip(recorded));
    let bytes = std::fs::read(&file).unwrap();
    assert!(bytes.starts_with(b"\x89MCAP0\r\n") && bytes.ends_with(b"\x89MCAP0\r\n"));
    assert!(!dir.path().join("run.mcap.partial").exists());
    // A file that cannot be created is the user's to fix, and nothing is left behind.
    let missing = dir.path().join("no/such/dir/run.mcap");
    let out = usar(&[
        "mission",
        "run",
        "--minutes",
        "0.1",
        "--record",
        missing.to_str().unwrap(),
    ]);
    assert_bad_input(&out, "--record");
    assert!(!dir.path().join("no").exists());
}

//! A recorded mission read back by independent clients: the MCAP project's Python readers
//! (`mcap` and `mcap-ros2-support`, the libraries behind Foxglove's own tooling) decode every
//! message with the schemas the file carries, and so does `rosbags`, a reader of its own. `./test.sh` installs them into a virtual
//! environment and sets `USAR_PYTHON`.

use std::sync::Arc;
use usar_mission::{MissionConfig, Operator, run_mission_live};
use usar_record::{MissionRecorder, Recording};
use usar_world::generate::{SceneKind, generate};

#[test]
fn python_mcap_decodes_every_message_of_a_recorded_mission() {
    let python = std::env::var("USAR_PYTHON")
        .expect("USAR_PYTHON: a Python with mcap and mcap-ros2-support; ./test.sh sets one up");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mission.mcap");
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let mut config = MissionConfig {
        minutes: 0.5,
        ..MissionConfig::default()
    };
    config.rescuer.train_trials = 20;
    let file = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    let mut recorder = MissionRecorder::new(Recording::new(file).unwrap());
    run_mission_live(
        scene,
        &config,
        1,
        None,
        Operator::Simulated,
        |_| {},
        &mut recorder,
    )
    .unwrap();
    let written = recorder.finish().unwrap();

    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/read_mcap.py");
    let out = std::process::Command::new(&python)
        .arg(script)
        .arg(&path)
        .output()
        .unwrap_or_else(|e| panic!("{python}: {e}"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let count = |topic: &str| v["counts"][topic].as_u64().unwrap_or(0);
    // Every message written was decoded.
    let decoded: u64 = v["counts"]
        .as_object()
        .unwrap()
        .values()
        .map(|c| c.as_u64().unwrap())
        .sum();
    assert_eq!(decoded, written, "{v}");
    assert_eq!(v["profile"], "ros2");
    // 30 simulated seconds at 10 steps a second, the first step included.
    assert_eq!(count("/clock"), 301, "{v}");
    assert_eq!(count("/tf"), 301);
    assert!(
        (v["last_clock_s"].as_f64().unwrap() - 30.0).abs() < 1e-6,
        "{v}"
    );
    assert!((v["last_log_time_s"].as_f64().unwrap() - 30.0).abs() < 1e-6);
    assert_eq!(v["tf"]["parents"], serde_json::json!(["map"]));
    assert_eq!(
        v["tf"]["children"],
        serde_json::json!(["crawler", "rescuer", "team_1", "team_2", "team_3", "team_4"])
    );
    assert_eq!(v["tf"]["unit_quaternions"], true);
    for k in 1..=4 {
        assert!(count(&format!("/team_{k}/scan")) >= 29, "{v}");
    }
    assert_eq!(v["schemas"]["/team_1/scan"], "sensor_msgs/msg/LaserScan");
    assert_eq!(v["scan"]["frame"], "team_1");
    assert!(v["scan"]["beams"].as_u64().unwrap() >= 180);
    assert!(v["scan"]["returns"].as_u64().unwrap() > 0, "{v}");
    assert_eq!(v["odom"]["frame"], "map");
    // The merged map every 2.5 s: -1 unknown, 0 free, 100 occupied, some of it known.
    assert_eq!(count("/map"), 13);
    let map = &v["map"];
    assert_eq!(
        map["cells"].as_u64().unwrap(),
        map["width"].as_u64().unwrap() * map["height"].as_u64().unwrap()
    );
    assert!(map["known"].as_u64().unwrap() > 1000, "{map}");
    assert_eq!(map["values"], serde_json::json!([-1, 0, 100]));
    // The crawler's BTM had grown nodes (plus the clearing marker and the links).
    assert!(v["btm_markers"].as_u64().unwrap() >= 3, "{v}");
    // Markers once a simulated second, from the first step to the last.
    assert_eq!(count("/victims"), 31);

    // The rosbags package decodes every message too, in time order.
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/read_rosbags.py");
    let out = std::process::Command::new(&python)
        .arg(script)
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["counts"], v["counts"], "{r}");
    assert_eq!(r["monotonic"], true);
}

//! The bridge against an independent DDS: Eclipse Cyclone DDS from Python (`cyclonedds`, in
//! the virtual environment `./test.sh` makes; its interpreter is `USAR_PYTHON`), on loopback,
//! in a DDS domain of this test's own.
//!
//! - the simulated robot's `LaserScan` reaches the peer at the simulated rate (10 Hz), and the
//!   peer's `Twist` on `/cmd_vel` drives it;
//! - the explorer node, fed a real log (Duke's) replayed over DDS by the peer, publishes goals.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use usar_ros2::explore::{ExploreOptions, run_explore};
use usar_ros2::sim::{SimOptions, run_sim};
use usar_ros2::{BridgeOptions, Topics};
use usar_world::generate::{SceneKind, generate};

fn peer(args: &[&str], domain: u16) -> serde_json::Value {
    let python = std::env::var("USAR_PYTHON")
        .expect("USAR_PYTHON: a Python with cyclonedds; ./test.sh sets one up");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let out = std::process::Command::new(python)
        .arg(dir.join("dds_peer.py"))
        .args(args)
        .env("ROS_DOMAIN_ID", domain.to_string())
        .env(
            "CYCLONEDDS_URI",
            format!("file://{}", dir.join("cyclone-loopback.xml").display()),
        )
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    serde_json::from_str(text.lines().last().unwrap_or(""))
        .unwrap_or_else(|e| panic!("{e}: {text}"))
}

/// A domain of this process's own (0–232 are valid), so parallel runs do not meet.
fn domain(offset: u16) -> u16 {
    (std::process::id() % 100) as u16 + 100 + offset
}

#[test]
fn a_cyclone_dds_peer_hears_the_simulated_laser_and_drives_the_robot() {
    let bridge = BridgeOptions {
        domain: domain(0),
        loopback: true,
    };
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let stop = Arc::new(AtomicBool::new(false));
    let options = SimOptions {
        duration_s: Some(14.0),
        ..SimOptions::default()
    };
    let sim = {
        let (scene, stop, bridge) = (scene.clone(), stop.clone(), bridge.clone());
        std::thread::spawn(move || run_sim(scene, &options, &bridge, &Topics::default(), &stop))
    };
    let v = peer(&["sim", "4"], bridge.domain);
    let report = sim.join().unwrap().unwrap();
    eprintln!("peer: {v}; sim: {report:?}");
    let hz = v["scan_hz"].as_f64().unwrap_or_else(|| panic!("{v}"));
    // The simulated laser runs at 10 Hz of simulated time, paced at real time.
    assert!((8.5..=11.5).contains(&hz), "{v}");
    assert_eq!(v["beams"], 360);
    assert_eq!(v["frame"], "laser");
    assert!(report.commands >= 20, "{report:?}");
    let moved = report.start.position().distance(report.end.position());
    assert!(moved > 0.5, "the robot moved {moved} m: {report:?}");
}

#[test]
fn the_explorer_node_on_a_replayed_real_log_publishes_goals() {
    let bridge = BridgeOptions {
        domain: domain(1),
        loopback: true,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let explorer = {
        let (stop, bridge) = (stop.clone(), bridge.clone());
        let options = ExploreOptions {
            duration_s: Some(60.0),
            ..ExploreOptions::default()
        };
        std::thread::spawn(move || run_explore(&options, &bridge, &Topics::default(), &stop))
    };
    let log = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/datasets/duke_dpslam_loop5/loop5.log");
    let v = peer(&["replay", log.to_str().unwrap(), "40"], bridge.domain);
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let report = explorer.join().unwrap().unwrap();
    eprintln!("peer: {v}; explorer: {report:?}");
    assert_eq!(v["scans_sent"], 551, "{v}");
    // Best effort on loopback: nearly every scan arrives.
    assert!(report.scans > 500, "{report:?}");
    assert!(v["goals"].as_u64().unwrap() >= 3, "{v}");
    assert_eq!(v["frame"], "map");
    let goal = report.last_goal.unwrap();
    assert!(goal.x.is_finite() && goal.y.is_finite());
}

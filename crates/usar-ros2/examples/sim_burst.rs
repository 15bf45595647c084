//! The simulated ROS 2 robot for two simulated seconds at 20 × real time, on loopback, with
//! nobody listening: `cargo run -p usar-ros2 --example sim_burst`.

use std::sync::{Arc, atomic::AtomicBool};
use usar_ros2::sim::{SimOptions, run_sim};
use usar_ros2::{BridgeOptions, Topics};
use usar_world::generate::{SceneKind, generate};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let options = SimOptions {
        speed: 20.0,
        duration_s: Some(2.0),
        ..SimOptions::default()
    };
    let bridge = BridgeOptions {
        domain: 199,
        loopback: true,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let r = run_sim(scene, &options, &bridge, &Topics::default(), &stop)?;
    println!(
        "{} steps, {} scans published on /scan, {} commands heard; the robot stayed at ({:.2}, {:.2})",
        r.steps, r.scans, r.commands, r.end.x, r.end.y
    );
    Ok(())
}

//! The BTM builder on your own robot: each control step you hand it the crawler's readings —
//! the 2-D laser, the laser tilted at the floor, attitude, odometry, the bumper — and drive the
//! velocity it returns. Here "your robot" is a bare `usar_sim::Simulation` on the test course
//! (no host), standing in for a real robot's drivers or another simulator.
//!
//! Run with `cargo run --release -p usar-btm --example btm_from_your_readings`.

use std::sync::Arc;
use usar_btm::build::{BuildConfig, CrawlerReadings, Explorer};
use usar_sim::{RobotSpec, SimConfig, Simulation};
use usar_world::generate::{SceneKind, generate};

fn main() {
    let scene = Arc::new(generate(SceneKind::Course, 1));
    let start = scene.start_poses[0];
    let spec = RobotSpec::crawler();
    let config = BuildConfig {
        max_time_s: 300.0,
        ..BuildConfig::default()
    };
    // Your robot and its drivers.
    let mut robot = Simulation::new(scene, SimConfig::default(), 1);
    let id = robot
        .add_robot(spec.clone(), start)
        .expect("a free start pose");
    // The builder, in the frame of where the robot starts.
    let mut builder = Explorer::new(spec, &config, start, None);
    let mut readings = CrawlerReadings::new(start);
    loop {
        readings.time_s = robot.time_s();
        readings.contact = robot.robot(id).in_contact();
        robot.scan_laser(id, &mut readings.laser);
        readings.tilted = robot.read_tilted_laser(id);
        readings.attitude = robot.read_attitude(id);
        readings.odometry = robot.robot(id).odometry.clone();
        match builder.next_command(&readings) {
            Some(command) => robot.step(&[command]),
            None => break,
        }
    }
    let why = builder.take_finished().expect("it says why it stopped");
    let btm = builder.btm();
    println!(
        "after {:.0} s: {:?}; a BTM of {} nodes and {} links ({} searched)",
        robot.time_s(),
        why,
        btm.nodes.len(),
        btm.links.len(),
        btm.links.iter().filter(|l| l.searched).count()
    );
    assert!(!btm.nodes.is_empty());
}

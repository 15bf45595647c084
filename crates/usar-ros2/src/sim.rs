//! `usar ros2 sim`: one simulated robot on a scene as a ROS 2 robot. Each simulation step
//! (0.1 s of simulated time, paced at `speed` × real time) it publishes
//!
//! | topic | type | QoS |
//! |---|---|---|
//! | `/clock` | `rosgraph_msgs/Clock` | reliable |
//! | `/scan` | `sensor_msgs/LaserScan` (frame `laser`, +∞ for no return) | sensor data |
//! | `/odom` | `nav_msgs/Odometry` (`odom` → `base_link`, what the wheels tell) | reliable |
//! | `/tf` | `odom` → `base_link` | reliable |
//!
//! and once, at the start, `/tf_static` (`map` → `odom` and `base_link` → `laser`, both
//! identity: odometry starts at the robot's start pose in the scene's frame) and `/map` (the
//! scene's obstacles, transient local, as `map_server` would serve the floor). It obeys
//! `geometry_msgs/Twist` on `/cmd_vel` (linear x, angular z); a robot that hears no command
//! for `cmd_timeout_s` stops, as ROS 2 drive controllers do.

use crate::msgs::{self, Header, LaserScan, Odometry, TFMessage, TransformStamped};
use crate::{Bridge, BridgeError, BridgeOptions, StopFlag, Topics, qos, stopped, types};
use std::sync::Arc;
use std::time::{Duration, Instant};
use usar_sim::host::{Controller, FleetIo, Host, Oracles};
use usar_sim::{RobotSpec, SimConfig, Velocity};
use usar_world::{Pose2, Scene};

/// How the simulated robot runs.
#[derive(Clone, Debug)]
pub struct SimOptions {
    pub robot: RobotSpec,
    /// Seed of the sensor and odometry noise.
    pub seed: u64,
    /// Simulated seconds per wall second.
    pub speed: f64,
    /// Stop after this many simulated seconds (`None`: when stopped).
    pub duration_s: Option<f64>,
    /// A command older than this (simulated seconds) is dropped: the robot stops.
    pub cmd_timeout_s: f64,
}

impl Default for SimOptions {
    fn default() -> Self {
        Self {
            robot: RobotSpec::wheeled(),
            seed: 1,
            speed: 1.0,
            duration_s: None,
            cmd_timeout_s: 0.5,
        }
    }
}

/// What a run of the simulated robot did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimReport {
    pub steps: u64,
    pub scans: u64,
    /// `/cmd_vel` messages received.
    pub commands: u64,
    pub start: Pose2,
    /// Its true pose at the end.
    pub end: Pose2,
}

/// Drives the one robot with the latest command; keeps its readings for publishing.
struct Driver {
    command: Velocity,
    scan: usar_sim::sensors::LaserScan,
    odometry: Pose2,
    achieved: Velocity,
}

impl Controller for Driver {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        io.laser(0, &mut self.scan);
        self.odometry = io.odometry(0).estimate;
        self.achieved = io.achieved(0);
        io.command(0, self.command);
    }
}

/// The scene's obstacles as a ROS map: 100 on an obstacle, 0 elsewhere.
fn scene_map(scene: &Scene) -> msgs::OccupancyGrid {
    let data = scene
        .obstacle
        .as_slice()
        .iter()
        .map(|&o| {
            if o == usar_world::obstacle::NONE {
                0
            } else {
                100
            }
        })
        .collect();
    msgs::OccupancyGrid::from_cells(0.0, scene.geometry(), data)
}

/// Runs the robot at the scene's first start pose until `stop` is set or the duration is
/// reached.
pub fn run_sim(
    scene: Arc<Scene>,
    options: &SimOptions,
    bridge: &BridgeOptions,
    topics: &Topics,
    stop: &StopFlag,
) -> Result<SimReport, BridgeError> {
    let start = *scene
        .start_poses
        .first()
        .ok_or_else(|| BridgeError::Setup(format!("{}: no start pose", scene.name)))?;
    if !(options.speed.is_finite() && options.speed > 0.0) {
        return Err(BridgeError::Setup(format!(
            "speed {} (expected a positive factor)",
            options.speed
        )));
    }
    let mut node = Bridge::new("usar_sim", bridge)?;
    let clock = node.publisher::<msgs::Clock>(&topics.clock, types::CLOCK, qos::reliable())?;
    let scan_pub = node.publisher::<LaserScan>(&topics.scan, types::LASER_SCAN, qos::sensor())?;
    let odom_pub = node.publisher::<Odometry>(&topics.odom, types::ODOMETRY, qos::reliable())?;
    let tf_pub = node.publisher::<TFMessage>(&topics.tf, types::TF, qos::reliable())?;
    let tf_static = node.publisher::<TFMessage>(&topics.tf_static, types::TF, qos::map())?;
    let map_pub =
        node.publisher::<msgs::OccupancyGrid>(&topics.map, types::OCCUPANCY_GRID, qos::map())?;
    let cmd = node.subscription::<msgs::Twist>(&topics.cmd_vel, types::TWIST, qos::reliable())?;

    let config = SimConfig::default();
    let dt = config.dt_s;
    let mut host = Host::new(scene.clone(), config, options.seed, Oracles::default());
    let fleet = host
        .add_fleet(&[(options.robot.clone(), start)])
        .map_err(|e| BridgeError::Setup(format!("{}: {e}", scene.name)))?;
    let id = host.fleet(fleet)[0];
    let identity = Pose2::new(0.0, 0.0, 0.0);
    tf_static
        .publish(TFMessage {
            transforms: vec![
                TransformStamped::planar(0.0, "map", "odom", identity),
                TransformStamped::planar(0.0, "base_link", "laser", identity),
            ],
        })
        .map_err(crate::dds)?;
    map_pub.publish(scene_map(&scene)).map_err(crate::dds)?;

    let mut driver = Driver {
        command: Velocity::default(),
        scan: usar_sim::sensors::LaserScan::default(),
        odometry: start,
        achieved: Velocity::default(),
    };
    let mut report = SimReport {
        steps: 0,
        scans: 0,
        commands: 0,
        start,
        end: start,
    };
    let mut last_command_s = f64::NEG_INFINITY;
    let wall = Instant::now();
    while !stopped(stop) && options.duration_s.is_none_or(|d| host.time_s() < d) {
        let t = host.time_s();
        while let Ok(Some((twist, _))) = cmd.take() {
            driver.command = Velocity {
                linear_mps: twist.linear.x,
                angular_radps: twist.angular.z,
            };
            last_command_s = t;
            report.commands += 1;
        }
        if t - last_command_s > options.cmd_timeout_s {
            driver.command = Velocity::default();
        }
        host.decide(fleet, &mut driver);
        publish_step(t, dt, &driver, &clock, &scan_pub, &odom_pub, &tf_pub)?;
        report.scans += 1;
        host.advance();
        report.steps += 1;
        // Pace: simulated time runs at `speed` × the wall clock.
        let due = Duration::from_secs_f64(host.time_s() / options.speed);
        if let Some(wait) = due.checked_sub(wall.elapsed()) {
            std::thread::sleep(wait.min(Duration::from_secs_f64(dt)));
        }
    }
    report.end = host.evaluator().robot(id).pose;
    Ok(report)
}

fn publish_step(
    t: f64,
    dt: f64,
    d: &Driver,
    clock: &ros2_client::Publisher<msgs::Clock>,
    scan: &ros2_client::Publisher<LaserScan>,
    odom: &ros2_client::Publisher<Odometry>,
    tf: &ros2_client::Publisher<TFMessage>,
) -> Result<(), BridgeError> {
    clock
        .publish(msgs::Clock {
            clock: msgs::Time::from_s(t),
        })
        .map_err(crate::dds)?;
    let s = &d.scan;
    let n = s.ranges_m.len().max(1);
    scan.publish(LaserScan {
        header: Header::new(t, "laser"),
        angle_min: s.angle_min_rad as f32,
        angle_max: (s.angle_min_rad + s.angle_increment_rad * (n - 1) as f64) as f32,
        angle_increment: s.angle_increment_rad as f32,
        time_increment: 0.0,
        scan_time: dt as f32,
        range_min: 0.0,
        range_max: s.max_range_m as f32,
        ranges: s.ranges_m.clone(),
        intensities: Vec::new(),
    })
    .map_err(crate::dds)?;
    let v = d.achieved;
    odom.publish(Odometry::planar(
        t,
        "odom",
        "base_link",
        d.odometry,
        v.linear_mps,
        v.angular_radps,
    ))
    .map_err(crate::dds)?;
    tf.publish(TFMessage {
        transforms: vec![TransformStamped::planar(t, "odom", "base_link", d.odometry)],
    })
    .map_err(crate::dds)?;
    Ok(())
}

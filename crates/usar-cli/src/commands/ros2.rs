//! `usar ros2 sim | explore | btm`: the live ROS 2 bridge of `usar-ros2`, in a build with
//! `--features ros2`; without it, the commands say how to get it.

use crate::cli::Ros2Command;
use crate::failure::CmdResult;

#[cfg(not(feature = "ros2"))]
pub fn run(_cmd: Ros2Command) -> CmdResult {
    Err(crate::failure::bad_input(anyhow::anyhow!(
        "usar was built without the ROS 2 bridge: build it with `cargo build --release --features ros2`"
    )))
}

#[cfg(feature = "ros2")]
pub fn run(cmd: Ros2Command) -> CmdResult {
    bridge::run(cmd)
}

#[cfg(feature = "ros2")]
mod bridge {
    use super::super::print_json;
    use crate::cli::{Ros2Args, Ros2Command};
    use crate::failure::{CmdResult, InputContext, bad_input};
    use crate::scene_source;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    use usar_ros2::explore::{ExploreOptions, run_explore};
    use usar_ros2::sim::{SimOptions, run_sim};
    use usar_ros2::{BridgeOptions, StopFlag, Topics};

    /// The domain, the topics and a stop flag set at Ctrl-C or after --seconds.
    fn setup(ros: &Ros2Args) -> CmdResult<(BridgeOptions, Topics, StopFlag)> {
        let mut bridge = BridgeOptions::from_env();
        if let Some(d) = ros.domain {
            if d > 232 {
                return Err(bad_input(anyhow::anyhow!(
                    "--domain {d}: expected 0 to 232"
                )));
            }
            bridge.domain = d;
        }
        bridge.loopback |= ros.localhost;
        let mut topics = Topics::default();
        topics.remap(&ros.remaps).input()?;
        if ros.seconds.is_some_and(|s| !(s.is_finite() && s > 0.0)) {
            return Err(bad_input(anyhow::anyhow!(
                "--seconds: expected a positive number"
            )));
        }
        let stop: StopFlag = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        std::thread::spawn(move || {
            let runtime = tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build();
            if let Ok(rt) = runtime {
                rt.block_on(async {
                    let _ = tokio::signal::ctrl_c().await;
                });
                flag.store(true, Ordering::Relaxed);
            }
        });
        if let Some(s) = ros.seconds {
            let flag = stop.clone();
            std::thread::spawn(move || {
                std::thread::sleep(std::time::Duration::from_secs_f64(s));
                flag.store(true, Ordering::Relaxed);
            });
        }
        Ok((bridge, topics, stop))
    }

    pub fn run(cmd: Ros2Command) -> CmdResult {
        match cmd {
            Ros2Command::Sim(args) => {
                let scene = scene_source::load(&args.scene, args.scene_seed, &args.image)?;
                let robot = scene_source::load_robot(&args.robot)?;
                let (bridge, topics, stop) = setup(&args.ros)?;
                let options = SimOptions {
                    robot,
                    seed: args.seed,
                    speed: args.speed,
                    ..SimOptions::default()
                };
                eprintln!(
                    "usar ros2 sim: {} on {} (domain {}), publishing {} {} {} {} {}, obeying {}",
                    options.robot.name,
                    scene.name,
                    bridge.domain,
                    topics.scan,
                    topics.odom,
                    topics.tf,
                    topics.map,
                    topics.clock,
                    topics.cmd_vel
                );
                let r = run_sim(Arc::new(scene), &options, &bridge, &topics, &stop).input()?;
                print_json(&serde_json::json!({
                    "steps": r.steps,
                    "scans": r.scans,
                    "commands": r.commands,
                    "start": r.start,
                    "end": r.end,
                }))
            }
            Ros2Command::Explore(args) => {
                let (bridge, topics, stop) = setup(&args.ros)?;
                let options = ExploreOptions {
                    size_m: args.size,
                    resolution_m: args.resolution,
                    scan_matching: !args.no_scan_matching,
                    ..ExploreOptions::default()
                };
                if !(options.resolution_m > 0.0
                    && options.size_m / options.resolution_m <= 10_000.0)
                {
                    return Err(bad_input(anyhow::anyhow!(
                        "--size / --resolution: at most 10 000 cells a side"
                    )));
                }
                eprintln!(
                    "usar ros2 explore (domain {}): on {} and {}, publishing {} {} {}",
                    bridge.domain,
                    topics.scan,
                    topics.odom,
                    topics.goal,
                    topics.map,
                    topics.markers
                );
                let r = run_explore(&options, &bridge, &topics, &stop).input()?;
                print_json(&serde_json::json!({
                    "scans": r.scans,
                    "goals": r.goals,
                    "last_goal": r.last_goal,
                }))
            }
            Ros2Command::Btm(args) => {
                let robot = scene_source::load_robot(&args.robot)?;
                let (bridge, topics, stop) = setup(&args.ros)?;
                let partial = usar_world::partial_path(&args.out);
                let _ = std::fs::remove_file(&partial);
                let store = usar_btm::store::BtmStore::create(&partial).input()?;
                eprintln!(
                    "usar ros2 btm (domain {}): on {} and {}, publishing {}",
                    bridge.domain, topics.scan, topics.odom, topics.markers
                );
                let btm = usar_ros2::btm::run_btm(
                    usar_btm::build::BuildConfig::default(),
                    robot.width_m,
                    !args.no_scan_matching,
                    Some(&store),
                    None,
                    &bridge,
                    &topics,
                    &stop,
                )
                .input()?;
                drop(store);
                std::fs::rename(&partial, &args.out)?;
                print_json(&usar_btm::report::describe(&btm))
            }
        }
    }
}

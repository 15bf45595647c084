//! `usar demo`: the main job on built-in defaults — six wheeled robots explore a generated
//! office floor with victims, and a report folder is written.

use super::explore::run_mission;
use super::print_json;
use crate::cli::DemoArgs;
use crate::failure::{CmdResult, InputContext};
use std::sync::Arc;
use std::time::Instant;
use usar_team::TeamConfig;
use usar_world::generate::{SceneKind, generate};

/// Robots in the demo: enough to know ≥ 95 % of the office floor within its time limit.
const DEMO_ROBOTS: usize = 6;

pub fn run(args: DemoArgs) -> CmdResult {
    let started = Instant::now();
    let scene = Arc::new(generate(SceneKind::Office, args.seed));
    if !args.json {
        eprintln!(
            "demo: {} wheeled robots explore {} ({:.0} × {:.0} m, {} victims), nearest-frontier strategy",
            DEMO_ROBOTS,
            scene.name,
            scene.geometry().extent_m().0,
            scene.geometry().extent_m().1,
            scene.victims.len()
        );
    }
    let config = TeamConfig {
        robots: DEMO_ROBOTS,
        ..TeamConfig::default()
    };
    let outcome = run_mission(scene.clone(), config, args.seed, args.json)?;
    let summary = usar_team::report::write_report(
        &args.out,
        &scene,
        &outcome,
        serde_json::json!({ "seed": args.seed, "wall_time_s": started.elapsed().as_secs_f64() }),
    )
    .input()?;
    if args.json {
        print_json(&summary)
    } else {
        println!(
            "coverage {:.1} %, victims seen {}/{}, {:.0} simulated s in {:.1} s; report in {}",
            outcome.coverage * 100.0,
            outcome.victims_seen,
            outcome.victims_total,
            outcome.time_s,
            started.elapsed().as_secs_f64(),
            args.out.display()
        );
        Ok(())
    }
}

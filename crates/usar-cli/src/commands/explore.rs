//! `usar explore`: a team of robots explores a scene, each going to its nearest frontier.

use super::print_json;
use crate::cli::ExploreArgs;
use crate::failure::{CmdResult, InputContext, bad_input};
use crate::record_file::RecordFile;
use crate::{progress, scene_source};
use std::path::Path;
use std::sync::Arc;
use usar_record::TeamRecorder;
use usar_team::{TeamConfig, TeamMission, TeamOutcome};
use usar_world::Scene;

/// Runs one mission with a progress bar (hidden when `quiet`), recorded into `record` when
/// given (written as `FILE.partial`, named when the run ends).
pub fn run_mission(
    scene: Arc<Scene>,
    config: TeamConfig,
    seed: u64,
    quiet: bool,
    record: Option<&Path>,
) -> CmdResult<TeamOutcome> {
    let total = config.duration_s;
    let mission = TeamMission::new(scene, config, seed).input()?;
    let bar = progress::bar(total.round() as u64, "exploring", quiet);
    let progress = |t: f64| bar.set_position(t.round() as u64);
    let outcome = match record {
        None => mission.run(progress),
        Some(path) => {
            let (file, recording) = RecordFile::create(path)?;
            let mut recorder = TeamRecorder::new(recording);
            let outcome = mission.run_observed(progress, |m| recorder.observe(m));
            file.done(recorder.finish())?;
            outcome
        }
    };
    bar.finish_and_clear();
    Ok(outcome)
}

pub fn run(args: ExploreArgs) -> CmdResult {
    if !(args.minutes.is_finite() && args.minutes > 0.0) {
        return Err(bad_input(anyhow::anyhow!(
            "--minutes: found {}, expected a positive number",
            args.minutes
        )));
    }
    if let Some(c) = args.stop_at_coverage
        && !(0.0..=1.0).contains(&c)
    {
        return Err(bad_input(anyhow::anyhow!(
            "--stop-at-coverage: found {c}, expected a fraction in [0, 1]"
        )));
    }
    if !(args.stall_minutes.is_finite() && args.stall_minutes >= 0.0) {
        return Err(bad_input(anyhow::anyhow!(
            "--stall-minutes: found {}, expected a number of minutes ≥ 0",
            args.stall_minutes
        )));
    }
    let scene = Arc::new(scene_source::load(&args.scene, args.seed, &args.image)?);
    let config = TeamConfig {
        robots: args.robots,
        robot: scene_source::load_robot(&args.robot)?,
        duration_s: args.minutes * 60.0,
        stop_at_coverage: args.stop_at_coverage,
        stall_after_s: (args.stall_minutes > 0.0).then_some(args.stall_minutes * 60.0),
        ..TeamConfig::default()
    };
    let outcome = run_mission(
        scene.clone(),
        config,
        args.seed,
        args.json,
        args.record.as_deref(),
    )?;
    if let Some(dir) = &args.out {
        usar_team::report::write_report(
            dir,
            &scene,
            &outcome,
            serde_json::json!({ "seed": args.seed }),
        )
        .input()?;
    }
    if args.json {
        print_json(&outcome)
    } else {
        println!(
            "{}: {} robots, {:.0} s, coverage {:.1} % ({:.0} of {:.0} m²), victims seen {}/{}, {:.0} m driven, {} collisions ({:?})",
            outcome.scene,
            outcome.robots,
            outcome.time_s,
            outcome.coverage * 100.0,
            outcome.explored_area_m2,
            outcome.reachable_area_m2,
            outcome.victims_seen,
            outcome.victims_total,
            outcome.distance_m,
            outcome.collisions,
            outcome.finish
        );
        Ok(())
    }
}

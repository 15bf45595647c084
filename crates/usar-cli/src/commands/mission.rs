//! `usar mission run`: the whole mission in one world (`usar_mission`).

use super::print_json;
use crate::cli::{MissionCommand, MissionRunArgs};
use crate::failure::{CmdResult, InputContext, bad_input};
use crate::record_file::RecordFile;
use crate::{progress, scene_source};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;
use usar_btm::store::BtmStore;
use usar_mission::{
    MissionConfig, MissionError, MissionOutcome, Operator, run_mission, run_mission_live,
};
use usar_record::MissionRecorder;
use usar_world::Scene;
use usar_world::partial_path;

pub fn run(cmd: MissionCommand) -> CmdResult {
    match cmd {
        MissionCommand::Run(args) => run_one(args),
    }
}

fn run_one(args: MissionRunArgs) -> CmdResult {
    let started = Instant::now();
    let mut config: MissionConfig = match &args.file {
        Some(path) => scene_source::read_toml(path)?,
        None => MissionConfig::default(),
    };
    if let Some(m) = args.minutes {
        config.minutes = m;
    }
    execute(&config, &args, started)
}

/// Runs `config` as `args` ask (seed, scene image, BTM file, report folder, JSON); the summary
/// carries the wall time since `started`.
pub(crate) fn execute(
    config: &MissionConfig,
    args: &MissionRunArgs,
    started: Instant,
) -> CmdResult {
    let scene = Arc::new(scene_source::load(
        &config.scene,
        config.scene_seed,
        &args.image,
    )?);
    // The crawler's map goes to DB.partial while it is built, renamed to DB at the end; a
    // refused or failed mission leaves no file.
    let partial = args.btm.as_deref().map(partial_path);
    let store = match &partial {
        Some(path) => {
            if path.exists() {
                std::fs::remove_file(path)?;
            }
            Some(BtmStore::create(path).input()?)
        }
        None => None,
    };
    let bar = progress::bar((config.minutes * 60.0).round() as u64, "mission", args.json);
    let progress = |t: f64| bar.set_position(t.round() as u64);
    let result = match &args.record {
        None => run_mission(scene, config, args.seed, store.as_ref(), progress),
        Some(path) => recorded(scene, config, args.seed, store.as_ref(), path, progress)?,
    };
    drop(store);
    let outcome = match result {
        Ok(o) => o,
        Err(e) => {
            if let Some(path) = &partial {
                let _ = std::fs::remove_file(path);
            }
            return Err(if e.is_input() { bad_input(e) } else { e.into() });
        }
    };
    if let (Some(partial), Some(out)) = (&partial, &args.btm) {
        std::fs::rename(partial, out)?;
    }
    bar.finish_and_clear();
    let wall = serde_json::json!({ "wall_time_s": started.elapsed().as_secs_f64() });
    let summary = match &args.out {
        Some(dir) => usar_mission::report::write_report(dir, &outcome, wall)?,
        None => {
            let mut s = serde_json::to_value(&outcome)?;
            s["wall_time_s"] = wall["wall_time_s"].clone();
            s
        }
    };
    if args.json {
        return print_json(&summary);
    }
    print_text(&outcome);
    if let Some(dir) = &args.out {
        println!("report: {}", dir.display());
    }
    Ok(())
}

/// The mission recorded into `path` (written as `path.partial`, renamed when complete; a
/// failed run or recording leaves no file).
fn recorded(
    scene: Arc<Scene>,
    config: &MissionConfig,
    seed: u64,
    store: Option<&BtmStore>,
    path: &Path,
    progress: impl FnMut(f64),
) -> CmdResult<Result<MissionOutcome, MissionError>> {
    let (file, recording) = RecordFile::create(path)?;
    let mut recorder = MissionRecorder::new(recording);
    let outcome = run_mission_live(
        scene,
        config,
        seed,
        store,
        Operator::Simulated,
        progress,
        &mut recorder,
    );
    if outcome.is_err() {
        file.abandon();
        return Ok(outcome);
    }
    file.done(recorder.finish())?;
    Ok(outcome)
}

fn print_text(o: &MissionOutcome) {
    let t = &o.team;
    println!(
        "mission on {} (seed {}), {:.0} s simulated",
        o.scene, o.seed, o.time_s
    );
    println!(
        "team ({} robots): relevant area {:.0} of {:.0} m², coverage {:.1} %, victims seen {}/{}, {:.0} m driven, {} collisions, largest pose error {:.2} m",
        t.robots,
        t.relevant_area_m2,
        t.relevant_total_m2,
        t.coverage * 100.0,
        t.victims_seen,
        t.victims_total,
        t.distance_m,
        t.collisions,
        t.max_pose_error_m
    );
    println!(
        "base station: {} BTMs received, {} keep-out zones for the wheeled robots",
        t.btm_maps_received, t.keep_out_zones
    );
    if let Some(c) = &o.crawler {
        println!(
            "crawler: BTM of {} nodes and {} links ({} un-searched), {:.0} m driven, {} collisions, largest position error {:.2} m, {} maps sent, {}",
            c.nodes,
            c.links,
            c.unsearched_links,
            c.distance_m,
            c.collisions,
            c.max_position_error_m,
            c.maps_sent,
            match c.stop {
                Some(s) => format!("stopped: {s:?}"),
                None => "still exploring at the end".into(),
            }
        );
    }
    if let Some(r) = &o.rescuer {
        println!(
            "rescuer (MAXQ, policy of {} trials): {} of {} zone cells visited, {} primitives, {} possible victims ({} undecided), {} tagged ({} real), hand-offs {} victim / {} stuck, {:.0} s waiting, {} collisions{}",
            r.policy_trials,
            r.cells_visited,
            r.zone_cells,
            r.primitives,
            r.possible_victims,
            r.pending,
            r.tags,
            r.true_tags,
            r.handoffs_victim,
            r.handoffs_stuck,
            r.waiting_s,
            r.collisions,
            if r.finished { ", search ended" } else { "" }
        );
    }
    let (op, v) = (&o.operator, &o.victim_figures);
    println!(
        "operator: {} hand-offs asked, {} answered, wait {:.1} s mean / {:.1} s longest, busy {:.0} %",
        op.asked,
        op.answered,
        op.mean_wait_s,
        op.max_wait_s,
        op.busy_fraction * 100.0
    );
    println!(
        "victims: {} detected, {} confirmed, {} missed of {}; {} false confirmations",
        v.detected, v.confirmed, v.missed, v.total, v.false_confirmations
    );
    println!(
        "robot-robot contacts {}, radio: {} sent, {} delivered, {} lost",
        o.robot_contacts, o.radio.sent, o.radio.delivered, o.radio.lost
    );
}

//! `usar team run`: one run of paper 002's semantically-informed exploration.

use super::print_json;
use crate::cli::{TeamCommand, TeamRunArgs};
use crate::failure::{CmdResult, bad_input};
use crate::scene_source;
use std::sync::Arc;
use usar_map::segmentation::SegmentationParams;
use usar_team::Radio;
use usar_team::paper_run::RunSummary;
use usar_team::scene_prep::prepare_scene;
use usar_team::setup::{TeamSetup, parse_failure};

pub fn run(cmd: TeamCommand) -> CmdResult {
    match cmd {
        TeamCommand::Run(args) => run_one(args),
    }
}

fn run_one(args: TeamRunArgs) -> CmdResult {
    let failures = args
        .failures
        .iter()
        .map(|f| parse_failure(f))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| bad_input(anyhow::anyhow!(e)))?;
    let setup = TeamSetup {
        robots: args.robots,
        robot: &args.robot,
        strategy: &args.strategy,
        coordination: &args.coordination,
        hypothesis: &args.hypothesis,
        minutes: args.minutes,
        label_errors: &args.label_errors,
        candidates: &args.candidates,
        semantics: &args.semantics,
        localization: &args.localization,
        stop_at_relevant: args.stop_at_relevant,
        merge_period_s: args.merge_period,
        radio: Radio {
            range_m: args.radio_range,
            drop_probability: args.radio_drop,
        },
        failures,
    };
    let config = setup
        .config()
        .map_err(|e| bad_input(anyhow::anyhow!("--{e}")))?;
    let mut scene = scene_source::load(&args.scene, args.scene_seed, &args.image)?;
    let prepared = prepare_scene(
        &mut scene,
        config.robots,
        config.robot.circumscribed_radius_m() + 0.1,
        &SegmentationParams::default(),
    );
    if prepared.segmented_rooms > 0 && !args.json {
        eprintln!(
            "{}: no room layer; the room segmentation made {} rooms and corridors",
            args.scene, prepared.segmented_rooms
        );
    }
    if scene.rooms.is_empty() {
        return Err(bad_input(anyhow::anyhow!(
            "{}: no room layer, and the room segmentation found no free space to split",
            args.scene
        )));
    }
    let scene = Arc::new(scene);
    let outcome = super::explore::run_mission(
        scene.clone(),
        config,
        args.seed,
        args.json,
        args.record.as_deref(),
    )?;
    if let Some(png) = &args.png {
        usar_team::report::render_explored_map(&scene, &outcome)
            .save_png(png)
            .map_err(|e| bad_input(anyhow::anyhow!("--png {}: {e}", png.display())))?;
    }
    if let Some(path) = &args.trace {
        usar_world::write_atomic(path, &allocations_csv(&outcome.allocations))
            .map_err(|e| bad_input(anyhow::anyhow!("--trace {}: {e}", path.display())))?;
    }
    let summary = RunSummary::new(
        &outcome,
        &args.strategy,
        &args.coordination,
        &args.hypothesis,
        args.seed,
    );
    if args.json {
        return print_json(&summary);
    }
    println!(
        "{}: {} robots, {} + {}, victims in {} rooms, {:.0} s: relevant area {:.0} of {:.0} m², total area {:.0} m², {:.0} m travelled{} ({:?})",
        summary.scene,
        summary.robots,
        summary.strategy,
        summary.coordination,
        summary.hypothesis,
        summary.time_s,
        summary.relevant_area_m2,
        summary.relevant_total_m2,
        summary.total_area_m2,
        summary.distance_m,
        summary
            .time_to_relevant_s
            .map(|t| format!(
                ", {:.0} % of the relevant area at {:.1} min",
                summary.relevant_target * 100.0,
                t / 60.0
            ))
            .unwrap_or_default(),
        summary.finish,
    );
    Ok(())
}

/// The auctions' allocations as CSV, one row each (no field needs quoting).
fn allocations_csv(allocations: &[usar_team::Allocation]) -> Vec<u8> {
    let mut out = String::from(
        "time_s,robot,x_m,y_m,label,relevance,frontier_cells,path_m,utility,ideal_robots,room_known\n",
    );
    for a in allocations {
        out.push_str(&format!(
            "{:.1},{},{:.2},{:.2},{},{:.2},{},{:.2},{:.4},{},{}\n",
            a.time_s,
            a.robot,
            a.x_m,
            a.y_m,
            a.label.map_or("none", |l| l.as_str()),
            a.relevance,
            a.frontier_cells,
            a.path_m,
            a.utility,
            a.ideal_robots,
            a.room_known.map_or(String::new(), |f| format!("{f:.3}")),
        ));
    }
    out.into_bytes()
}

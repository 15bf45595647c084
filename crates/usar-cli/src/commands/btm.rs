//! `usar btm`: show, export, plan on and merge Behavioral Trace Maps.

use super::print_json;
use crate::cli::{BtmBuildArgs, BtmCommand, BtmExportArgs, BtmMergeArgs, BtmPlanArgs, BtmShowArgs};
use crate::failure::{CmdResult, Failure, InputContext, bad_input};
use crate::record_file::RecordFile;
use crate::{progress, scene_source};
use serde_json::json;
use std::path::Path;
use std::sync::Arc;
use usar_btm::build::BuildConfig;
use usar_btm::plan::{NodeRefError, RobotLimits, find_node, plan};
use usar_btm::report::{self, ReportError, Sizes};
use usar_btm::{Btm, exchange};
use usar_world::{Point2, Pose2};

pub fn run(cmd: BtmCommand) -> CmdResult {
    match cmd {
        BtmCommand::Build(args) => build(args),
        BtmCommand::Show(args) => show(args),
        BtmCommand::Export(args) => export(args),
        BtmCommand::Plan(args) => route(args),
        BtmCommand::Merge(args) => merge(args),
    }
}

fn read(path: &Path) -> CmdResult<Btm> {
    exchange::read(path).input()
}

/// Report errors keep their kind: bad input exits 2, anything else 1.
pub(super) fn fail(e: ReportError) -> Failure {
    if e.is_input() {
        bad_input(e)
    } else {
        Failure::from(e)
    }
}

pub(super) fn build_config(args: &BtmBuildArgs) -> CmdResult<BuildConfig> {
    let mut config = match &args.config {
        Some(path) => scene_source::read_toml::<BuildConfig>(path)?,
        None => BuildConfig::default(),
    };
    if let Some(minutes) = args.max_minutes {
        if !(minutes.is_finite() && minutes > 0.0) {
            return Err(bad_input(anyhow::anyhow!(
                "--max-minutes: found {minutes}, expected a positive number"
            )));
        }
        config.max_time_s = minutes * 60.0;
    }
    Ok(config)
}

fn build(args: BtmBuildArgs) -> CmdResult {
    if let Some(log) = &args.from_log {
        return super::logs::btm_from_log(log, &args);
    }
    let mut scene = scene_source::load(&args.scene, args.scene_seed, &args.image)?;
    if let Some((x, y, theta)) = args.start {
        scene.start_poses.insert(0, Pose2::new(x, y, theta));
    }
    let robot = scene_source::load_robot(&args.robot)?;
    let config = build_config(&args)?;
    let scene = Arc::new(scene);
    let bar = progress::bar(config.max_time_s.ceil() as u64, "simulated s", args.json);
    let mut recording = match &args.record {
        Some(path) => {
            let (file, recording) = RecordFile::create(path)?;
            Some((file, usar_record::BtmRecorder::new(recording)))
        }
        None => None,
    };
    let built = report::build_to_file(
        scene.clone(),
        robot.clone(),
        &config,
        args.seed,
        &args.out,
        &mut |p| {
            bar.set_position(p.time_s as u64);
            if let Some((_, recorder)) = &mut recording {
                recorder.observe(p);
            }
        },
    );
    bar.finish_and_clear();
    if let Some((file, recorder)) = recording {
        match &built {
            Ok(_) => {
                file.done(recorder.finish())?;
            }
            Err(_) => file.abandon(),
        }
    }
    let outcome = built.map_err(fail)?;
    if let Some(png) = &args.png {
        let trace: Vec<Point2> = outcome
            .trajectory
            .iter()
            .map(|s| s.truth.position())
            .collect();
        report::save_drawing(&outcome.btm, Some(&scene), &trace, png).map_err(fail)?;
    }
    if let Some(path) = &args.trace {
        usar_world::write_atomic(path, report::trajectory_csv(&outcome.trajectory).as_bytes())?;
    }
    let sizes = Sizes::measure(&outcome.btm, &args.out, scene.geometry().len()).map_err(fail)?;
    if args.json {
        let mut v = report::describe_build(&outcome, &sizes);
        v["scene"] = json!(scene.name);
        v["robot"] = json!(robot.name);
        v["seed"] = json!(args.seed);
        v["out"] = json!(args.out);
        return print_json(&v);
    }
    println!(
        "{} on {}: {} nodes {:?}, {} links searched, {} un-searched; {:?} after {:.0} s, {:.0} m driven, {} collisions → {}; {} bytes as .btmb, {} as JSON, {} as SQLite; the occupancy grid {} bytes (×{:.0} the .btmb)",
        robot.name,
        scene.name,
        outcome.btm.nodes.len(),
        outcome.nodes_by_type,
        outcome.searched_links,
        outcome.unsearched_links,
        outcome.stop,
        outcome.time_s,
        outcome.distance_m,
        outcome.collisions,
        args.out.display(),
        sizes.btm_binary,
        sizes.btm_json,
        sizes.btm_sqlite,
        sizes.occupancy_grid,
        sizes.grid_over_binary,
    );
    Ok(())
}

fn show(args: BtmShowArgs) -> CmdResult {
    let btm = read(&args.btm)?;
    let svg = args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    let scene = match &args.scene {
        Some(spec) if !svg => Some(scene_source::load(spec, args.seed, &args.image)?),
        _ => None,
    };
    report::save_drawing(&btm, scene.as_ref(), &[], &args.out).map_err(fail)?;
    if args.json {
        print_json(&json!({ "out": args.out, "nodes": btm.nodes.len(), "links": btm.links.len() }))
    } else {
        println!(
            "{} nodes, {} links → {}",
            btm.nodes.len(),
            btm.links.len(),
            args.out.display()
        );
        Ok(())
    }
}

fn export(args: BtmExportArgs) -> CmdResult {
    let btm = read(&args.btm)?;
    if let Some(out) = &args.out {
        exchange::write(&btm, out).input()?;
    }
    if args.json {
        return print_json(&report::describe(&btm));
    }
    // Kinds this version does not know are kept as read; say which there are.
    let unknown = report::unknown_kinds(&btm);
    let unknown = if unknown.is_empty() {
        String::new()
    } else {
        let list: Vec<String> = unknown.iter().map(|(k, n)| format!("{k} ×{n}")).collect();
        format!(
            " (nodes of kinds this usar does not know, kept as read: {})",
            list.join(", ")
        )
    };
    println!(
        "{}: {} nodes, {} links{unknown}{}",
        args.btm.display(),
        btm.nodes.len(),
        btm.links.len(),
        args.out
            .as_ref()
            .map(|o| format!(" → {}", o.display()))
            .unwrap_or_default()
    );
    Ok(())
}

/// A node given as an id or as "x,y" (the nearest node).
fn node_arg(btm: &Btm, name: &str, s: &str) -> CmdResult<u32> {
    find_node(btm, s).map_err(|e| {
        bad_input(match e {
            NodeRefError::Malformed(_) => anyhow::anyhow!("{name} {e}"),
            NodeRefError::EmptyMap => anyhow::anyhow!("{name}: {e}"),
        })
    })
}

fn route(args: BtmPlanArgs) -> CmdResult {
    let btm = read(&args.btm)?;
    let robot = scene_source::load_robot(&args.robot)?;
    let from = node_arg(&btm, "--from", &args.from)?;
    let to = node_arg(&btm, "--to", &args.to)?;
    match plan(&btm, &RobotLimits::of(&robot), from, to) {
        Ok(r) => {
            if args.json {
                print_json(&json!({ "found": true, "robot": robot.name, "route": r }))
            } else {
                println!(
                    "route for {} from node {from} to node {to}: {:.2} m through nodes {:?}",
                    robot.name, r.length_m, r.nodes
                );
                Ok(())
            }
        }
        Err(why) => {
            if args.json {
                print_json(
                    &json!({ "found": false, "robot": robot.name, "reason": why.to_string() }),
                )?;
            }
            let code = if matches!(why, usar_btm::plan::NoRoute::UnknownNode(_)) {
                2
            } else {
                3
            };
            Err(Failure {
                error: anyhow::anyhow!("no route for robot {}: {why}", robot.name),
                code,
            })
        }
    }
}

fn merge(args: BtmMergeArgs) -> CmdResult {
    if !(args.radius.is_finite() && args.radius > 0.0) {
        return Err(bad_input(anyhow::anyhow!(
            "--radius: found {}, expected a positive number of metres",
            args.radius
        )));
    }
    let maps: Vec<Btm> = args
        .inputs
        .iter()
        .map(|p| read(p))
        .collect::<CmdResult<_>>()?;
    let merged = usar_btm::merge::merge(&maps, args.radius);
    exchange::write(&merged, &args.out).input()?;
    if args.json {
        print_json(
            &json!({ "inputs": maps.len(), "out": args.out, "nodes": merged.nodes.len(), "links": merged.links.len() }),
        )
    } else {
        println!(
            "{} maps → {} nodes, {} links in {}",
            maps.len(),
            merged.nodes.len(),
            merged.links.len(),
            args.out.display()
        );
        Ok(())
    }
}

//! `usar btm`: show, export, plan on and merge Behavioral Trace Maps.

use super::print_json;
use crate::cli::{BtmBuildArgs, BtmCommand, BtmExportArgs, BtmMergeArgs, BtmPlanArgs, BtmShowArgs};
use crate::failure::{CmdResult, Failure, InputContext, bad_input};
use crate::{progress, scene_source};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use usar_btm::build::{BuildConfig, build_btm_observed};
use usar_btm::model::kind;
use usar_btm::plan::{RobotLimits, nearest_node, plan};
use usar_btm::{Btm, BtmStore, exchange, render};
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

fn build_config(args: &BtmBuildArgs) -> CmdResult<BuildConfig> {
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

/// The file a build writes while the robot drives.
fn partial_path(out: &Path) -> PathBuf {
    let mut name = out.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

fn file_len(path: &Path) -> CmdResult<u64> {
    Ok(std::fs::metadata(path)?.len())
}

fn build(args: BtmBuildArgs) -> CmdResult {
    let mut scene = scene_source::load(&args.scene, args.scene_seed, &args.image)?;
    if let Some((x, y, theta)) = args.start {
        scene.start_poses.insert(0, Pose2::new(x, y, theta));
    }
    let robot = scene_source::load_robot(&args.robot)?;
    let config = build_config(&args)?;
    let partial = partial_path(&args.out);
    if partial.exists() {
        std::fs::remove_file(&partial)?;
    }
    let store = BtmStore::create(&partial).input()?;
    let scene = Arc::new(scene);
    let bar = progress::bar(config.max_time_s.ceil() as u64, "simulated s", args.json);
    let built = build_btm_observed(
        scene.clone(),
        robot.clone(),
        &config,
        args.seed,
        Some(&store),
        &mut |t, _, _| bar.set_position(t as u64),
    );
    bar.finish_and_clear();
    drop(store);
    let outcome = match built {
        Ok(o) => o,
        Err(e) => {
            let _ = std::fs::remove_file(&partial);
            return Err(bad_input(e));
        }
    };
    std::fs::rename(&partial, &args.out)?;
    if let Some(png) = &args.png {
        if png
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
        {
            usar_world::write_atomic(png, render::to_svg(&outcome.btm).as_bytes())?;
        } else {
            let trace: Vec<Point2> = outcome
                .trajectory
                .iter()
                .map(|s| s.truth.position())
                .collect();
            render::draw_traced(&outcome.btm, Some(&scene), &trace)
                .save_png(png)
                .input()?;
        }
    }
    if let Some(path) = &args.trace {
        let mut csv = String::from(
            "time_s,est_x_m,est_y_m,est_theta_rad,true_x_m,true_y_m,true_theta_rad,mode,contact\n",
        );
        for t in &outcome.trajectory {
            csv += &format!(
                "{:.2},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{},{}\n",
                t.time_s,
                t.estimated.x,
                t.estimated.y,
                t.estimated.theta,
                t.truth.x,
                t.truth.y,
                t.truth.theta,
                t.mode.as_str(),
                u8::from(t.contact)
            );
        }
        usar_world::write_atomic(path, csv.as_bytes())?;
    }
    // The occupancy grid of the same floor: one byte per cell (a ROS map_server PGM's raster).
    let grid_bytes = scene.geometry().len() as u64;
    let sqlite_bytes = file_len(&args.out)?;
    let json_bytes = serde_json::to_string(&exchange::to_json_value(&outcome.btm))?.len() as u64;
    let binary_bytes = usar_btm::wire::encode(&outcome.btm).len() as u64;
    let sizes = json!({
        "btm_binary": binary_bytes,
        "btm_json": json_bytes,
        "btm_sqlite": sqlite_bytes,
        "occupancy_grid": grid_bytes,
        "grid_over_binary": grid_bytes as f64 / binary_bytes as f64,
        "grid_over_json": grid_bytes as f64 / json_bytes as f64,
        "grid_over_sqlite": grid_bytes as f64 / sqlite_bytes as f64,
    });
    if args.json {
        let mut v = describe(&outcome.btm);
        let extra = json!({
            "scene": scene.name,
            "robot": robot.name,
            "seed": args.seed,
            "out": args.out,
            "stop": outcome.stop,
            "time_s": outcome.time_s,
            "distance_m": outcome.distance_m,
            "collisions": outcome.collisions,
            "max_position_error_m": outcome.max_position_error_m,
            "bytes": sizes,
        });
        for (k, val) in extra.as_object().expect("object") {
            v[k] = val.clone();
        }
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
        binary_bytes,
        json_bytes,
        sqlite_bytes,
        grid_bytes,
        grid_bytes as f64 / binary_bytes as f64,
    );
    Ok(())
}

fn show(args: BtmShowArgs) -> CmdResult {
    let btm = read(&args.btm)?;
    let svg = args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    if svg {
        usar_world::write_atomic(&args.out, render::to_svg(&btm).as_bytes())?;
    } else {
        let scene = match &args.scene {
            Some(spec) => Some(scene_source::load(spec, args.seed, &args.image)?),
            None => None,
        };
        render::draw(&btm, scene.as_ref())
            .save_png(&args.out)
            .input()?;
    }
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

/// Every node with its Table I fields (links, angles) and every link.
fn describe(btm: &Btm) -> serde_json::Value {
    let by_kind = usar_btm::build::count_nodes(btm);
    let searched = btm.links.iter().filter(|l| l.searched).count();
    json!({
        "nodes_by_kind": by_kind,
        "links_searched": searched,
        "links_unsearched": btm.links.len() - searched,
        "nodes": exchange::node_rows(btm),
        "links": btm.links,
    })
}

fn export(args: BtmExportArgs) -> CmdResult {
    let btm = read(&args.btm)?;
    if let Some(out) = &args.out {
        exchange::write(&btm, out).input()?;
    }
    if args.json {
        return print_json(&describe(&btm));
    }
    // Kinds this version does not know are kept as read; say which there are.
    let mut unknown: std::collections::BTreeMap<&str, usize> = Default::default();
    for n in btm.nodes.iter().filter(|n| !kind::is_known(&n.kind)) {
        *unknown.entry(n.kind.as_str()).or_default() += 1;
    }
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
    if let Ok(id) = s.trim().parse::<u32>() {
        return Ok(id);
    }
    let xy = s
        .split_once(',')
        .and_then(|(x, y)| Some((x.trim().parse::<f64>().ok()?, y.trim().parse::<f64>().ok()?)));
    let Some((x, y)) = xy else {
        return Err(bad_input(anyhow::anyhow!(
            "{name} {s:?}: expected a node id or \"x,y\" in metres"
        )));
    };
    nearest_node(btm, x, y)
        .map(|n| n.id)
        .ok_or_else(|| bad_input(anyhow::anyhow!("{name}: the map has no nodes")))
}

fn route(args: BtmPlanArgs) -> CmdResult {
    let btm = read(&args.btm)?;
    let robot = scene_source::load_robot(&args.robot)?;
    let limits = RobotLimits {
        width_m: robot.width_m,
        max_inclination_rad: robot.max_inclination_rad,
        max_step_m: robot.max_step_m,
    };
    let from = node_arg(&btm, "--from", &args.from)?;
    let to = node_arg(&btm, "--to", &args.to)?;
    match plan(&btm, &limits, from, to) {
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

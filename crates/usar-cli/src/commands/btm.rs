//! `usar btm`: show, export, plan on and merge Behavioral Trace Maps.

use super::print_json;
use crate::cli::{BtmCommand, BtmExportArgs, BtmMergeArgs, BtmPlanArgs, BtmShowArgs};
use crate::failure::{CmdResult, Failure, InputContext, bad_input};
use crate::scene_source;
use serde_json::json;
use std::path::Path;
use usar_btm::plan::{RobotLimits, nearest_node, plan};
use usar_btm::{Btm, exchange, render};

pub fn run(cmd: BtmCommand) -> CmdResult {
    match cmd {
        BtmCommand::Show(args) => show(args),
        BtmCommand::Export(args) => export(args),
        BtmCommand::Plan(args) => route(args),
        BtmCommand::Merge(args) => merge(args),
    }
}

fn read(path: &Path) -> CmdResult<Btm> {
    exchange::read(path).map_err(|e| bad_input(anyhow::anyhow!(e)))
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
    let mut by_kind = std::collections::BTreeMap::<String, usize>::new();
    for n in &btm.nodes {
        let key = match &n.subtype {
            Some(s) => format!("{}/{s}", n.kind),
            None => n.kind.clone(),
        };
        *by_kind.entry(key).or_default() += 1;
    }
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
        exchange::write(&btm, out).map_err(|e| bad_input(anyhow::anyhow!(e)))?;
    }
    if args.json {
        return print_json(&describe(&btm));
    }
    println!(
        "{}: {} nodes, {} links{}",
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
    exchange::write(&merged, &args.out).map_err(|e| bad_input(anyhow::anyhow!(e)))?;
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

//! `usar plan`: check MovingAI scenarios, or plan on a scene for a robot.

use super::print_json;
use crate::cli::{ConnectivityArg, PlanArgs};
use crate::failure::{CmdResult, Failure, InputContext, bad_input};
use crate::scene_source;
use serde_json::json;
use usar_map::planning::{Connectivity, GridAStar, NavGrid, NoPath, check_scenarios, inflate};
use usar_world::Point2;
use usar_world::render::{RenderOptions, render_scene};

pub fn run(args: PlanArgs) -> CmdResult {
    if let Some(scen) = &args.scen {
        let report = check_scenarios(scen).input()?;
        if args.json {
            print_json(&report)?;
        } else {
            println!(
                "{}: {} of {} scenarios match the published optimal length (max |error| {:.2e})",
                scen.display(),
                report.matched,
                report.scenarios,
                report.max_abs_error
            );
            for m in &report.mismatches {
                println!(
                    "  scenario {}: {:?} → {:?} expected {} found {:?}",
                    m.index, m.start, m.goal, m.expected, m.found
                );
            }
        }
        if report.matched < report.scenarios {
            return Err(Failure {
                error: anyhow::anyhow!(
                    "{} scenarios do not match their optimal length",
                    report.scenarios - report.matched
                ),
                code: 1,
            });
        }
        return Ok(());
    }
    let (Some(spec), Some(from), Some(to)) = (&args.scene, args.from, args.to) else {
        return Err(bad_input(anyhow::anyhow!(
            "give --scen FILE, or --scene SCENE --from x,y --to x,y"
        )));
    };
    let scene = scene_source::load(spec, args.seed, &args.image)?;
    let robot = scene_source::load_robot(&args.robot)?;
    let g = *scene.geometry();
    let (start, goal) = (
        g.world_to_cell(Point2::new(from.0, from.1)),
        g.world_to_cell(Point2::new(to.0, to.1)),
    );
    for (name, cell, p) in [("--from", start, from), ("--to", goal, to)] {
        if !g.contains(cell) {
            return Err(bad_input(anyhow::anyhow!(
                "{name} {},{} lies outside the scene ({} × {} m from ({}, {}))",
                p.0,
                p.1,
                g.extent_m().0,
                g.extent_m().1,
                g.origin.x,
                g.origin.y
            )));
        }
    }
    let blocked = inflate(
        &usar_sim::compute_blocked(&scene, &robot),
        robot.circumscribed_radius_m(),
    );
    let grid = NavGrid::from_blocked(&blocked);
    let connectivity = match args.connectivity {
        ConnectivityArg::Four => Connectivity::Four,
        ConnectivityArg::Eight => Connectivity::Eight,
    };
    let mut astar = GridAStar::new();
    let path = astar.plan(&grid, start, goal, connectivity);
    let Some(path) = path else {
        let why = NoPath::explain(&grid, start, goal);
        if args.json {
            print_json(&json!({ "found": false, "reason": why.to_string(), "robot": robot.name }))?;
        }
        return Err(Failure {
            error: anyhow::anyhow!("no route for robot {}: {why}", robot.name),
            code: 3,
        });
    };
    let waypoints: Vec<Point2> = path.cells.iter().map(|&c| g.cell_center(c)).collect();
    if let Some(png) = &args.png {
        let mut canvas = render_scene(&scene, &RenderOptions::default());
        canvas.draw_polyline(&waypoints, [0, 90, 255]);
        canvas.save_png(png).input()?;
    }
    if args.json {
        print_json(&json!({
            "found": true,
            "robot": robot.name,
            "length_m": path.length_m(g.resolution_m),
            "cells": path.cells.len(),
            "expanded": astar.expanded(),
            "waypoints": waypoints,
        }))
    } else {
        println!(
            "path of {:.2} m through {} cells ({} expanded)",
            path.length_m(g.resolution_m),
            path.cells.len(),
            astar.expanded()
        );
        Ok(())
    }
}

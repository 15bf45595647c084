//! `usar log import` and `usar map build --from-log`: real robot logs through
//! [`usar_log`].

use super::print_json;
use crate::cli::{BtmBuildArgs, LogCommand, MapBuildArgs, MapCommand};
use crate::failure::{CmdResult, InputContext, bad_input};
use crate::progress;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;
use usar_log::mapping::{Drift, LogMap, MapParams, Matcher, build_map};
use usar_log::{LogFormat, RobotLog, read_log};
use usar_map::segmentation::{SegmentationParams, segment_free_space};
use usar_world::{Grid, Scene, obstacle, partial_path, write_atomic};

pub fn import(cmd: LogCommand) -> CmdResult {
    let LogCommand::Import(args) = cmd;
    let log = read(&args.log, args.format.as_deref())?;
    let summary = log.summary();
    let mut messages = None;
    if let Some(out) = &args.out {
        messages = Some(write_mcap(&log, out)?);
    }
    if args.json {
        #[derive(Serialize)]
        struct Out<'a> {
            #[serde(flatten)]
            summary: &'a usar_log::LogSummary,
            mcap: Option<&'a Path>,
            messages: Option<u64>,
        }
        return print_json(&Out {
            summary: &summary,
            mcap: args.out.as_deref(),
            messages,
        });
    }
    print_summary(&summary);
    if let (Some(out), Some(n)) = (&args.out, messages) {
        println!("wrote {} ({n} messages)", out.display());
    }
    Ok(())
}

/// Reads a log, its format named or told by its content; a bad log is bad input.
fn read(path: &Path, format: Option<&str>) -> CmdResult<RobotLog> {
    let format = match format {
        None => None,
        Some(name) => Some(LogFormat::from_name(name).ok_or_else(|| {
            bad_input(anyhow::anyhow!(
                "--format {name}: expected {}",
                LogFormat::NAMES.join(", ")
            ))
        })?),
    };
    read_log(path, format).input()
}

fn write_mcap(log: &RobotLog, out: &Path) -> CmdResult<u64> {
    let partial = partial_path(out);
    let file = std::io::BufWriter::new(std::fs::File::create(&partial).input()?);
    let n = usar_log::export::write_mcap(log, file)?;
    std::fs::rename(&partial, out)?;
    Ok(n)
}

fn print_summary(s: &usar_log::LogSummary) {
    println!("{}: {} log", s.path.display(), s.format.name());
    println!(
        "  {} scans of {}{} beams over {:.1}° from {:.1}°; {} odometry readings",
        s.scans,
        s.beams_min,
        if s.beams_max != s.beams_min {
            format!("-{}", s.beams_max)
        } else {
            String::new()
        },
        s.field_of_view_deg,
        s.first_beam_deg,
        s.odometry_readings
    );
    match s.no_return_m {
        Some(m) => println!(
            "  no return: readings >= {m:.3} m ({:?}), {:.1} % of the readings; longest return {:.2} m",
            s.no_return_source,
            100.0 * s.no_return_share,
            s.longest_return_m
        ),
        None => println!(
            "  no return value stated or found: every reading is a return (longest {:.2} m)",
            s.longest_return_m
        ),
    }
    println!(
        "  time {:.1} s to {:.1} s ({:?}), {} steps back; odometry path {:.1} m",
        s.t_first_s, s.t_last_s, s.timestamps, s.backward_steps, s.odometry_path_m
    );
}

/// What `usar map build` writes into summary.json.
#[derive(Serialize)]
struct MapSummary {
    log: usar_log::LogSummary,
    matcher: &'static str,
    resolution_m: f64,
    usable_range_m: f64,
    until_s: Option<f64>,
    scans_drawn: usize,
    scans_matched: u64,
    scans_rejected: u64,
    drift: Drift,
    width_cells: u32,
    height_cells: u32,
    known_area_m2: f64,
    free_area_m2: f64,
    rooms: usize,
    corridors: usize,
    doors: usize,
    frontiers: usize,
    candidates: Vec<[f64; 2]>,
    seconds: f64,
}

pub fn map(cmd: MapCommand) -> CmdResult {
    let MapCommand::Build(args) = cmd;
    let started = Instant::now();
    let params = map_params(&args)?;
    let log = read(&args.from_log, args.format.as_deref())?;
    let bar = progress::bar(3, "mapping", args.json);
    let map = build_map(&log, &params).input()?;
    bar.inc(1);
    let g = *map.grid.geometry();
    let free = Grid::from_vec(
        g,
        (0..g.len())
            .map(|i| map.grid.class_at_index(i) == usar_map::CellClass::Free)
            .collect(),
    )
    .expect("one value per cell");
    let rooms = segment_free_space(&free, &SegmentationParams::default());
    let frontiers = map.frontiers(args.min_frontier);
    bar.inc(1);

    std::fs::create_dir_all(&args.out).input()?;
    let summary_path = args.out.join("summary.json");
    // A folder with an older summary is not left looking complete while it is rewritten.
    let _ = std::fs::remove_file(&summary_path);
    usar_log::output::write_ros_map(&map, &args.out.join("map.yaml"))?;
    let png = |canvas: usar_world::render::Canvas, name: &str| -> CmdResult {
        write_atomic(&args.out.join(name), &canvas.encode_png()?)?;
        Ok(())
    };
    png(usar_log::output::picture(&map, &frontiers, 1600), "map.png")?;
    png(rooms.draw(&walls_scene(&map)), "rooms.png")?;
    let mut csv = String::from(
        "t_s,odometry_x,odometry_y,odometry_theta,estimate_x,estimate_y,estimate_theta,logged_x,logged_y,logged_theta\n",
    );
    for t in &map.trajectory {
        let logged = t
            .logged
            .map_or(",,".into(), |p| format!("{},{},{}", p.x, p.y, p.theta));
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{logged}\n",
            t.t_s,
            t.odometry.x,
            t.odometry.y,
            t.odometry.theta,
            t.estimate.x,
            t.estimate.y,
            t.estimate.theta
        ));
    }
    write_atomic(&args.out.join("trajectory.csv"), csv.as_bytes())?;
    bar.finish_and_clear();

    let corridors = rooms
        .segments
        .iter()
        .filter(|s| s.label == usar_world::RoomLabel::Corridor)
        .count();
    let summary = MapSummary {
        log: log.summary(),
        matcher: params.matcher.name(),
        resolution_m: params.resolution_m,
        usable_range_m: params.usable_range_m,
        until_s: params.until_s,
        scans_drawn: map.scans,
        scans_matched: map.matched,
        scans_rejected: map.rejected,
        drift: map.drift,
        width_cells: g.width,
        height_cells: g.height,
        known_area_m2: map.grid.known_area_m2(),
        free_area_m2: free.as_slice().iter().filter(|&&f| f).count() as f64 * g.cell_area_m2(),
        rooms: rooms.segments.len() - corridors,
        corridors,
        doors: rooms.doors.len(),
        frontiers: frontiers.len(),
        candidates: frontiers
            .iter()
            .map(|f| {
                let p = g.cell_center(f.candidate);
                [p.x, p.y]
            })
            .collect(),
        seconds: started.elapsed().as_secs_f64(),
    };
    write_atomic(
        &summary_path,
        serde_json::to_string_pretty(&summary)?.as_bytes(),
    )?;
    if args.json {
        return print_json(&summary);
    }
    print_map_summary(&summary, &args.out);
    Ok(())
}

/// The matcher called `name`.
fn matcher(name: &str) -> CmdResult<Matcher> {
    Matcher::from_name(name).ok_or_else(|| {
        bad_input(anyhow::anyhow!(
            "--matcher {name}: expected {}",
            Matcher::NAMES.join(", ")
        ))
    })
}

fn map_params(args: &MapBuildArgs) -> CmdResult<MapParams> {
    let matcher = matcher(&args.matcher)?;
    let params = MapParams {
        resolution_m: args.resolution,
        usable_range_m: args.usable_range,
        matcher,
        no_return_m: args.no_return,
        until_s: args.until,
    };
    params
        .check()
        .map_err(|e| bad_input(anyhow::anyhow!("{e}")))?;
    if !(args.min_frontier.is_finite() && args.min_frontier >= 0.0) {
        return Err(bad_input(anyhow::anyhow!(
            "--min-frontier {}: expected a length in metres, 0 or more",
            args.min_frontier
        )));
    }
    Ok(params)
}

fn print_map_summary(s: &MapSummary, out: &Path) {
    print_summary(&s.log);
    println!(
        "map: {} x {} cells of {} m, {:.0} m² known ({:.0} m² free); {} rooms, {} corridors, {} doors",
        s.width_cells,
        s.height_cells,
        s.resolution_m,
        s.known_area_m2,
        s.free_area_m2,
        s.rooms,
        s.corridors,
        s.doors
    );
    println!(
        "matcher {}: {} of {} scans matched, {} rejected (odometry kept)",
        s.matcher, s.scans_matched, s.scans_drawn, s.scans_rejected
    );
    let d = &s.drift;
    let line = |name: &str, v: &usar_log::mapping::Deviation| {
        println!(
            "  {name:<28} mean {:.2} m, max {:.2} m, final {:.2} m; heading mean {:.1}°, max {:.1}°",
            v.mean_m, v.max_m, v.final_m, v.mean_heading_deg, v.max_heading_deg
        );
    };
    println!(
        "drift over {:.1} m of the laser's path by odometry:",
        d.path_m
    );
    line("estimate vs odometry", &d.estimate_vs_odometry);
    if let (Some(o), Some(e)) = (&d.odometry_vs_logged, &d.estimate_vs_logged) {
        line("odometry vs the log's poses", o);
        line("estimate vs the log's poses", e);
    }
    println!(
        "{} frontiers; {:.1} s; wrote {}/{{map.yaml, map.pgm, map.png, rooms.png, trajectory.csv, summary.json}}",
        s.frontiers,
        s.seconds,
        out.display()
    );
}

/// The map as a scene to draw on: every cell not seen free is a wall.
fn walls_scene(map: &LogMap) -> Scene {
    let g = *map.grid.geometry();
    let mut walls = Scene::empty("log map", g);
    for (i, o) in walls.obstacle.as_mut_slice().iter_mut().enumerate() {
        if map.grid.class_at_index(i) != usar_map::CellClass::Free {
            *o = obstacle::WALL;
        }
    }
    walls
}

/// `usar btm build --from-log`: a BTM built passively along a log's path.
pub fn btm_from_log(path: &Path, args: &BtmBuildArgs) -> CmdResult {
    use usar_btm::build::passive::PassiveBuilder;
    use usar_btm::report::{self, Sizes};
    use usar_btm::store::BtmStore;
    let started = Instant::now();
    let config = super::btm::build_config(args)?;
    let robot = crate::scene_source::load_robot(&args.robot)?;
    let params = MapParams {
        matcher: matcher(&args.matcher)?,
        ..MapParams::default()
    };
    let log = read(path, None)?;
    let bar = progress::bar(2, "passive BTM", args.json);
    let map = build_map(&log, &params).input()?;
    let scans = map.drawn_scans(&log, &params).input()?;
    bar.inc(1);
    let partial = partial_path(&args.out);
    let _ = std::fs::remove_file(&partial);
    let store = BtmStore::create(&partial).input()?;
    let mut builder = PassiveBuilder::new(config, robot.width_m, Some(&store));
    for scan in &scans {
        builder.observe(
            scan.pose,
            &usar_map::localization::ScanView::from_scan(scan),
        )?;
    }
    let btm = builder.finish()?;
    drop(store);
    std::fs::rename(&partial, &args.out)?;
    bar.finish_and_clear();
    let scene = walls_scene(&map);
    if let Some(png) = &args.png {
        let trace: Vec<usar_world::Point2> = map
            .trajectory
            .iter()
            .map(|t| t.estimate.position())
            .collect();
        report::save_drawing(&btm, Some(&scene), &trace, png).map_err(super::btm::fail)?;
    }
    let sizes =
        Sizes::measure(&btm, &args.out, scene.geometry().len()).map_err(super::btm::fail)?;
    let by_kind = |k: &str| btm.nodes.iter().filter(|n| n.kind == k).count();
    let searched = btm.links.iter().filter(|l| l.searched).count();
    if args.json {
        let mut v = report::describe(&btm);
        v["log"] = serde_json::json!(path);
        v["robot"] = serde_json::json!(robot.name);
        v["matcher"] = serde_json::json!(params.matcher.name());
        v["scans"] = serde_json::json!(scans.len());
        v["distance_m"] = serde_json::json!(map.drift.path_m);
        v["seconds"] = serde_json::json!(started.elapsed().as_secs_f64());
        v["bytes"] = serde_json::json!(sizes);
        v["out"] = serde_json::json!(args.out);
        return print_json(&v);
    }
    println!(
        "{}: {} nodes ({} divergence, {} free space, {} terminal), {} links searched, {} un-searched, along {:.0} m of {} scans → {}; {} bytes as .btmb against {} for the grid; {:.1} s",
        path.display(),
        btm.nodes.len(),
        by_kind(usar_btm::model::kind::DIVERGENCE),
        by_kind(usar_btm::model::kind::FREE_SPACE),
        by_kind(usar_btm::model::kind::TERMINAL),
        searched,
        btm.links.len() - searched,
        map.drift.path_m,
        scans.len(),
        args.out.display(),
        sizes.btm_binary,
        sizes.occupancy_grid,
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

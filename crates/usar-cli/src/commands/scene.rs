//! `usar scene gen|import|export|show|info` (`segment` is in `segment.rs`).

use super::print_json;
use crate::cli::{
    SceneCommand, SceneExportArgs, SceneGenArgs, SceneImportArgs, SceneInfoArgs, SceneShowArgs,
};
use crate::failure::{CmdResult, InputContext, bad_input};
use crate::scene_source;
use serde_json::json;
use usar_world::generate::generate_furnished;
use usar_world::io::Exports;
use usar_world::render::{RenderOptions, render_scene};

pub fn run(cmd: SceneCommand) -> CmdResult {
    match cmd {
        SceneCommand::Gen(args) => generate(args),
        SceneCommand::Import(args) => import(args),
        SceneCommand::Export(args) => export(args),
        SceneCommand::Show(args) => show(args),
        SceneCommand::Info(args) => info(args),
        SceneCommand::Segment(args) => super::segment::run(args),
    }
}

fn generate(args: SceneGenArgs) -> CmdResult {
    scene_source::check_scene_output(&args.output, "-o")?;
    let kind = scene_source::kind(args.kind);
    let scene = generate_furnished(kind, args.seed, args.furniture)
        .map_err(|e| bad_input(anyhow::anyhow!("--furniture: {e}")))?;
    usar_world::write_scene(&scene, &args.output).input()?;
    let summary = scene.summary(&args.output);
    if args.json {
        print_json(&summary)
    } else {
        println!(
            "wrote {} ({}: {}×{} cells at {} m, {} rooms, {} victims)",
            args.output.display(),
            summary.name,
            summary.width,
            summary.height,
            summary.resolution_m,
            summary.rooms,
            summary.victims
        );
        Ok(())
    }
}

fn import(args: SceneImportArgs) -> CmdResult {
    scene_source::check_scene_output(&args.output, "-o")?;
    let spec = args.input.to_string_lossy().into_owned();
    if !args.input.exists() {
        return Err(bad_input(anyhow::anyhow!("{spec}: no such file")));
    }
    let scene = scene_source::load(&spec, 0, &args.image)?;
    usar_world::write_scene(&scene, &args.output).input()?;
    let summary = scene.summary(&args.output);
    if args.json {
        print_json(&summary)
    } else {
        println!(
            "wrote {} ({}×{} cells at {} m)",
            args.output.display(),
            summary.width,
            summary.height,
            summary.resolution_m
        );
        Ok(())
    }
}

fn export(args: SceneExportArgs) -> CmdResult {
    let exports = Exports {
        ros: args.ros.as_deref(),
        png: args.png.as_deref(),
        scene_file: args.scene_file.as_deref(),
    };
    if exports.is_empty() {
        return Err(bad_input(anyhow::anyhow!(
            "nothing to export: give --ros FILE.yaml, --png FILE.png or --scene-file FILE.json"
        )));
    }
    exports
        .check()
        .map_err(|e| bad_input(anyhow::anyhow!("--scene-file {e}")))?;
    let scene = scene_source::load_spec(&args.source)?;
    let written: Vec<String> = exports
        .write(&scene)
        .input()?
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    if args.json {
        print_json(&json!({ "written": written }))
    } else {
        println!("wrote {}", written.join(", "));
        Ok(())
    }
}

fn show(args: SceneShowArgs) -> CmdResult {
    let scene = scene_source::load_spec(&args.source)?;
    let opts = RenderOptions {
        px_per_cell: args.px_per_cell,
        show_ground_truth: args.ground_truth,
        ..RenderOptions::default()
    };
    let canvas = render_scene(&scene, &opts);
    canvas.save_png(&args.png).input()?;
    if args.json {
        print_json(
            &json!({ "png": args.png.display().to_string(), "width_px": canvas.width(), "height_px": canvas.height() }),
        )
    } else {
        println!(
            "wrote {} ({}×{} px)",
            args.png.display(),
            canvas.width(),
            canvas.height()
        );
        Ok(())
    }
}

fn info(args: SceneInfoArgs) -> CmdResult {
    let scene = scene_source::load_spec(&args.source)?;
    let info = scene.info();
    if args.json {
        return print_json(&info);
    }
    println!("scene {} ({})", info.name, info.provenance.source);
    println!(
        "  grid {}×{} cells at {} m = {:.1} × {:.1} m",
        info.grid.width, info.grid.height, info.grid.resolution_m, info.width_m, info.height_m
    );
    println!(
        "  free area {:.1} m², reachable from start {:.1} m²",
        info.free_area_m2, info.reachable_area_m2
    );
    for (label, share) in &info.labels {
        println!(
            "  {label:<12} {:>3} rooms {:>8.1} m² ({:.0} %)",
            share.rooms,
            share.area_m2,
            share.share * 100.0
        );
    }
    println!(
        "  doors {}, victims {}, other heat sources {}, start poses {}",
        info.doors.len(),
        info.victims.len(),
        info.heat_sources.len(),
        info.start_poses.len()
    );
    if !info.junctions.is_empty() {
        println!("  junctions {}", info.junctions.len());
    }
    Ok(())
}

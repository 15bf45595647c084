//! `usar scene gen|import|export|show|info` (`segment` is in `segment.rs`).

use super::print_json;
use crate::cli::{
    GeneratorKind, SceneCommand, SceneExportArgs, SceneGenArgs, SceneImportArgs, SceneInfoArgs,
    SceneShowArgs,
};
use crate::failure::{CmdResult, InputContext, bad_input};
use crate::scene_source;
use serde_json::json;
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

fn summary(scene: &usar_world::Scene, path: &std::path::Path) -> serde_json::Value {
    let g = scene.geometry();
    json!({
        "file": path.display().to_string(),
        "name": scene.name,
        "width": g.width,
        "height": g.height,
        "resolution_m": g.resolution_m,
        "rooms": scene.rooms.len(),
        "victims": scene.victims.len(),
        "start_poses": scene.start_poses.len(),
    })
}

fn generate(args: SceneGenArgs) -> CmdResult {
    scene_source::check_scene_output(&args.output, "-o")?;
    let scene = match (args.kind, args.furniture) {
        (_, None) => usar_world::generate::generate(scene_source::kind(args.kind), args.seed),
        (GeneratorKind::Office | GeneratorKind::Mall, Some(share)) => {
            use usar_world::generate::{BuildingParams, generate_mall, generate_office};
            type Generator = fn(u64, &BuildingParams) -> usar_world::Scene;
            let (defaults, generate): (BuildingParams, Generator) =
                if args.kind == GeneratorKind::Office {
                    (BuildingParams::office(), generate_office)
                } else {
                    (BuildingParams::mall(), generate_mall)
                };
            let params = BuildingParams {
                furniture_fraction: share,
                ..defaults
            };
            params
                .check()
                .map_err(|e| bad_input(anyhow::anyhow!("--furniture: {e}")))?;
            generate(args.seed, &params)
        }
        (kind, Some(_)) => {
            return Err(bad_input(anyhow::anyhow!(
                "--furniture: the {} generator has no furniture (only office and mall do)",
                scene_source::kind(kind)
            )));
        }
    };
    usar_world::write_scene(&scene, &args.output).input()?;
    if args.json {
        print_json(&summary(&scene, &args.output))
    } else {
        let g = scene.geometry();
        println!(
            "wrote {} ({}: {}×{} cells at {} m, {} rooms, {} victims)",
            args.output.display(),
            scene.name,
            g.width,
            g.height,
            g.resolution_m,
            scene.rooms.len(),
            scene.victims.len()
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
    if args.json {
        print_json(&summary(&scene, &args.output))
    } else {
        let g = scene.geometry();
        println!(
            "wrote {} ({}×{} cells at {} m)",
            args.output.display(),
            g.width,
            g.height,
            g.resolution_m
        );
        Ok(())
    }
}

fn export(args: SceneExportArgs) -> CmdResult {
    if args.ros.is_none() && args.png.is_none() && args.scene_file.is_none() {
        return Err(bad_input(anyhow::anyhow!(
            "nothing to export: give --ros FILE.yaml, --png FILE.png or --scene-file FILE.json"
        )));
    }
    if let Some(file) = &args.scene_file {
        scene_source::check_scene_output(file, "--scene-file")?;
    }
    let scene = scene_source::load_spec(&args.source)?;
    let mut written = Vec::new();
    if let Some(yaml) = &args.ros {
        usar_world::io::ros::write_ros_map(&scene, yaml).input()?;
        written.push(yaml.display().to_string());
    }
    if let Some(png) = &args.png {
        render_scene(&scene, &RenderOptions::default())
            .save_png(png)
            .input()?;
        written.push(png.display().to_string());
    }
    if let Some(file) = &args.scene_file {
        usar_world::write_scene(&scene, file).input()?;
        written.push(file.display().to_string());
    }
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

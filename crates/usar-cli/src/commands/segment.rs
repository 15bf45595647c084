//! `usar scene segment`: the room segmentation of a map, drawn, saved as the scene's room layer
//! and scored against a ground truth.

use super::print_json;
use crate::cli::SceneSegmentArgs;
use crate::failure::{CmdResult, InputContext, bad_input};
use crate::scene_source;
use serde_json::json;
use std::path::Path;
use usar_map::segmentation::evaluate::{
    ClassScore, RoomScore, scene_truth, score_classes, score_rooms, truth_classes_from_image,
    truth_image, truth_rooms_from_image,
};
use usar_map::segmentation::{SegmentationParams, segment_scene};

pub fn run(args: SceneSegmentArgs) -> CmdResult {
    let mut scene = scene_source::load_spec(&args.source)?;
    let params = match &args.params {
        Some(path) => read_params(path)?,
        None => SegmentationParams::default(),
    };
    let seg = segment_scene(&scene, &params);
    if args.against_layer && scene.rooms.is_empty() {
        return Err(bad_input(anyhow::anyhow!(
            "{}: --against-layer needs a scene with a room layer",
            args.source.scene
        )));
    }
    let (own_rooms, own_classes) = scene_truth(&scene);
    let rooms = match &args.truth_rooms {
        Some(path) => Some(score_rooms(
            &seg.labels(),
            &truth_rooms_from_image(&truth_image(path, &scene).input()?),
        )),
        None => args
            .against_layer
            .then(|| score_rooms(&seg.labels(), &own_rooms)),
    };
    let classes = match &args.truth_classes {
        Some(path) => Some(score_classes(
            &seg.corridor_classes(),
            &truth_classes_from_image(&truth_image(path, &scene).input()?),
        )),
        None => args
            .against_layer
            .then(|| score_classes(&seg.corridor_classes(), &own_classes)),
    };
    if let Some(png) = &args.png {
        seg.draw(&scene).save_png(png).input()?;
    }
    seg.apply_to(&mut scene);
    if let Some(out) = &args.output {
        usar_world::write_scene(&scene, out).input()?;
    }
    let by_label = seg.area_by_label();
    if args.json {
        let labels: serde_json::Map<String, serde_json::Value> = by_label
            .iter()
            .map(|(l, a)| {
                let n = seg.segments.iter().filter(|s| s.label == *l).count();
                (
                    l.as_str().to_string(),
                    json!({ "segments": n, "area_m2": a }),
                )
            })
            .collect();
        return print_json(&json!({
            "scene": scene.name,
            "params": params,
            "segments": seg.segments,
            "doors": seg.doors.len(),
            "corridor_links": seg.corridor_links.len(),
            "labels": labels,
            "truth_rooms": rooms,
            "truth_classes": classes,
        }));
    }
    println!(
        "{}: {} segments, {} doors, {} corridor junctions",
        scene.name,
        seg.segments.len(),
        seg.doors.len(),
        seg.corridor_links.len()
    );
    for (label, area) in by_label {
        let n = seg.segments.iter().filter(|s| s.label == label).count();
        println!("  {:<12} {n:>3} segments {area:>8.1} m²", label.as_str());
    }
    if let Some(RoomScore {
        truth_rooms,
        segments,
        recall,
        precision,
        jaccard,
    }) = rooms
    {
        println!(
            "  against {truth_rooms} true rooms ({segments} segments): recall {recall:.3}, precision {precision:.3}, best-match Jaccard {jaccard:.3}"
        );
    }
    if let Some(ClassScore {
        cells,
        accuracy,
        corridor_recall,
        room_recall,
    }) = classes
    {
        println!(
            "  room vs corridor on {cells} cells: accuracy {accuracy:.3} (corridor recall {corridor_recall:.3}, room recall {room_recall:.3})"
        );
    }
    Ok(())
}

fn read_params(path: &Path) -> CmdResult<SegmentationParams> {
    let params: SegmentationParams = scene_source::read_toml(path)?;
    params
        .check()
        .map_err(|e| bad_input(anyhow::anyhow!("{}: {e}", path.display())))?;
    Ok(params)
}

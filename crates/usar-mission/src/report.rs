//! A mission's report folder: `map.png` (the team's merged map, the crawler's BTM, the
//! keep-out zones, the rescuer's zone, every robot's trajectory as it believed it, the
//! victims), `victims.csv` (who detected, who confirmed, when), `handoffs.csv` (the operator's
//! timeline), `coverage.csv` and `summary.json`, written last so that a folder with a summary
//! is complete.

use crate::MissionOutcome;
use std::path::Path;
use usar_world::render::Canvas;
use usar_world::{Point2, write_atomic};

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("{path}: cannot create the report folder: {io}")]
    Folder { path: String, io: std::io::Error },
    #[error(transparent)]
    World(#[from] usar_world::WorldError),
}

/// Team robots' colours, then the crawler's.
const TEAM_RGB: [[u8; 3]; 6] = [
    [31, 119, 180],
    [44, 160, 44],
    [148, 103, 189],
    [23, 190, 207],
    [188, 189, 34],
    [140, 86, 75],
];
const CRAWLER_RGB: [u8; 3] = [255, 127, 14];
const RESCUER_RGB: [u8; 3] = [214, 39, 40];

/// The map: unknown grey, free white, occupied black; keep-out zones shaded red; the BTM's
/// links and nodes in the crawler's orange; the rescuer's zone outlined and its path in red;
/// trajectories; victims confirmed (green discs), detected only (yellow discs) and missed (red
/// circles).
pub fn render_mission_map(outcome: &MissionOutcome) -> Canvas {
    let mut canvas = usar_team::report::draw_grid(&outcome.merged_map);
    for &(a, b, r) in &outcome.keep_outs {
        let steps = (a.distance(b) / (r / 2.0).max(0.05)).ceil().max(1.0) as usize;
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let p = Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
            canvas.draw_circle(p, r, [220, 60, 60]);
        }
    }
    for (k, trajectory) in outcome.team_trajectories.iter().enumerate() {
        canvas.draw_polyline(trajectory, TEAM_RGB[k % TEAM_RGB.len()]);
    }
    canvas.draw_polyline(&outcome.crawler_trajectory, CRAWLER_RGB);
    if let Some(btm) = &outcome.btm {
        for link in &btm.links {
            let (Some(a), Some(b)) = (btm.node(link.start), link.end.and_then(|e| btm.node(e)))
            else {
                continue;
            };
            canvas.draw_polyline(
                &[Point2::new(a.x_m, a.y_m), Point2::new(b.x_m, b.y_m)],
                CRAWLER_RGB,
            );
        }
        for n in &btm.nodes {
            canvas.draw_disc(Point2::new(n.x_m, n.y_m), 0.25, CRAWLER_RGB);
        }
    }
    if let Some(zone) = &outcome.rescuer_zone {
        let (w, h) = zone.extent_m();
        let o = zone.origin;
        canvas.draw_polyline(
            &[
                o,
                Point2::new(o.x + w, o.y),
                Point2::new(o.x + w, o.y + h),
                Point2::new(o.x, o.y + h),
                o,
            ],
            RESCUER_RGB,
        );
    }
    canvas.draw_polyline(&outcome.rescuer_trajectory, RESCUER_RGB);
    for v in &outcome.victims {
        let p = Point2::new(v.x_m, v.y_m);
        if v.confirmed_by.is_some() {
            canvas.draw_disc(p, 0.35, [0, 170, 0]);
        } else if v.detected_by.is_some() {
            canvas.draw_disc(p, 0.35, [230, 200, 0]);
        } else {
            canvas.draw_circle(p, 0.35, [220, 0, 0]);
        }
    }
    canvas
}

/// Writes the report folder `dir` (created if needed) and returns the summary it wrote: the
/// outcome, with the fields of `extra` (e.g. the wall time) added.
pub fn write_report(
    dir: &Path,
    outcome: &MissionOutcome,
    extra: serde_json::Value,
) -> Result<serde_json::Value, ReportError> {
    std::fs::create_dir_all(dir).map_err(|io| ReportError::Folder {
        path: dir.display().to_string(),
        io,
    })?;
    render_mission_map(outcome).save_png(&dir.join("map.png"))?;
    let time = |t: Option<f64>| t.map_or(String::new(), |t| format!("{t:.1}"));
    let mut victims =
        String::from("id,x_m,y_m,detected_by,detected_at_s,confirmed_by,confirmed_at_s\n");
    for v in &outcome.victims {
        victims.push_str(&format!(
            "{},{:.2},{:.2},{},{},{},{}\n",
            v.id,
            v.x_m,
            v.y_m,
            v.detected_by.as_deref().unwrap_or(""),
            time(v.detected_at_s),
            v.confirmed_by.as_deref().unwrap_or(""),
            time(v.confirmed_at_s),
        ));
    }
    write_atomic(&dir.join("victims.csv"), victims.as_bytes())?;
    let mut handoffs = String::from("robot,kind,asked_s,started_s,answered_s,answer,was_victim\n");
    for h in &outcome.handoffs {
        handoffs.push_str(&format!(
            "{},{},{:.1},{:.1},{:.1},{},{}\n",
            h.robot,
            h.kind,
            h.asked_s,
            h.started_s,
            h.answered_s,
            h.answer,
            h.was_victim.map_or(String::new(), |v| v.to_string()),
        ));
    }
    write_atomic(&dir.join("handoffs.csv"), handoffs.as_bytes())?;
    let mut coverage = String::from("time_s,coverage,relevant_area_m2\n");
    for s in &outcome.series {
        coverage.push_str(&format!(
            "{:.1},{:.6},{:.2}\n",
            s.time_s, s.coverage, s.relevant_area_m2
        ));
    }
    write_atomic(&dir.join("coverage.csv"), coverage.as_bytes())?;
    let mut summary = serde_json::to_value(outcome).expect("an outcome serialises");
    if let (Some(summary), serde_json::Value::Object(extra)) = (summary.as_object_mut(), extra) {
        summary.extend(extra);
    }
    summary["files"] = serde_json::json!([
        "map.png",
        "victims.csv",
        "handoffs.csv",
        "coverage.csv",
        "summary.json"
    ]);
    let text = serde_json::to_string_pretty(&summary).expect("JSON");
    write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    Ok(summary)
}

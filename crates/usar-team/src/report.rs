//! A mission's report folder: the explored map with the robots' trajectories and the victims,
//! coverage over time (CSV, PNG, SVG), victims (CSV) and `summary.json`. Every file is written
//! atomically; `summary.json` is written last, so a folder with a summary is complete.

use crate::outcome::TeamOutcome;
use serde_json::json;
use std::path::Path;
use usar_map::{CellClass, OccupancyGrid};
use usar_plot::{LineChart, PALETTE, Series};
use usar_world::render::Canvas;
use usar_world::{Scene, write_atomic};

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("{path}: cannot create the report folder: {io}")]
    Folder { path: String, io: std::io::Error },
    #[error(transparent)]
    World(#[from] usar_world::WorldError),
    #[error(transparent)]
    Plot(#[from] usar_plot::PlotError),
    #[error("cannot write CSV: {0}")]
    Csv(String),
}

/// An occupancy grid on a canvas at most 1 600 pixels a side: unknown grey, free white,
/// occupied black.
pub fn draw_grid(grid: &OccupancyGrid) -> Canvas {
    let g = *grid.geometry();
    let mut canvas = Canvas::fit(g, 1600);
    canvas.fill([150, 150, 150]);
    for i in 0..g.len() {
        let rgb = match grid.class_at_index(i) {
            CellClass::Unknown => continue,
            CellClass::Free => [255, 255, 255],
            CellClass::Occupied => [0, 0, 0],
        };
        canvas.fill_cell(g.cell_of_index(i), rgb);
    }
    canvas
}

/// Renders the base station's map: unknown grey, free white, occupied black; trajectories in
/// the palette colours; victims seen as filled green discs, victims missed as red circles.
pub fn render_explored_map(scene: &Scene, outcome: &TeamOutcome) -> Canvas {
    let mut canvas = draw_grid(&outcome.merged_map);
    for (k, robot) in outcome.per_robot.iter().enumerate() {
        let (r, gr, b) = PALETTE[k % PALETTE.len()];
        canvas.draw_polyline(&robot.trajectory, [r, gr, b]);
        if let Some(&last) = robot.trajectory.last() {
            canvas.draw_disc(last, 0.3, [r, gr, b]);
        }
    }
    for v in &scene.victims {
        if outcome.victim_sightings.iter().any(|s| s.victim_id == v.id) {
            canvas.draw_disc(v.position, 0.35, [0, 170, 0]);
        } else {
            canvas.draw_circle(v.position, 0.35, [220, 0, 0]);
        }
    }
    canvas
}

fn csv_bytes(
    rows: impl FnOnce(&mut csv::Writer<Vec<u8>>) -> csv::Result<()>,
) -> Result<Vec<u8>, ReportError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    rows(&mut w).map_err(|e| ReportError::Csv(e.to_string()))?;
    w.into_inner().map_err(|e| ReportError::Csv(e.to_string()))
}

/// Writes the report folder `dir` (created if needed) and returns the summary it wrote.
pub fn write_report(
    dir: &Path,
    scene: &Scene,
    outcome: &TeamOutcome,
    extra: serde_json::Value,
) -> Result<serde_json::Value, ReportError> {
    std::fs::create_dir_all(dir).map_err(|io| ReportError::Folder {
        path: dir.display().to_string(),
        io,
    })?;
    render_explored_map(scene, outcome).save_png(&dir.join("map.png"))?;
    let coverage_csv = csv_bytes(|w| {
        w.write_record([
            "time_s",
            "coverage",
            "explored_area_m2",
            "victims_seen",
            "distance_m",
        ])?;
        for s in &outcome.series {
            w.write_record([
                format!("{:.1}", s.time_s),
                format!("{:.6}", s.coverage),
                format!("{:.2}", s.explored_area_m2),
                s.victims_seen.to_string(),
                format!("{:.2}", s.distance_m),
            ])?;
        }
        Ok(())
    })?;
    write_atomic(&dir.join("coverage.csv"), &coverage_csv)?;
    let chart = LineChart {
        title: format!("Coverage of {} by {} robots", outcome.scene, outcome.robots),
        x_label: "time (s)".into(),
        y_label: "known fraction of the reachable area".into(),
        series: vec![Series::line(
            "coverage",
            outcome
                .series
                .iter()
                .map(|s| (s.time_s, s.coverage))
                .collect(),
        )],
        y_range: Some((0.0, 1.0)),
    };
    chart.save(&dir.join("coverage.png"))?;
    chart.save(&dir.join("coverage.svg"))?;
    let victims_csv = csv_bytes(|w| {
        w.write_record(["victim_id", "x_m", "y_m", "seen", "time_s", "robot"])?;
        for v in &scene.victims {
            let seen = outcome
                .victim_sightings
                .iter()
                .find(|s| s.victim_id == v.id);
            w.write_record([
                v.id.to_string(),
                format!("{:.2}", v.position.x),
                format!("{:.2}", v.position.y),
                seen.is_some().to_string(),
                seen.map(|s| format!("{:.1}", s.time_s)).unwrap_or_default(),
                seen.map(|s| s.robot.to_string()).unwrap_or_default(),
            ])?;
        }
        Ok(())
    })?;
    write_atomic(&dir.join("victims.csv"), &victims_csv)?;
    let mut summary = json!({
        "scene": outcome.scene,
        "robots": outcome.robots,
        "time_s": outcome.time_s,
        "finish": outcome.finish,
        "coverage": outcome.coverage,
        "explored_area_m2": outcome.explored_area_m2,
        "reachable_area_m2": outcome.reachable_area_m2,
        "victims_seen": outcome.victims_seen,
        "victims_total": outcome.victims_total,
        "distance_m": outcome.distance_m,
        "collisions": outcome.collisions,
        "files": ["map.png", "coverage.csv", "coverage.png", "coverage.svg", "victims.csv", "summary.json"],
    });
    if let (Some(obj), serde_json::Value::Object(more)) = (summary.as_object_mut(), extra) {
        obj.extend(more);
    }
    let mut text =
        serde_json::to_string_pretty(&summary).map_err(|e| ReportError::Csv(e.to_string()))?;
    text.push('\n');
    write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    Ok(summary)
}

//! How the simulator and paper 002's team scale with the team's size: simulated ÷ wall time
//! and peak resident memory for teams of 1 to 512 robots on the generated mall floor, one
//! core, for two pipelines:
//!
//! - `nearest`: the simulator with every robot mapping (its laser once per simulated second,
//!   the base station merging) and the nearest-frontier explorer;
//! - `s-mcdm-mrv1`: paper 002's team, S-MCDM with MRv1 coordination and the big-rooms
//!   hypothesis (auctions every 5 s and on arrival).
//!
//! Every run starts the same way: the mall floor (seed 1) with start poses added for the team
//! as `usar mission` adds them, then `seconds` of simulated time. Peak memory is the process's
//! resident high-water mark (`VmHWM`), reset before each run (`/proc/self/clear_refs`, Linux);
//! `None` elsewhere.

use crate::BenchError;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::time::Instant;
use usar_map::segmentation::SegmentationParams;
use usar_team::coordination::Coordination;
use usar_team::{Exploration, Strategy, TeamConfig, TeamMission};
use usar_world::generate::{SceneKind, generate};

/// The team sizes of the table.
pub const SIZES: [usize; 5] = [1, 8, 32, 128, 512];

/// One cell of the scaling table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScalingRow {
    pub pipeline: String,
    pub robots: usize,
    pub simulated_s: f64,
    pub wall_s: f64,
    /// Simulated ÷ wall time.
    pub realtime_factor: f64,
    /// Robot-seconds simulated per wall second (the work rate).
    pub robot_s_per_s: f64,
    pub peak_rss_mib: Option<f64>,
}

/// The scaling table (`usar bench --scaling`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScalingReport {
    pub floor: String,
    pub rows: Vec<ScalingRow>,
}

/// The two pipelines of the table.
pub const PIPELINES: [&str; 2] = ["nearest", "s-mcdm-mrv1"];

fn config(pipeline: &str, robots: usize, seconds: f64) -> TeamConfig {
    let exploration = match pipeline {
        "nearest" => Exploration {
            strategy: Strategy::Nearest,
            ..Exploration::default()
        },
        _ => Exploration {
            strategy: Strategy::SMcdm,
            coordination: Coordination::Mrv1,
            ..Exploration::default()
        },
    };
    TeamConfig::paper_002(robots, seconds / 60.0, exploration)
}

/// Resets the resident high-water mark (Linux: `5` to `/proc/self/clear_refs`).
fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// The resident high-water mark, MiB.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kb: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb / 1024.0)
}

/// Runs `pipelines` (of [`PIPELINES`]) at every size of `sizes` for `seconds` simulated seconds;
/// `row_done` is called after each run. Peak memory is only the run's own when it runs alone
/// in its process (the allocator keeps what earlier runs freed): `usar bench --scaling` runs
/// each cell of the table in a process of its own.
pub fn scaling(
    sizes: &[usize],
    pipelines: &[&'static str],
    seconds: f64,
    mut row_done: impl FnMut(&ScalingRow),
) -> Result<ScalingReport, BenchError> {
    let floor = generate(SceneKind::Mall, 1);
    let widest = config(PIPELINES[0], 1, seconds)
        .robot
        .circumscribed_radius_m();
    let mut rows = Vec::new();
    for &robots in sizes {
        let mut scene = floor.clone();
        usar_team::scene_prep::prepare_scene(
            &mut scene,
            robots,
            widest + 0.1,
            &SegmentationParams::default(),
        );
        let scene = Arc::new(scene);
        for &pipeline in pipelines {
            let config = config(pipeline, robots, seconds);
            let measured_peak = reset_peak();
            let mission = TeamMission::new(scene.clone(), config, 1)?;
            let t = Instant::now();
            let outcome = mission.run(|_| {});
            let wall_s = t.elapsed().as_secs_f64();
            let simulated_s = outcome.time_s;
            std::hint::black_box(&outcome);
            let row = ScalingRow {
                pipeline: pipeline.to_string(),
                robots,
                simulated_s,
                wall_s,
                realtime_factor: simulated_s / wall_s,
                robot_s_per_s: simulated_s * robots as f64 / wall_s,
                peak_rss_mib: if measured_peak { peak_rss_mib() } else { None },
            };
            row_done(&row);
            rows.push(row);
        }
    }
    Ok(ScalingReport {
        floor: format!(
            "mall (seed 1), {} × {} cells at {} m",
            floor.geometry().width,
            floor.geometry().height,
            floor.geometry().resolution_m
        ),
        rows,
    })
}

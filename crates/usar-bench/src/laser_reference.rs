//! usar's laser beside the Python reference (`usar bench --laser-reference`): the same scans on
//! the same floor from the same poses, timed in one run, usar first, then the reference —
//! `reference/laser_reference.py`, the raycast2D package (a C Bresenham raycaster on a NumPy
//! image) with an OpenCV occupancy update, as a Python user would write it.

use crate::{BenchError, bench_scene, free_poses, laser_rate};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use usar_sim::sensors::{LaserModel, LaserSpec};
use usar_world::{GridGeometry, Pose2, Scene};

/// The reference script, written next to the floor it reads.
pub const SCRIPT: &str = include_str!("../reference/laser_reference.py");

/// Poses the scans cycle through (as in [`crate::run`]).
const POSES: usize = 500;

/// One side-by-side measurement.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LaserComparison {
    /// usar: 360-beam 20 m scans with their occupancy update per second (as
    /// [`crate::BenchReport::lidar_scans_per_s`]).
    pub usar_scans_per_s: f64,
    /// The reference, on the same floor and poses.
    pub reference_scans_per_s: f64,
    /// usar ÷ reference.
    pub ratio: f64,
    /// Scans per timed repetition (each side) and repetitions (the median is kept).
    pub scans: usize,
    pub reps: usize,
    /// The interpreter that ran the reference.
    pub python: PathBuf,
}

/// What the reference script prints.
#[derive(Deserialize)]
struct ReferenceRate {
    scans_per_s: f64,
}

/// The floor as the reference reads it: a binary PGM, 255 on free cells and 0 on obstacles,
/// rows in grid order (row 0 first).
pub fn write_pgm(scene: &Scene, path: &Path) -> std::io::Result<()> {
    let g = scene.geometry();
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(out, "P5\n{} {}\n255\n", g.width, g.height)?;
    let pixels: Vec<u8> = scene
        .obstacle
        .as_slice()
        .iter()
        .map(|&o| {
            if o == usar_world::obstacle::NONE {
                255
            } else {
                0
            }
        })
        .collect();
    out.write_all(&pixels)?;
    out.flush()
}

/// Poses as the reference reads them: `col,row,theta` per line, at their cells.
pub fn write_poses(g: &GridGeometry, poses: &[Pose2], path: &Path) -> std::io::Result<()> {
    let mut text = String::new();
    for p in poses {
        let c = g.world_to_cell(p.position());
        text.push_str(&format!("{},{},{}\n", c.col, c.row, p.theta));
    }
    std::fs::write(path, text)
}

/// The reference's inputs (floor, poses, script) in `dir`; returns the script's path.
pub fn write_inputs(scene: &Scene, poses: &[Pose2], dir: &Path) -> std::io::Result<PathBuf> {
    write_pgm(scene, &dir.join("floor.pgm"))?;
    write_poses(scene.geometry(), poses, &dir.join("poses.csv"))?;
    let script = dir.join("laser_reference.py");
    std::fs::write(&script, SCRIPT)?;
    Ok(script)
}

/// The 20 m range in cells of `g`.
fn range_cells(g: &GridGeometry) -> u32 {
    (LaserSpec::default().max_range_m / g.resolution_m).round() as u32
}

/// usar's laser and the reference with `python` (which must have `raycast2D`, `opencv-python`
/// and `numpy`), `scans` scans a repetition, median of `reps`.
pub fn compare(python: &Path, scans: usize, reps: usize) -> Result<LaserComparison, BenchError> {
    let scene = bench_scene();
    let poses = free_poses(&scene, POSES);
    let laser = LaserModel::new(LaserSpec::default());
    let mut rng = Pcg64Mcg::seed_from_u64(7);
    let usar_scans_per_s = laser_rate(&scene, &laser, &mut rng, reps, scans);

    let dir = tempfile::tempdir()?;
    let script = write_inputs(&scene, &poses, dir.path())?;
    let out = Command::new(python)
        .arg(&script)
        .arg("bench")
        .arg(dir.path().join("floor.pgm"))
        .arg(dir.path().join("poses.csv"))
        .arg(range_cells(scene.geometry()).to_string())
        .arg(scans.to_string())
        .arg(reps.to_string())
        .output()
        .map_err(|e| BenchError::Reference(format!("{}: {e}", python.display())))?;
    if !out.status.success() {
        return Err(BenchError::Reference(format!(
            "{} {}: {}",
            python.display(),
            script.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let reference: ReferenceRate = serde_json::from_slice(&out.stdout).map_err(|e| {
        BenchError::Reference(format!(
            "the reference printed {:?}, not its JSON rate: {e}",
            String::from_utf8_lossy(&out.stdout)
        ))
    })?;
    Ok(LaserComparison {
        usar_scans_per_s,
        reference_scans_per_s: reference.scans_per_s,
        ratio: usar_scans_per_s / reference.scans_per_s,
        scans,
        reps,
        python: python.to_path_buf(),
    })
}

//! What recording a run costs (`usar bench --recording`): the demo's mission — the built-in
//! [`MissionConfig`] on office floor 1, seed 1, the MAXQ robot's training included, as
//! `usar demo` runs it — timed alone and with a [`MissionRecorder`] writing its MCAP file to
//! disk, alternately, `reps` times each; the medians and their ratio.

use crate::{BenchError, median};
use serde::Serialize;
use std::sync::Arc;
use std::time::Instant;
use usar_mission::{MissionConfig, Operator, run_mission, run_mission_live};
use usar_record::{MissionRecorder, Recording};

/// The figures of [`recording_overhead`].
#[derive(Clone, Debug, Serialize)]
pub struct RecordingOverhead {
    pub runs_each: usize,
    /// Median wall seconds of the mission alone and recorded.
    pub plain_s: f64,
    pub recorded_s: f64,
    /// recorded ÷ plain − 1 (the limit: 0.20).
    pub overhead: f64,
    pub messages: u64,
    pub bytes: u64,
}

/// Times the demo's mission `reps` times alone and `reps` times recorded, alternately.
pub fn recording_overhead(
    reps: usize,
    mut run_done: impl FnMut(),
) -> Result<RecordingOverhead, BenchError> {
    let config = MissionConfig::default();
    let scene = usar_world::io::source::load_scene(
        &config.scene,
        config.scene_seed,
        &usar_world::io::source::BareImage::default(),
    )
    .map_err(|e| BenchError::Mission(format!("the demo's scene: {e}")))?;
    let scene = Arc::new(scene);
    let dir = tempfile::tempdir()?;
    let path = dir.path().join("run.mcap");
    let (mut plain, mut recorded) = (Vec::new(), Vec::new());
    let (mut messages, mut bytes) = (0, 0);
    for _ in 0..reps.max(1) {
        let t = Instant::now();
        let outcome = run_mission(scene.clone(), &config, 1, None, |_| {});
        std::hint::black_box(outcome.map_err(mission_error)?);
        plain.push(t.elapsed().as_secs_f64());
        run_done();

        let t = Instant::now();
        let file = std::io::BufWriter::new(std::fs::File::create(&path)?);
        let mut recorder = MissionRecorder::new(Recording::new(file).map_err(record_error)?);
        let outcome = run_mission_live(
            scene.clone(),
            &config,
            1,
            None,
            Operator::Simulated,
            |_| {},
            &mut recorder,
        );
        std::hint::black_box(outcome.map_err(mission_error)?);
        messages = recorder.finish().map_err(record_error)?;
        recorded.push(t.elapsed().as_secs_f64());
        bytes = std::fs::metadata(&path)?.len();
        run_done();
    }
    let (plain_s, recorded_s) = (median(plain), median(recorded));
    Ok(RecordingOverhead {
        runs_each: reps.max(1),
        plain_s,
        recorded_s,
        overhead: recorded_s / plain_s - 1.0,
        messages,
        bytes,
    })
}

fn mission_error(e: impl std::fmt::Display) -> BenchError {
    BenchError::Mission(format!("the demo's mission: {e}"))
}

fn record_error(e: usar_record::RecordError) -> BenchError {
    BenchError::Mission(e.to_string())
}

//! Many WebSocket viewers against a running console: does the simulation keep its speed, and
//! does every viewer keep receiving frames? First the simulation's speed is measured with no
//! viewer, then with `viewers` connected; each viewer counts its frames and its longest gap.

use crate::{ConsoleConfig, ConsoleError, MissionConfig, start};
use futures_util::StreamExt;
use serde::Serialize;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tokio_tungstenite::tungstenite::Message;

/// What the bench measured.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub viewers: usize,
    pub seconds: f64,
    /// The speed asked for (simulated s per wall s).
    pub target_speed: f64,
    /// Measured with no viewer and with all viewers connected.
    pub speed_without_viewers: f64,
    pub speed_with_viewers: f64,
    /// speed_with_viewers / speed_without_viewers − 1.
    pub speed_change: f64,
    /// The team simulation's steps per wall-clock second in each measurement (0 once the
    /// team's mission has ended and only the clock and the MAXQ robot go on).
    pub team_steps_per_s_without_viewers: f64,
    pub team_steps_per_s_with_viewers: f64,
    /// Frames per second received: the slowest viewer, the mean, the fastest.
    pub min_frames_per_s: f64,
    pub mean_frames_per_s: f64,
    pub max_frames_per_s: f64,
    /// The longest time any viewer went without a frame, s.
    pub max_gap_s: f64,
    /// Viewers that received at least one frame in every second of the measurement.
    pub viewers_receiving_every_second: usize,
    pub load_average: Option<String>,
}

#[derive(Default)]
struct ViewerStats {
    frames: u64,
    max_gap_s: f64,
    seconds_with_frames: Vec<bool>,
}

async fn viewer(url: String, stop: Arc<AtomicBool>, start: Instant, seconds: usize) -> ViewerStats {
    let mut stats = ViewerStats {
        seconds_with_frames: vec![false; seconds],
        ..ViewerStats::default()
    };
    let Ok((mut ws, _)) = tokio_tungstenite::connect_async(url.as_str()).await else {
        return stats;
    };
    let mut last = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        let next = tokio::time::timeout(Duration::from_millis(200), ws.next()).await;
        let now = Instant::now();
        match next {
            Ok(Some(Ok(Message::Text(text)))) => {
                if text.as_str().starts_with("{\"type\":\"frame\"") {
                    stats.frames += 1;
                    stats.max_gap_s = stats.max_gap_s.max(now.duration_since(last).as_secs_f64());
                    last = now;
                    let k = now.duration_since(start).as_secs() as usize;
                    if k < seconds {
                        stats.seconds_with_frames[k] = true;
                    }
                }
            }
            Ok(Some(Ok(_))) => {}
            Ok(_) => break,
            Err(_) => {
                stats.max_gap_s = stats.max_gap_s.max(now.duration_since(last).as_secs_f64());
            }
        }
    }
    stats
}

/// The simulation's speed (simulated s per wall s) and the team's steps per wall second over
/// `seconds` of wall-clock time.
async fn measure_speed(console: &crate::RunningConsole, seconds: f64) -> (f64, f64) {
    let Some(shared) = console.shared() else {
        return (0.0, 0.0);
    };
    let steps = || shared.steps.load(Ordering::Relaxed) as f64;
    let (t0, s0, n0) = (Instant::now(), shared.clock.now_s(), steps());
    tokio::time::sleep(Duration::from_secs_f64(seconds)).await;
    let wall = t0.elapsed().as_secs_f64();
    ((shared.clock.now_s() - s0) / wall, (steps() - n0) / wall)
}

/// Runs the bench on a fresh local console.
pub async fn run(
    mission: MissionConfig,
    viewers: usize,
    seconds: f64,
) -> Result<BenchReport, ConsoleError> {
    let target_speed = mission.speed;
    let console = start(ConsoleConfig::local(mission)).await?;
    // Warm-up: the first frames, the first map.
    tokio::time::sleep(Duration::from_secs(2)).await;
    let (speed_without_viewers, team_steps_per_s_without_viewers) =
        measure_speed(&console, seconds).await;
    let url = format!("ws://{}/ws", console.addr);
    let stop = Arc::new(AtomicBool::new(false));
    let whole = seconds.ceil() as usize;
    let connected_at = Instant::now();
    let tasks: Vec<_> = (0..viewers)
        .map(|_| {
            tokio::spawn(viewer(
                url.clone(),
                stop.clone(),
                connected_at + Duration::from_secs(1),
                whole,
            ))
        })
        .collect();
    tokio::time::sleep(Duration::from_secs(1)).await;
    let measured_from = Instant::now();
    let (speed_with_viewers, team_steps_per_s_with_viewers) =
        measure_speed(&console, seconds).await;
    let measured_s = measured_from.elapsed().as_secs_f64();
    stop.store(true, Ordering::Relaxed);
    let mut stats = Vec::new();
    for t in tasks {
        stats.push(t.await.unwrap_or_default());
    }
    console.stop().await;
    // Frames counted from connection; rate over the connected time.
    let connected_s = measured_s + 1.0;
    let rates: Vec<f64> = stats
        .iter()
        .map(|s| s.frames as f64 / connected_s)
        .collect();
    let n = rates.len().max(1) as f64;
    Ok(BenchReport {
        viewers,
        seconds,
        target_speed,
        speed_without_viewers,
        speed_with_viewers,
        speed_change: if speed_without_viewers > 0.0 {
            speed_with_viewers / speed_without_viewers - 1.0
        } else {
            0.0
        },
        team_steps_per_s_without_viewers,
        team_steps_per_s_with_viewers,
        min_frames_per_s: rates
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .min(f64::MAX),
        mean_frames_per_s: rates.iter().sum::<f64>() / n,
        max_frames_per_s: rates.iter().copied().fold(0.0, f64::max),
        max_gap_s: stats.iter().map(|s| s.max_gap_s).fold(0.0, f64::max),
        viewers_receiving_every_second: stats
            .iter()
            .filter(|s| {
                !s.seconds_with_frames.is_empty() && s.seconds_with_frames.iter().all(|&b| b)
            })
            .count(),
        load_average: std::fs::read_to_string("/proc/loadavg")
            .ok()
            .map(|s| s.trim().to_string()),
    })
}

/// [`run`] on its own runtime (for the `usar console bench` command).
pub fn run_blocking(
    mission: MissionConfig,
    viewers: usize,
    seconds: f64,
) -> Result<BenchReport, ConsoleError> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| ConsoleError::Field {
            field: "runtime".into(),
            message: e.to_string(),
        })?;
    runtime.block_on(run(mission, viewers, seconds))
}

//! Many WebSocket viewers, and connections held against the console's limits, against a running
//! console: does the simulation keep its speed, and does every viewer keep receiving frames?
//! First the simulation's speed is measured with no client, then with `viewers` (authenticated
//! WebSockets, each counting its frames and its longest gap) and `connections` (bounded
//! connections: raw WebSockets without the token, half of them idle until the auth deadline
//! closes them, half announcing a 1 MiB message that is refused from its frame header; each
//! opens another half a second after the server closed it) connected. The console runs with
//! its default limits.

use crate::{ConsoleConfig, ConsoleError, MissionConfig, start};
use futures_util::StreamExt;
use serde::Serialize;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_tungstenite::tungstenite::Message;

/// What the bench measured.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub viewers: usize,
    /// Bounded connections held open during the second measurement.
    pub connections: usize,
    pub seconds: f64,
    /// The speed asked for (simulated s per wall s).
    pub target_speed: f64,
    /// Measured with no client, and with all viewers and bounded connections connected.
    pub speed_without_viewers: f64,
    pub speed_with_viewers: f64,
    /// speed_with_viewers / speed_without_viewers − 1.
    pub speed_change: f64,
    /// The team simulation's steps per wall-clock second in each measurement (0 once the
    /// team's mission has ended and only the clock and the MAXQ robot go on).
    pub team_steps_per_s_without_viewers: f64,
    pub team_steps_per_s_with_viewers: f64,
    /// Frames per second received: the slowest viewer, the mean, the fastest (0 without viewers).
    pub min_frames_per_s: f64,
    pub mean_frames_per_s: f64,
    pub max_frames_per_s: f64,
    /// The longest time any viewer went without a frame, s.
    pub max_gap_s: f64,
    /// Viewers that received at least one frame in every second of the measurement.
    pub viewers_receiving_every_second: usize,
    /// Viewers that received at least one frame.
    pub viewers_with_frames: usize,
    /// The bounded connections' WebSocket upgrades accepted (101), refused with 503 at the
    /// connection cap, and connections the server closed (auth deadline, oversize message).
    pub connections_upgraded: u64,
    pub connections_refused: u64,
    pub connections_closed_by_server: u64,
    /// The process's resident memory (server and clients) at the end of each measurement, MiB.
    pub rss_mib_without_viewers: Option<f64>,
    pub rss_mib_with_viewers: Option<f64>,
    pub load_average: Option<String>,
}

/// What the bounded connections saw.
#[derive(Default)]
struct HostileCounts {
    upgraded: AtomicU64,
    refused: AtomicU64,
    closed_by_server: AtomicU64,
}

/// The process's resident memory, MiB (Linux).
fn rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Reads until the server closes the connection or `stop` is set; whether the server closed it.
async fn until_closed(tcp: &mut tokio::net::TcpStream, stop: &AtomicBool) -> bool {
    let mut buf = vec![0u8; 16 * 1024];
    while !stop.load(Ordering::Relaxed) {
        match tokio::time::timeout(Duration::from_millis(200), tcp.read(&mut buf)).await {
            Ok(Ok(0)) | Ok(Err(_)) => return true,
            Ok(Ok(_)) | Err(_) => {}
        }
    }
    false
}

/// One bounded connection, again and again: a WebSocket upgrade without the token; when
/// accepted, either idle (odd rounds) until the auth deadline closes it, or a frame header
/// announcing a 1 MiB text message (even rounds), which the server refuses unread.
async fn hostile(addr: SocketAddr, k: usize, stop: Arc<AtomicBool>, counts: Arc<HostileCounts>) {
    let request = format!(
        "GET /ws HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
    );
    let pause = Duration::from_millis(500);
    let mut round = k;
    while !stop.load(Ordering::Relaxed) {
        round += 1;
        let Ok(mut tcp) = tokio::net::TcpStream::connect(addr).await else {
            tokio::time::sleep(pause).await;
            continue;
        };
        if tcp.write_all(request.as_bytes()).await.is_err() {
            tokio::time::sleep(pause).await;
            continue;
        }
        let mut head = Vec::new();
        let mut byte = [0u8; 1];
        while !head.ends_with(b"\r\n\r\n") && head.len() < 8192 {
            match tokio::time::timeout(Duration::from_secs(10), tcp.read(&mut byte)).await {
                Ok(Ok(1)) => head.push(byte[0]),
                _ => break,
            }
        }
        let status = String::from_utf8_lossy(&head)
            .split_whitespace()
            .nth(1)
            .and_then(|s| s.parse::<u16>().ok());
        match status {
            Some(101) => {
                counts.upgraded.fetch_add(1, Ordering::Relaxed);
            }
            Some(503) => {
                counts.refused.fetch_add(1, Ordering::Relaxed);
                tokio::time::sleep(pause).await;
                continue;
            }
            _ => {
                tokio::time::sleep(pause).await;
                continue;
            }
        }
        if round.is_multiple_of(2) {
            // FIN + text, masked, 64-bit length 1 MiB, mask, the first bytes of the payload.
            let mut frame = vec![0x81, 0xFF];
            frame.extend_from_slice(&(1u64 << 20).to_be_bytes());
            frame.extend_from_slice(&[1, 2, 3, 4]);
            frame.extend_from_slice(&[b'x'; 64]);
            let _ = tcp.write_all(&frame).await;
        }
        if until_closed(&mut tcp, &stop).await {
            counts.closed_by_server.fetch_add(1, Ordering::Relaxed);
        }
        tokio::time::sleep(pause).await;
    }
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

/// Runs the bench on a fresh local console (default limits): `viewers` authenticated viewers
/// and `connections` bounded connections during the second measurement.
pub async fn run(
    mission: MissionConfig,
    viewers: usize,
    connections: usize,
    seconds: f64,
) -> Result<BenchReport, ConsoleError> {
    let target_speed = mission.speed;
    let console = start(ConsoleConfig::local(mission)).await?;
    // Warm-up: the first frames, the first map.
    tokio::time::sleep(Duration::from_secs(2)).await;
    let (speed_without_viewers, team_steps_per_s_without_viewers) =
        measure_speed(&console, seconds).await;
    let rss_mib_without_viewers = rss_mib();
    let url = format!("ws://{}/ws?token={}", console.addr, console.token);
    let stop = Arc::new(AtomicBool::new(false));
    let counts = Arc::new(HostileCounts::default());
    let hostile_tasks: Vec<_> = (0..connections)
        .map(|k| tokio::spawn(hostile(console.addr, k, stop.clone(), counts.clone())))
        .collect();
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
    let rss_mib_with_viewers = rss_mib();
    stop.store(true, Ordering::Relaxed);
    let mut stats = Vec::new();
    for t in tasks {
        stats.push(t.await.unwrap_or_default());
    }
    for t in hostile_tasks {
        let _ = t.await;
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
        connections,
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
        min_frames_per_s: rates.iter().copied().reduce(f64::min).unwrap_or(0.0),
        mean_frames_per_s: if rates.is_empty() {
            0.0
        } else {
            rates.iter().sum::<f64>() / n
        },
        max_frames_per_s: rates.iter().copied().fold(0.0, f64::max),
        max_gap_s: stats.iter().map(|s| s.max_gap_s).fold(0.0, f64::max),
        viewers_receiving_every_second: stats
            .iter()
            .filter(|s| {
                !s.seconds_with_frames.is_empty() && s.seconds_with_frames.iter().all(|&b| b)
            })
            .count(),
        viewers_with_frames: stats.iter().filter(|s| s.frames > 0).count(),
        connections_upgraded: counts.upgraded.load(Ordering::Relaxed),
        connections_refused: counts.refused.load(Ordering::Relaxed),
        connections_closed_by_server: counts.closed_by_server.load(Ordering::Relaxed),
        rss_mib_without_viewers,
        rss_mib_with_viewers,
        load_average: std::fs::read_to_string("/proc/loadavg")
            .ok()
            .map(|s| s.trim().to_string()),
    })
}

/// [`run`] on its own runtime (for the `usar console bench` command).
pub fn run_blocking(
    mission: MissionConfig,
    viewers: usize,
    connections: usize,
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
    runtime.block_on(run(mission, viewers, connections, seconds))
}

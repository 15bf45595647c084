//! A small, fast mission and a bare HTTP client for the tests.

use std::time::{Duration, Instant};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use usar_console::{ConsoleConfig, Frame, MissionConfig, RunningConsole, start};

/// The built-in mission with two team robots and a short MAXQ training, faster than real
/// time.
pub fn small_mission() -> MissionConfig {
    let mut config = MissionConfig {
        speed: 4.0,
        ..MissionConfig::default()
    };
    config.mission.team.robots = 2;
    config.mission.rescuer.train_trials = 100;
    config
}

pub async fn start_local(mission: MissionConfig) -> RunningConsole {
    start(ConsoleConfig::local(mission))
        .await
        .expect("the console starts")
}

/// One HTTP/1.1 request; the status code and the body. A `Host` among `headers` replaces the
/// console's address.
pub async fn http(
    console: &RunningConsole,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: &str,
) -> (u16, String) {
    let mut stream = tokio::net::TcpStream::connect(console.addr)
        .await
        .expect("connects");
    let mut request = format!(
        "{method} {path} HTTP/1.1\r\nConnection: close\r\nContent-Length: {}\r\nContent-Type: application/json\r\n",
        body.len()
    );
    if !headers.iter().any(|(k, _)| k.eq_ignore_ascii_case("host")) {
        request.push_str(&format!("Host: {}\r\n", console.addr));
    }
    for (k, v) in headers {
        request.push_str(&format!("{k}: {v}\r\n"));
    }
    request.push_str("\r\n");
    request.push_str(body);
    stream.write_all(request.as_bytes()).await.expect("writes");
    let mut response = Vec::new();
    stream.read_to_end(&mut response).await.expect("reads");
    let text = String::from_utf8_lossy(&response).to_string();
    let status = text
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let body = text
        .split_once("\r\n\r\n")
        .map(|(_, b)| b.to_string())
        .unwrap_or_default();
    (status, body)
}

/// The latest frame (`GET /api/state`), waiting up to 60 s for the first one.
pub async fn frame(console: &RunningConsole) -> Frame {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let (status, body) = http(console, "GET", "/api/state", &[], "").await;
        if status == 200
            && let Ok(f) = serde_json::from_str::<Frame>(&body)
        {
            return f;
        }
        assert!(Instant::now() < deadline, "no frame within 60 s");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

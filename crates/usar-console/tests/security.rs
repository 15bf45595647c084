//! Control needs the token: without it every control message is refused (HTTP 401 or an
//! error reply) and the mission's state does not change; with it the same message works.

use crate::common::{frame, http, small_mission, start_local};
use futures_util::{SinkExt, StreamExt};
use std::time::Duration;
use tokio_tungstenite::tungstenite::Message;
use usar_console::{ConsoleConfig, ConsoleError, start};

const CONTROLS: [&str; 5] = [
    r#"{"type":"pause"}"#,
    r#"{"type":"speed","factor":0.5}"#,
    r#"{"type":"weights","w_l":20,"w_p":1,"w_q":1}"#,
    r#"{"type":"hypothesis","name":"small"}"#,
    r#"{"type":"teleop","robot":1,"linear":1,"angular":0}"#,
];

/// Reads replies until one that is not a frame or a map.
async fn reply<S>(ws: &mut S) -> serde_json::Value
where
    S: StreamExt<Item = Result<Message, tokio_tungstenite::tungstenite::Error>> + Unpin,
{
    loop {
        let m = tokio::time::timeout(Duration::from_secs(10), ws.next())
            .await
            .expect("a reply within 10 s")
            .expect("open")
            .expect("no error");
        if let Message::Text(t) = m {
            let v: serde_json::Value = serde_json::from_str(t.as_str()).expect("JSON");
            if v["type"] != "frame" && v["type"] != "map" {
                return v;
            }
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn control_without_the_token_is_refused_and_changes_nothing() {
    let console = start_local(small_mission()).await;
    let before = frame(&console).await;
    let bearer_wrong = format!("Bearer {}x", console.token);
    for body in CONTROLS {
        let (status, text) = http(&console, "POST", "/api/control", &[], body).await;
        assert_eq!(status, 401, "{body}: {text}");
        let (status, _) = http(
            &console,
            "POST",
            "/api/control",
            &[("Authorization", &bearer_wrong)],
            body,
        )
        .await;
        assert_eq!(status, 401, "{body} with a wrong token");
    }
    // Over the WebSocket: a viewer without the token, then a wrong `auth`.
    let url = format!("ws://{}/ws", console.addr);
    let (mut ws, _) = tokio_tungstenite::connect_async(url.as_str())
        .await
        .expect("connects");
    for body in CONTROLS {
        ws.send(Message::Text(body.into())).await.expect("sends");
        let r = reply(&mut ws).await;
        assert_eq!(r["type"], "error", "{body}: {r}");
        assert!(r["message"].as_str().unwrap_or("").contains("unauthorized"));
    }
    ws.send(Message::Text(r#"{"type":"auth","token":"guess"}"#.into()))
        .await
        .expect("sends");
    assert_eq!(reply(&mut ws).await["type"], "error");
    ws.send(Message::Text(CONTROLS[0].into()))
        .await
        .expect("sends");
    assert_eq!(reply(&mut ws).await["type"], "error");

    tokio::time::sleep(Duration::from_millis(500)).await;
    let after = frame(&console).await;
    assert!(!after.paused);
    assert_eq!(after.speed, before.speed);
    assert_eq!(after.weights, before.weights);
    assert_eq!(after.hypothesis, before.hypothesis);
    assert!(after.time_s > before.time_s, "the mission went on");
    assert!(
        after
            .robots
            .iter()
            .all(|r| r.mode == "autonomous" || r.id == 0),
        "no team robot was teleoperated: {:?}",
        after.robots
    );

    // The same messages with the token work (so the refusals above were the token's doing).
    let bearer = format!("Bearer {}", console.token);
    for body in CONTROLS {
        let (status, text) = http(
            &console,
            "POST",
            "/api/control",
            &[("Authorization", &bearer)],
            body,
        )
        .await;
        assert_eq!(status, 200, "{body}: {text}");
    }
    tokio::time::sleep(Duration::from_millis(300)).await;
    let controlled = frame(&console).await;
    assert!(controlled.paused);
    assert_eq!(controlled.speed, 0.5);
    assert_eq!(controlled.weights, [20.0, 1.0, 1.0]);
    assert_eq!(controlled.hypothesis, "small");
    console.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_non_loopback_address_needs_an_explicit_token() {
    let mut config = ConsoleConfig::local(small_mission());
    config.bind = "0.0.0.0:0".parse().expect("address");
    match start(config).await {
        Err(ConsoleError::OpenBindWithoutToken(_)) => {}
        Err(e) => panic!("wrong error: {e}"),
        Ok(_) => panic!("served on 0.0.0.0 without a token"),
    }
}

/// A WebSocket with one extra request header; the HTTP status of a refused upgrade, or the
/// socket.
async fn ws_with(
    url: &str,
    header: (&'static str, &str),
) -> Result<
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>,
    u16,
> {
    use tokio_tungstenite::tungstenite::client::IntoClientRequest;
    let mut request = url.into_client_request().expect("a request");
    request
        .headers_mut()
        .insert(header.0, header.1.parse().expect("a header value"));
    match tokio_tungstenite::connect_async(request).await {
        Ok((ws, _)) => Ok(ws),
        Err(tokio_tungstenite::tungstenite::Error::Http(response)) => {
            Err(response.status().as_u16())
        }
        Err(e) => panic!("{url}: {e}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn foreign_origins_and_hosts_get_403_and_allowed_ones_pass() {
    let mut config = ConsoleConfig::local(small_mission());
    config.allow_origins = vec!["https://Console.Example.org".into()];
    let console = start(config).await.expect("the console starts");
    let port = console.addr.port();
    let url = format!("ws://{}/ws?token={}", console.addr, console.token);

    // Another site's page opening the WebSocket (with the right token, even).
    assert_eq!(
        ws_with(&url, ("Origin", "http://evil.example")).await.err(),
        Some(403)
    );
    assert_eq!(ws_with(&url, ("Origin", "null")).await.err(), Some(403));
    // DNS rebinding: the attacker's name in Host, on every route.
    for path in ["/", "/app.js", "/api/state", "/api/map", "/ws"] {
        for host in ["attacker.example", &format!("attacker.example:{port}")] {
            let (status, body) = http(&console, "GET", path, &[("Host", host)], "").await;
            assert_eq!(status, 403, "{path} with Host {host}: {body}");
        }
    }
    let bearer = format!("Bearer {}", console.token);
    let (status, _) = http(
        &console,
        "POST",
        "/api/control",
        &[
            ("Authorization", &bearer),
            ("Origin", "http://evil.example"),
        ],
        r#"{"type":"pause"}"#,
    )
    .await;
    assert_eq!(status, 403, "a foreign page posting control");

    // The console's own names, its own page's origin, and the allowed origin pass.
    for host in [
        format!("127.0.0.1:{port}"),
        format!("localhost:{port}"),
        format!("[::1]:{port}"),
        "console.example.org".to_string(),
    ] {
        let (status, _) = http(&console, "GET", "/api/state", &[("Host", &host)], "").await;
        assert_eq!(status, 200, "Host {host}");
    }
    for origin in [
        format!("http://127.0.0.1:{port}"),
        format!("http://localhost:{port}"),
        "https://console.example.org".to_string(),
    ] {
        let mut ws = ws_with(&url, ("Origin", &origin))
            .await
            .unwrap_or_else(|status| panic!("Origin {origin}: {status}"));
        ws.send(Message::Text(r#"{"type":"resume"}"#.into()))
            .await
            .expect("sends");
        assert_eq!(reply(&mut ws).await["type"], "ok", "Origin {origin}");
    }
    // Without Origin (curl, scripts): fine on an allowed Host.
    let (status, _) = http(&console, "GET", "/api/map", &[], "").await;
    assert_eq!(status, 200);
    console.stop().await;
}

#[test]
fn a_public_address_needs_a_strong_token() {
    let mut config = ConsoleConfig::local(small_mission());
    config.bind = "0.0.0.0:8080".parse().expect("address");
    for weak in [
        "a",
        "correct horse",
        "abababababababababababababab",
        "0123456789abcdefghijklm",
    ] {
        config.token = Some(weak.into());
        match config.validate() {
            Err(e @ ConsoleError::WeakToken(_)) | Err(e @ ConsoleError::Token(_)) => {
                if let ConsoleError::WeakToken(_) = e {
                    let text = e.to_string();
                    assert!(
                        text.contains("24 characters") && text.contains("10 different"),
                        "the rule is said: {text}"
                    );
                }
            }
            other => panic!("{weak:?} on 0.0.0.0: {other:?}"),
        }
    }
    config.token = Some("3f9a1c07d2b84e6f9a0c5d1e7b2f4a68".into());
    assert!(config.validate().is_ok());
    // On loopback any non-empty token will do (only this machine can reach it).
    config.bind = "127.0.0.1:8080".parse().expect("address");
    config.token = Some("a".into());
    assert!(config.validate().is_ok());
    config.token = Some(String::new());
    assert!(matches!(config.validate(), Err(ConsoleError::Token(_))));
    config.token = None;
    config.allow_origins = vec!["https://console.example.org/".into()];
    assert!(matches!(
        config.validate(),
        Err(ConsoleError::AllowOrigin { .. })
    ));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_weak_token_on_a_public_address_does_not_start() {
    let mut config = ConsoleConfig::local(small_mission());
    config.bind = "0.0.0.0:0".parse().expect("address");
    config.token = Some("a".into());
    assert!(matches!(
        start(config).await.err(),
        Some(ConsoleError::WeakToken(_))
    ));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_token_can_come_from_a_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("token");
    std::fs::write(&path, "3f9a1c07d2b84e6f9a0c5d1e7b2f4a68\n").expect("writes");
    let token = usar_console::read_token_file(&path).expect("reads the token");
    assert_eq!(token, "3f9a1c07d2b84e6f9a0c5d1e7b2f4a68");
    let mut config = ConsoleConfig::local(small_mission());
    config.token = Some(token.clone());
    let console = start(config).await.expect("the console starts");
    assert_eq!(console.token, token);
    let bearer = format!("Bearer {token}");
    let (status, body) = http(
        &console,
        "POST",
        "/api/control",
        &[("Authorization", &bearer)],
        r#"{"type":"resume"}"#,
    )
    .await;
    assert_eq!(status, 200, "{body}");
    console.stop().await;
    // An empty file, two lines, a missing file: refused, naming the file.
    for text in ["", "\n", "one\ntwo\n"] {
        std::fs::write(&path, text).expect("writes");
        let e = usar_console::read_token_file(&path).expect_err("refused");
        assert!(e.to_string().contains("--token-file"), "{e}");
    }
    let missing = dir.path().join("missing");
    assert!(usar_console::read_token_file(&missing).is_err());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn failed_token_attempts_are_limited_per_connection_and_per_address() {
    let mut config = ConsoleConfig::local(small_mission());
    config.limits.auth_failures_per_connection = 2;
    config.limits.auth_failures_per_peer = 4;
    config.limits.auth_window = Duration::from_secs(3600);
    let console = start(config).await.expect("the console starts");
    let url = format!("ws://{}/ws", console.addr);
    let wrong = Message::Text(r#"{"type":"auth","token":"guess"}"#.into());

    // One connection: its second wrong token closes it (1008).
    let (mut ws, _) = tokio_tungstenite::connect_async(url.as_str())
        .await
        .expect("connects");
    ws.send(wrong.clone()).await.expect("sends");
    assert_eq!(reply(&mut ws).await["type"], "error");
    ws.send(wrong.clone()).await.expect("sends");
    assert_eq!(reply(&mut ws).await["type"], "error");
    assert_eq!(closed_with(&mut ws).await, Some(1008));

    // Two more from the same address (another connection): the address has used up its four.
    let (mut ws, _) = tokio_tungstenite::connect_async(url.as_str())
        .await
        .expect("connects");
    ws.send(wrong.clone()).await.expect("sends");
    assert_eq!(reply(&mut ws).await["type"], "error");
    let bearer_wrong = format!("Bearer {}x", console.token);
    let (status, _) = http(
        &console,
        "POST",
        "/api/control",
        &[("Authorization", &bearer_wrong)],
        r#"{"type":"pause"}"#,
    )
    .await;
    assert_eq!(status, 401);

    // Now even the right token is refused from this address, over both ways in.
    let right = format!(r#"{{"type":"auth","token":"{}"}}"#, console.token);
    ws.send(Message::Text(right.into())).await.expect("sends");
    let r = reply(&mut ws).await;
    assert_eq!(r["type"], "error", "{r}");
    assert!(
        r["message"]
            .as_str()
            .unwrap_or("")
            .contains("too many failed token attempts"),
        "{r}"
    );
    let bearer = format!("Bearer {}", console.token);
    let (status, body) = http(
        &console,
        "POST",
        "/api/control",
        &[("Authorization", &bearer)],
        r#"{"type":"pause"}"#,
    )
    .await;
    assert_eq!(status, 429, "{body}");
    let with_token = format!("{url}?token={}", console.token);
    assert_eq!(ws_with(&with_token, ("X-Test", "1")).await.err(), Some(429));
    assert!(!frame(&console).await.paused, "nothing was controlled");
    console.stop().await;
}

/// Reads until the server closes the socket; the close code if it sent one.
pub async fn closed_with<S>(ws: &mut S) -> Option<u16>
where
    S: StreamExt<Item = Result<Message, tokio_tungstenite::tungstenite::Error>> + Unpin,
{
    loop {
        let m = tokio::time::timeout(Duration::from_secs(30), ws.next())
            .await
            .expect("closed within 30 s");
        match m {
            Some(Ok(Message::Close(frame))) => return frame.map(|f| u16::from(f.code)),
            Some(Ok(_)) => {}
            Some(Err(_)) | None => return None,
        }
    }
}

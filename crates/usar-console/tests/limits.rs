//! What one console lets its clients take: messages over the size cap close the socket before
//! their payload is read, connections beyond the cap get 503, a WebSocket without the token is
//! closed after the auth deadline, and a mission file with absurd numbers is refused before
//! anything starts.

use crate::common::{http, small_mission};
use crate::security::closed_with;
use futures_util::{SinkExt, StreamExt};
use std::time::{Duration, Instant};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_tungstenite::tungstenite::Message;
use usar_console::{ConsoleConfig, ConsoleError, MissionConfig, start};

/// A raw WebSocket handshake on `path`; the stream after the `101` head.
async fn raw_websocket(addr: std::net::SocketAddr, path: &str) -> tokio::net::TcpStream {
    let mut tcp = tokio::net::TcpStream::connect(addr)
        .await
        .expect("connects");
    let request = format!(
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
    );
    tcp.write_all(request.as_bytes()).await.expect("writes");
    let mut head = Vec::new();
    let mut byte = [0u8; 1];
    while !head.ends_with(b"\r\n\r\n") {
        tcp.read_exact(&mut byte).await.expect("the answer's head");
        head.push(byte[0]);
    }
    let head = String::from_utf8_lossy(&head);
    assert!(head.starts_with("HTTP/1.1 101"), "{head}");
    tcp
}

/// The opcodes of the server's frames up to the end of the stream, and the close code.
fn server_frames(bytes: &[u8]) -> (Vec<u8>, Option<u16>) {
    let (mut opcodes, mut code, mut at) = (Vec::new(), None, 0usize);
    while at + 2 <= bytes.len() {
        let opcode = bytes[at] & 0x0F;
        let (len, header) = match bytes[at + 1] & 0x7F {
            126 if at + 4 <= bytes.len() => (
                u16::from_be_bytes([bytes[at + 2], bytes[at + 3]]) as usize,
                4,
            ),
            127 if at + 10 <= bytes.len() => {
                let mut b = [0u8; 8];
                b.copy_from_slice(&bytes[at + 2..at + 10]);
                (u64::from_be_bytes(b) as usize, 10)
            }
            126 | 127 => break,
            n => (n as usize, 2),
        };
        let payload = at + header;
        if payload + len > bytes.len() {
            break;
        }
        if opcode == 8 && len >= 2 {
            code = Some(u16::from_be_bytes([bytes[payload], bytes[payload + 1]]));
        }
        opcodes.push(opcode);
        at = payload + len;
    }
    (opcodes, code)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_oversized_message_closes_the_socket_before_its_payload_arrives() {
    let console = start(ConsoleConfig::local(small_mission()))
        .await
        .expect("the console starts");
    // A frame header announcing 16 MiB and only 64 bytes of it: the server closes at the
    // header (1009) instead of waiting for, and buffering, the rest.
    let mut tcp = raw_websocket(console.addr, &format!("/ws?token={}", console.token)).await;
    let mut frame = vec![0x81, 0xFF];
    frame.extend_from_slice(&(16u64 << 20).to_be_bytes());
    frame.extend_from_slice(&[7, 7, 7, 7]);
    frame.extend_from_slice(&[b'x'; 64]);
    tcp.write_all(&frame).await.expect("writes");
    let mut received = Vec::new();
    let mut buf = vec![0u8; 64 * 1024];
    loop {
        match tokio::time::timeout(Duration::from_secs(30), tcp.read(&mut buf))
            .await
            .expect("the server closes the connection without the payload")
        {
            Ok(0) | Err(_) => break,
            Ok(n) => received.extend_from_slice(&buf[..n]),
        }
    }
    let (opcodes, code) = server_frames(&received);
    assert_eq!(
        opcodes.last(),
        Some(&8),
        "ends with a close frame: {opcodes:?}"
    );
    assert_eq!(code, Some(1009), "message too big");

    // Through a WebSocket client: one byte over the cap closes the socket with 1009.
    let url = format!("ws://{}/ws?token={}", console.addr, console.token);
    let (mut ws, _) = tokio_tungstenite::connect_async(url.as_str())
        .await
        .expect("connects");
    let over = format!(r#"{{"type":"pause","x":"{}"}}"#, "x".repeat(4097));
    ws.send(Message::Text(over.into())).await.expect("sends");
    assert_eq!(closed_with(&mut ws).await, Some(1009));
    // Over HTTP: 413.
    let bearer = format!("Bearer {}", console.token);
    let body = format!(r#"{{"type":"pause","x":"{}"}}"#, "x".repeat(5000));
    let (status, _) = http(
        &console,
        "POST",
        "/api/control",
        &[("Authorization", &bearer)],
        &body,
    )
    .await;
    assert_eq!(status, 413);
    // The console goes on.
    let (status, _) = http(&console, "GET", "/api/state", &[], "").await;
    assert_eq!(status, 200);
    console.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_connection_cap_refuses_one_more_with_503() {
    let mut config = ConsoleConfig::local(small_mission());
    config.limits.max_connections = 3;
    let console = start(config).await.expect("the console starts");
    let url = format!("ws://{}/ws?token={}", console.addr, console.token);
    let mut held = Vec::new();
    for _ in 0..3 {
        let (ws, _) = tokio_tungstenite::connect_async(url.as_str())
            .await
            .expect("connects within the cap");
        held.push(ws);
    }
    let (status, body) = http(&console, "GET", "/api/state", &[], "").await;
    assert_eq!(status, 503, "{body}");
    match tokio_tungstenite::connect_async(url.as_str()).await {
        Err(tokio_tungstenite::tungstenite::Error::Http(r)) => assert_eq!(r.status(), 503),
        Err(e) => panic!("expected 503, got {e}"),
        Ok(_) => panic!("a fourth WebSocket was accepted"),
    }
    // A slot is free again once a connection has closed.
    let mut ws = held.pop().expect("a socket");
    ws.close(None).await.expect("closes");
    drop(ws);
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let (status, _) = http(&console, "GET", "/api/state", &[], "").await;
        if status == 200 {
            break;
        }
        assert_eq!(status, 503);
        assert!(Instant::now() < deadline, "the slot was never freed");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    console.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_websocket_without_the_token_is_closed_after_the_deadline() {
    let mut config = ConsoleConfig::local(small_mission());
    config.limits.auth_deadline = Duration::from_millis(300);
    let console = start(config).await.expect("the console starts");
    let bare = format!("ws://{}/ws", console.addr);
    let (mut anonymous, _) = tokio_tungstenite::connect_async(bare.as_str())
        .await
        .expect("connects");
    let with_token = format!("{bare}?token={}", console.token);
    let (mut member, _) = tokio_tungstenite::connect_async(with_token.as_str())
        .await
        .expect("connects");

    // The anonymous socket is closed with 1008, having received no frame or map.
    let mut seen = Vec::new();
    let code = loop {
        let m = tokio::time::timeout(Duration::from_secs(30), anonymous.next())
            .await
            .expect("closed within 30 s");
        match m {
            Some(Ok(Message::Close(frame))) => break frame.map(|f| u16::from(f.code)),
            Some(Ok(Message::Text(t))) => seen.push(t.to_string()),
            Some(Ok(_)) => {}
            Some(Err(_)) | None => break None,
        }
    };
    assert_eq!(code, Some(1008));
    assert!(seen.is_empty(), "sent before the token: {seen:?}");

    // The one with the token is still open and answered (after the other one's deadline).
    {
        let ws = &mut member;
        ws.send(Message::Text(r#"{"type":"resume"}"#.into()))
            .await
            .expect("sends");
        let deadline = Instant::now() + Duration::from_secs(30);
        loop {
            let m = tokio::time::timeout(Duration::from_secs(30), ws.next())
                .await
                .expect("a reply")
                .expect("open")
                .expect("no error");
            if let Message::Text(t) = m {
                let v: serde_json::Value = serde_json::from_str(t.as_str()).expect("JSON");
                if v["type"] == "ok" {
                    break;
                }
                assert_ne!(v["type"], "error", "{v}");
            }
            assert!(Instant::now() < deadline, "no reply");
        }
    }
    console.stop().await;
}

#[test]
fn absurd_numbers_in_a_mission_file_are_refused_naming_the_file_and_field() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("mission.toml");
    for (text, field) in [
        (
            "[rescuer]\ntrain_trials = 4000000000\n",
            "rescuer.train_trials",
        ),
        ("[rescuer]\ntrain_trials = 0\n", "rescuer.train_trials"),
        ("[rescuer]\nzone_cells = 4000000000\n", "rescuer.zone_cells"),
        ("[rescuer]\nweights = \"heavy\"\n", "rescuer.weights"),
        ("[team]\nrobots = 100000\n", "team.robots"),
        ("[team]\nrobots = 0\n", "team.robots"),
        ("[team]\nstrategy = \"psychic\"\n", "strategy"),
        ("minutes = 1e12\n", "minutes"),
        ("[crawler]\nshare_period_s = -1\n", "crawler.share_period_s"),
        ("warp = 9\n", "warp"),
    ] {
        std::fs::write(&path, text).expect("writes");
        let e = MissionConfig::from_file(&path).expect_err(text);
        let message = e.to_string();
        assert!(
            matches!(e, ConsoleError::MissionFile { .. }),
            "{text}: {message}"
        );
        assert!(
            message.contains("mission.toml"),
            "names the file: {message}"
        );
        assert!(message.contains(field), "names {field}: {message}");
    }
    std::fs::write(&path, "[rescuer]\ntrain_trials = 4000000000\n").expect("writes");
    assert!(
        MissionConfig::from_file(&path)
            .expect_err("refused")
            .to_string()
            .contains("1000000"),
        "says the limit"
    );
    std::fs::write(
        &path,
        "[rescuer]\ntrain_trials = 1000000\n[team]\nrobots = 32\n",
    )
    .expect("writes");
    assert!(MissionConfig::from_file(&path).is_ok());
}

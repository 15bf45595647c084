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

//! 10 000 malformed messages over one WebSocket: every one gets an error reply, the
//! connection stays usable and the mission keeps running.

use crate::common::{frame, small_mission, start_local};
use futures_util::{SinkExt, StreamExt};
use std::time::Duration;
use tokio_tungstenite::tungstenite::Message;

/// The k-th malformed message: broken JSON, unknown types and fields, wrong types, numbers
/// out of range, binary frames.
fn malformed(k: usize) -> Message {
    let text = match k % 10 {
        0 => format!("{{\"type\":\"pause\"{k}"),
        1 => format!("{{\"type\":\"warp_{k}\"}}"),
        2 => format!("{{\"type\":\"speed\",\"factor\":{}}}", -(k as f64)),
        3 => format!("{{\"type\":\"drive\",\"robot\":{k},\"command\":\"fly\"}}"),
        4 => format!("{{\"type\":\"weights\",\"w_l\":\"{k}\",\"w_p\":1,\"w_q\":1}}"),
        5 => format!("{{\"type\":\"pause\",\"unexpected\":{k}}}"),
        6 => format!("[{k}, \"pause\"]"),
        7 => "\u{0}\u{1}garbage".repeat(k % 7 + 1),
        8 => format!("{{\"type\":\"send_to\",\"robot\":1,\"x\":1e999,\"y\":{k}}}"),
        _ => return Message::Binary(vec![0xFF, (k % 256) as u8].into()),
    };
    Message::Text(text.into())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn ten_thousand_malformed_messages_each_get_an_error_and_nothing_breaks() {
    const N: usize = 10_000;
    let console = start_local(small_mission()).await;
    let before = frame(&console).await;
    let url = format!("ws://{}/ws?token={}", console.addr, console.token);
    let (ws, _) = tokio_tungstenite::connect_async(url.as_str())
        .await
        .expect("connects");
    let (mut sink, mut stream) = ws.split();
    let sender = tokio::spawn(async move {
        for k in 0..N {
            sink.send(malformed(k)).await.expect("sends");
        }
        sink
    });
    let mut errors = 0usize;
    let mut other = 0usize;
    while errors + other < N {
        let m = tokio::time::timeout(Duration::from_secs(30), stream.next())
            .await
            .expect("replies keep coming")
            .expect("open")
            .expect("no error");
        if let Message::Text(t) = m {
            let v: serde_json::Value = serde_json::from_str(t.as_str()).expect("JSON");
            match v["type"].as_str() {
                Some("frame") | Some("map") => {}
                Some("error") => errors += 1,
                _ => other += 1,
            }
        }
    }
    assert_eq!(errors, N, "{other} replies were not errors");
    // The connection still works, and so does the mission.
    let mut sink = sender.await.expect("sender");
    sink.send(Message::Text(r#"{"type":"speed","factor":2}"#.into()))
        .await
        .expect("sends");
    loop {
        let m = tokio::time::timeout(Duration::from_secs(10), stream.next())
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
    }
    // The next frame shows the new speed.
    let mut after = frame(&console).await;
    for _ in 0..50 {
        if after.speed == 2.0 {
            break;
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
        after = frame(&console).await;
    }
    assert!(after.time_s > before.time_s);
    assert_eq!(after.speed, 2.0);
    console.stop().await;
}

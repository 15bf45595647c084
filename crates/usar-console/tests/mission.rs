//! What the live mission shows without a browser: every robot of the default mission, the BTM
//! crawler among them, moving on one clock.

use crate::common::{frame, small_mission, start_local};
use std::time::{Duration, Instant};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_btm_crawler_is_shown_driving_while_it_builds_the_map() {
    let console = start_local(small_mission()).await;
    let crawler = |f: &usar_console::Frame| f.robots.iter().find(|r| r.kind == "btm").cloned();
    let deadline = Instant::now() + Duration::from_secs(90);
    let first = loop {
        let f = frame(&console).await;
        if let Some(r) = crawler(&f) {
            break r;
        }
        assert!(
            Instant::now() < deadline,
            "no BTM crawler in {:?}",
            f.robots
        );
        tokio::time::sleep(Duration::from_millis(200)).await;
    };
    assert_eq!(first.name, "BTM crawler");
    assert_eq!(first.mode, "autonomous");
    let f = loop {
        let f = frame(&console).await;
        let now = crawler(&f).expect("the crawler stays on the list");
        if (now.x - first.x).hypot(now.y - first.y) > 0.5 && f.btm_nodes > 0 {
            break f;
        }
        assert!(
            Instant::now() < deadline,
            "the crawler did not drive and add nodes: {now:?}, {} nodes",
            f.btm_nodes
        );
        tokio::time::sleep(Duration::from_millis(200)).await;
    };
    // The team's ids come first, then the crawler's.
    let ids: Vec<usize> = f.robots.iter().map(|r| r.id).collect();
    assert_eq!(ids, (0..ids.len()).collect::<Vec<_>>());
    assert!(crawler(&f).expect("crawler").task.contains("nodes"));
    console.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_recorded_console_leaves_one_complete_mcap_when_it_stops() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("console.mcap");
    let mut mission = small_mission();
    mission.mission.crawler.enabled = false;
    mission.record = Some(path.clone());
    let console = start_local(mission).await;
    // Some simulated seconds go by, then the console is stopped.
    let deadline = Instant::now() + Duration::from_secs(60);
    while frame(&console).await.time_s < 3.0 {
        assert!(Instant::now() < deadline, "the mission did not move");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
    assert!(!path.exists(), "the recording is named only once complete");
    console.stop().await;
    let bytes = std::fs::read(&path).expect("the recording");
    assert!(bytes.starts_with(b"\x89MCAP0\r\n") && bytes.ends_with(b"\x89MCAP0\r\n"));
    assert!(!dir.path().join("console.mcap.partial").exists());
}

//! A short run of `usar console bench`: what it measures is a benchmark figure (the simulation's
//! speed with and without clients, see the README), not asserted here, since the machine is
//! shared. The test states behaviour: every viewer receives frames, the bounded connections
//! are accepted and closed by the server, and the report carries its fields.

use crate::common::small_mission;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_viewer_receives_frames_beside_bounded_connections() {
    let mut mission = small_mission();
    mission.speed = 2.0;
    mission.mission.crawler.enabled = false;
    let report = usar_console::bench::run(mission, 20, 10, 3.0)
        .await
        .expect("the bench runs");
    assert_eq!((report.viewers, report.connections), (20, 10));
    assert_eq!(report.target_speed, 2.0);
    assert_eq!(report.viewers_with_frames, 20, "{report:?}");
    assert!(report.min_frames_per_s > 0.0, "{report:?}");
    // (Up to rounding: the mean of equal rates may differ from them in the last bit.)
    let slack = 1e-9 * report.max_frames_per_s;
    assert!(report.min_frames_per_s <= report.mean_frames_per_s + slack);
    assert!(report.mean_frames_per_s <= report.max_frames_per_s + slack);
    assert!(report.viewers_receiving_every_second <= report.viewers);
    assert!(report.speed_without_viewers > 0.0 && report.speed_with_viewers > 0.0);
    assert!(report.speed_change.is_finite());
    assert!(report.connections_upgraded >= 1, "{report:?}");
    assert!(report.connections_closed_by_server >= 1, "{report:?}");
    assert_eq!(
        report.connections_refused, 0,
        "30 connections are within the cap"
    );
    let json = serde_json::to_value(&report).expect("serialises");
    for field in [
        "speed_without_viewers",
        "speed_with_viewers",
        "speed_change",
        "connections_refused",
    ] {
        assert!(json.get(field).is_some(), "{field} in {json}");
    }
}

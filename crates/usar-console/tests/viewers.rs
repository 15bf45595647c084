//! A short version of `usar console bench`: 50 viewers for a few seconds. The simulation keeps
//! its speed within 10 % of its speed without viewers, and every viewer gets frames every
//! second at 10 or more per second.

use crate::common::small_mission;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn fifty_viewers_neither_slow_the_simulation_nor_starve() {
    let mut mission = small_mission();
    mission.speed = 2.0;
    mission.btm = false;
    let report = usar_console::bench::run(mission, 50, 4.0)
        .await
        .expect("the bench runs");
    assert!(
        report.speed_change.abs() <= 0.10,
        "speed changed by {:.1} %: {report:?}",
        100.0 * report.speed_change
    );
    assert_eq!(report.viewers_receiving_every_second, 50, "{report:?}");
    assert!(report.min_frames_per_s >= 10.0, "{report:?}");
}

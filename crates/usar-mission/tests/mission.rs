//! The whole mission: one host, one physics, the crawler's map shared over the radio.

use std::sync::Arc;
use usar_mission::{MissionConfig, run_mission};
use usar_world::generate::{SceneKind, generate};

#[test]
fn a_mission_is_a_pure_function_of_scene_configuration_and_seed() {
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let config = MissionConfig {
        minutes: 1.0,
        ..MissionConfig::default()
    };
    let a = run_mission(scene.clone(), &config, 3, None, |_| {}).unwrap();
    let b = run_mission(scene, &config, 3, None, |_| {}).unwrap();
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
    // The crawler's map reached the base station.
    let crawler = a.crawler.as_ref().unwrap();
    assert!(crawler.maps_sent >= 1 && a.team.btm_maps_received >= 1);
    assert!(a.radio.delivered >= u64::from(crawler.maps_sent));
}

#[test]
fn the_slopes_and_stairs_the_crawler_records_are_closed_to_the_wheeled_robots() {
    // The course has a slope and stairs no wheeled robot climbs (15° and 0.05 m at most).
    let scene = Arc::new(generate(SceneKind::Course, 1));
    let config: MissionConfig = toml::from_str(
        r#"
        scene = "course"
        minutes = 15
        [team]
        robots = 2
        robot = "wheeled"
        strategy = "nearest"
        [rescuer]
        enabled = false
        "#,
    )
    .unwrap();
    let out = run_mission(scene, &config, 1, None, |_| {}).unwrap();
    let crawler = out.crawler.as_ref().unwrap();
    let obstacles: usize = crawler
        .nodes_by_type
        .iter()
        .filter(|(k, _)| k.starts_with("obstacle"))
        .map(|(_, n)| n)
        .sum();
    assert!(obstacles >= 2, "{:?}", crawler.nodes_by_type);
    assert!(out.team.keep_out_zones >= 1, "{:?}", out.team);
    // Every obstacle node the crawler recorded lies in a keep-out zone, and every zone lies
    // on the BTM's obstacle links or nodes.
    let btm = out.btm.as_ref().unwrap();
    let in_zone = |p| usar_team::base_station::kept_out(&out.keep_outs, p);
    let obstacle_nodes: Vec<usar_world::Point2> = btm
        .nodes
        .iter()
        .filter(|n| n.kind == "obstacle")
        .map(|n| usar_world::Point2::new(n.x_m, n.y_m))
        .collect();
    for &p in &obstacle_nodes {
        assert!(
            in_zone(p),
            "obstacle node at {p:?} is open to the wheeled robots"
        );
    }
    for &(a, b, _) in &out.keep_outs {
        let near = |q: usar_world::Point2| obstacle_nodes.iter().any(|&p| p.distance(q) < 8.0);
        assert!(near(a) || near(b), "{a:?} {b:?}");
    }
}

#[test]
fn a_mission_without_a_crawler_has_no_btm() {
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let config: MissionConfig =
        toml::from_str("minutes = 0.5\n[crawler]\nenabled = false\n").unwrap();
    let out = run_mission(scene, &config, 1, None, |_| {}).unwrap();
    assert!(out.crawler.is_none() && out.btm.is_none());
    assert_eq!((out.team.robots, out.radio.sent), (4, 0));
}

#[test]
fn a_bad_mission_file_names_the_field() {
    let err = toml::from_str::<MissionConfig>("minutes = 5\n[team]\nrobotz = 3\n").unwrap_err();
    assert!(err.to_string().contains("robotz"), "{err}");
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let config = MissionConfig {
        minutes: -1.0,
        ..MissionConfig::default()
    };
    let err = run_mission(scene, &config, 1, None, |_| {}).unwrap_err();
    assert_eq!(
        err.to_string(),
        "mission field minutes: found -1, expected (0, 1440]"
    );
}

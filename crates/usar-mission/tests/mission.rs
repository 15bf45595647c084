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

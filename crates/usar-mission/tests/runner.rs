//! The `mission` campaign runner: a configuration is the built-in mission with the factors'
//! values, and every metric it names comes out.

use usar_campaign::{Design, Runner};
use usar_mission::runner::MissionRunner;

#[test]
fn a_campaign_run_of_the_mission_reports_every_metric() {
    let runner = MissionRunner::new();
    let design = Design::parse(
        r#"
        name = "m"
        runner = "mission"
        runs = 1
        [factors]
        rescuer = [1, 0]
        [fixed]
        minutes = 0.5
        train_trials = 10
        "#,
        "m.toml",
        &runner,
    )
    .unwrap();
    assert_eq!(design.configs.len(), 2);
    let with = runner.run(&design.configs[0], 3).unwrap();
    for m in runner.metrics() {
        assert!(with.metrics.contains_key(&m.name), "{}", m.name);
    }
    assert!(with.metrics["btm_nodes"] > 0.0);
    assert!(!with.series.is_empty());
    let without = runner.run(&design.configs[1], 3).unwrap();
    assert_eq!(without.metrics["rescuer_cells"], 0.0);
    // The same configuration and seed: the same figures.
    assert_eq!(
        runner.run(&design.configs[0], 3).unwrap().metrics,
        with.metrics
    );
}

#[test]
fn a_scene_that_does_not_exist_is_the_configurations_fault() {
    let runner = MissionRunner::new();
    let err = Design::parse(
        "name = \"m\"\nrunner = \"mission\"\nruns = 1\n[fixed]\nscene = \"/no/such/floor.json\"\n",
        "m.toml",
        &runner,
    )
    .unwrap_err();
    assert!(err.is_input(), "{err}");
    assert!(err.to_string().contains("floor.json"), "{err}");
}

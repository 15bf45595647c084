//! Paper 000's robot in the mission: it searches a rubble zone of the floor, and every
//! hand-off — its own and the base station's questions about the team's victim reports — goes
//! to one operator who answers one question at a time.

use std::sync::Arc;
use usar_mission::{MissionConfig, MissionOutcome, run_mission};
use usar_world::generate::{SceneKind, generate};

fn built_in(minutes: f64) -> (usize, MissionOutcome) {
    let scene = generate(SceneKind::Office, 1);
    let floor_victims = scene.victims.len();
    let config = MissionConfig {
        minutes,
        ..MissionConfig::default()
    };
    let out = run_mission(Arc::new(scene), &config, 1, None, |_| {}).unwrap();
    (floor_victims, out)
}

#[test]
fn the_rescuer_searches_its_rubble_zone_and_one_operator_answers_everyone() {
    let (floor_victims, out) = built_in(10.0);
    let r = out
        .rescuer
        .as_ref()
        .expect("the built-in mission has a rescuer");
    assert_eq!(r.zone_cells, 100);
    // The zone's rubble arena brought its own buried victims.
    assert!(
        out.victim_figures.total > floor_victims,
        "{:?}",
        out.victim_figures
    );
    assert!(r.primitives >= 50 && r.cells_visited >= 10, "{r:?}");
    let op = &out.operator;
    assert!(op.asked >= 1 && op.answered <= op.asked, "{op:?}");
    // One question at a time: each is answered after it was asked and after the operator
    // turned to it, and the operator turns to the next only once the last is answered.
    for h in &out.handoffs {
        assert!(
            h.asked_s <= h.started_s && h.started_s <= h.answered_s,
            "{h:?}"
        );
    }
    for w in out.handoffs.windows(2) {
        assert!(w[1].started_s >= w[0].answered_s, "{w:?}");
    }
    // A victim is confirmed only after someone detected it.
    for v in &out.victims {
        if let (Some(c), detected) = (v.confirmed_at_s, v.detected_at_s) {
            assert!(detected.is_some_and(|d| d <= c), "{v:?}");
        }
    }
    let f = &out.victim_figures;
    assert_eq!(f.detected + f.missed, f.total);
}

#[test]
fn without_the_rescuer_no_zone_is_laid_and_nobody_waits_for_it() {
    let scene = generate(SceneKind::Office, 1);
    let floor_victims = scene.victims.len();
    let config: MissionConfig =
        toml::from_str("minutes = 0.5\n[rescuer]\nenabled = false\n").unwrap();
    let out = run_mission(Arc::new(scene), &config, 1, None, |_| {}).unwrap();
    assert!(out.rescuer.is_none());
    assert_eq!(out.victim_figures.total, floor_victims);
}

#[test]
fn a_bad_rescuer_field_names_it() {
    let scene = Arc::new(generate(SceneKind::Office, 1));
    for (text, field) in [
        ("[rescuer]\nzone = \"attic\"\n", "rescuer.zone"),
        ("[rescuer]\nput_down = \"roof\"\n", "rescuer.put_down"),
        ("[rescuer]\nweights = \"heavy\"\n", "rescuer.weights"),
        (
            "[rescuer]\nlocalization = \"gps\"\n",
            "rescuer.localization",
        ),
        (
            "[rescuer]\npolicy = \"/nonexistent/policy.json\"\n",
            "rescuer.policy",
        ),
    ] {
        let config: MissionConfig = toml::from_str(text).unwrap();
        let err = run_mission(scene.clone(), &config, 1, None, |_| {}).unwrap_err();
        assert!(err.to_string().contains(field), "{text}: {err}");
        assert!(err.is_input());
    }
}

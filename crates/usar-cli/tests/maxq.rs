//! `usar maxq train / eval / teleop-study`: JSON fields, determinism, policy files.

use super::{assert_bad_input, usar};

fn json(out: &std::process::Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

#[test]
fn train_then_eval_is_deterministic_and_reports_every_scene() {
    let dir = tempfile::tempdir().unwrap();
    let policy = dir.path().join("policy.json");
    let p = policy.to_str().unwrap();
    let train = json(&usar(&[
        "maxq", "train", "--trials", "30", "--seed", "3", "--out", p, "--json",
    ]));
    assert!(train["maxq_q_values"].as_u64().unwrap() > 0);
    assert!(train["flat_q_values"].as_u64().unwrap() > 0);
    assert_eq!(train["curve"].as_array().unwrap().len(), 30);
    let args = [
        "maxq",
        "eval",
        "--policy",
        p,
        "--reps",
        "1",
        "--max-steps",
        "300",
        "--json",
    ];
    let first = usar(&args);
    let second = usar(&args);
    assert_eq!(
        first.stdout, second.stdout,
        "same policy and seed, same JSON"
    );
    let eval = json(&first);
    assert_eq!(eval["runs_total"], 36);
    for scene in ["A", "B", "C"] {
        let s = &eval["scenes"][scene];
        for key in [
            "steps",
            "coverage",
            "collisions",
            "victims_found",
            "victims_reachable",
        ] {
            assert!(s[key]["mean"].is_number(), "{scene} {key}: {s}");
        }
    }
    assert!(eval["paired_t_steps"]["travel_vs_equal"].is_object());
}

#[test]
fn a_corrupt_policy_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("cut.json");
    std::fs::write(&f, "{\"format\": \"usar-maxq-policy\"").unwrap();
    assert_bad_input(
        &usar(&["maxq", "eval", "--policy", f.to_str().unwrap()]),
        "not a policy file",
    );
    assert_bad_input(
        &usar(&[
            "maxq",
            "teleop-study",
            "--policy",
            dir.path().join("missing.json").to_str().unwrap(),
        ]),
        "missing.json",
    );
}

#[test]
fn teleop_study_compares_ten_operators() {
    let out = json(&usar(&["maxq", "teleop-study", "--trials", "20", "--json"]));
    assert_eq!(out["participants"].as_array().unwrap().len(), 10);
    for side in ["semi_autonomous", "teleoperated"] {
        for key in ["victims_found", "explored_percent", "collisions", "time_s"] {
            assert!(out[side][key]["mean"].is_number(), "{side} {key}");
        }
    }
}

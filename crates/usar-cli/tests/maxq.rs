//! `usar maxq train / eval / teleop-study`: JSON fields, determinism, policy files.

use super::{assert_bad_input, usar, usar_env};

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
    // Tests print their statistic and p, or why they could not be computed; no Rust wrappers.
    for test in [
        &eval["anova_steps_by_weights"],
        &eval["paired_t_steps"]["travel_vs_equal"],
    ] {
        assert!(test["p"].is_number() || test["error"].is_string(), "{test}");
        assert!(test.get("Ok").is_none() && test.get("Err").is_none());
    }

    // §VI-B runs in parallel; the results do not depend on the number of threads.
    let threads = |n: &str| usar_env(&args, &[("RAYON_NUM_THREADS", n)]).stdout;
    assert_eq!(threads("1"), first.stdout, "1 thread vs default");
    assert_eq!(threads("3"), first.stdout, "3 threads vs default");
}

#[test]
fn maxq_eval_campaign_runs_through_the_experiment_engine() {
    let dir = tempfile::tempdir().unwrap();
    let campaign = dir.path().join("eval.toml");
    std::fs::write(
        &campaign,
        r#"
name = "maxq-eval-small"
runner = "maxq-eval"
runs = 2
base_seed = 4

[factors]
scene = ["A", "B"]
weights = ["travel", "equal"]

[fixed]
train_trials = 20
max_steps = 200

[report]
rows = "scene"
columns = "weights"
metrics = ["steps", "coverage"]

[[report.compare]]
metric = "steps"
factor = "weights"
test = "paired"
groups = ["travel", "equal"]
tails = "less"
"#,
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    let run = json(&usar(&[
        "campaign",
        "run",
        campaign.to_str().unwrap(),
        "--jobs",
        "2",
        "--json",
        "--out",
        out_dir.to_str().unwrap(),
    ]));
    assert_eq!(run["report"]["stored"], 8, "{run}");
    let csv = dir.path().join("runs.csv");
    let export = usar(&[
        "campaign",
        "export",
        out_dir.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(export.status.success());
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    for column in ["steps", "coverage", "victims_found", "handoffs_stuck"] {
        assert!(header.contains(&column), "{column} not in {header:?}");
    }
    let coverage = header.iter().position(|c| *c == "coverage").unwrap();
    for line in text.lines().skip(1) {
        let c: f64 = line.split(',').nth(coverage).unwrap().parse().unwrap();
        assert!((0.0..=1.0).contains(&c) && c > 0.0, "coverage {c}");
    }
    // The same design, run again with one job, stores the same results.
    let again = dir.path().join("again");
    json(&usar(&[
        "campaign",
        "run",
        campaign.to_str().unwrap(),
        "--jobs",
        "1",
        "--json",
        "--out",
        again.to_str().unwrap(),
    ]));
    let digest = |d: &std::path::Path| {
        usar_campaign::Store::open(&usar_campaign::Store::path_in(d))
            .unwrap()
            .results_digest()
            .unwrap()
    };
    assert_eq!(digest(&out_dir), digest(&again));
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
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("fig16.svg");
    let out = json(&usar(&[
        "maxq",
        "teleop-study",
        "--trials",
        "20",
        "--plot",
        plot.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(out["participants"].as_array().unwrap().len(), 10);
    for name in [
        "fig16.svg",
        "fig16-victims.svg",
        "fig16-collisions.svg",
        "fig16-time.svg",
    ] {
        let svg = std::fs::read_to_string(dir.path().join(name)).unwrap();
        assert!(svg.contains("teleoperated") && svg.contains("semi-autonomous"));
    }
    for side in ["semi_autonomous", "teleoperated"] {
        for key in ["victims_found", "explored_percent", "collisions", "time_s"] {
            assert!(out[side][key]["mean"].is_number(), "{side} {key}");
        }
    }
}

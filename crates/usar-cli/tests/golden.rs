//! Golden outputs: the safety net for moving code between crates (issue 20). The JSON that
//! `team run` (every strategy × coordination, two seeds), `explore`, `btm build` on the course
//! and `maxq eval` print is kept in `tests/golden/`; after a refactoring it must be identical,
//! or the commit that changes it says why and blesses the new output with
//! `USAR_BLESS=1 cargo test -p usar-cli --test cli golden`.
//!
//! Output paths (`out`, `policy`) are dropped before comparing; everything else must match to
//! the last digit (a run is a pure function of scene, configuration and seed).

use super::usar_json;
use std::path::{Path, PathBuf};

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// The command's JSON, without the keys naming files this run wrote, pretty-printed with
/// sorted keys.
fn canonical_json(args: &[&str]) -> String {
    let mut value = usar_json(args);
    if let Some(map) = value.as_object_mut() {
        map.remove("out");
        map.remove("policy");
    }
    let mut text = serde_json::to_string_pretty(&value).unwrap();
    text.push('\n');
    text
}

/// Compares (or, with `USAR_BLESS=1`, writes) `tests/golden/NAME.json`.
fn check(name: &str, args: &[&str]) {
    let path = golden_dir().join(format!("{name}.json"));
    let text = canonical_json(args);
    if std::env::var_os("USAR_BLESS").is_some() {
        std::fs::create_dir_all(golden_dir()).unwrap();
        std::fs::write(&path, &text).unwrap();
        return;
    }
    let golden = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (bless with USAR_BLESS=1)", path.display()));
    if golden != text {
        let first = golden
            .lines()
            .zip(text.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(golden.lines().count().min(text.lines().count()));
        panic!(
            "usar {}: output differs from {} at line {}:\n  golden: {}\n  now:    {}",
            args.join(" "),
            path.display(),
            first + 1,
            golden.lines().nth(first).unwrap_or("<end>"),
            text.lines().nth(first).unwrap_or("<end>")
        );
    }
}

#[test]
fn team_runs_of_every_strategy_and_coordination_are_unchanged() {
    for strategy in ["random", "distance", "d-mcdm", "s-mcdm"] {
        for coordination in ["sr", "mrv1", "mrv2"] {
            for seed in ["1", "2"] {
                check(
                    &format!("team-{strategy}-{coordination}-{seed}"),
                    &[
                        "team",
                        "run",
                        "--scene",
                        "office",
                        "--robots",
                        "6",
                        "--strategy",
                        strategy,
                        "--coordination",
                        coordination,
                        "--hypothesis",
                        "big",
                        "--minutes",
                        "4",
                        "--seed",
                        seed,
                        "--json",
                    ],
                );
            }
        }
    }
}

#[test]
fn explore_and_btm_build_are_unchanged() {
    for seed in ["1", "2"] {
        check(
            &format!("explore-{seed}"),
            &[
                "explore",
                "--scene",
                "office",
                "--robots",
                "3",
                "--minutes",
                "3",
                "--seed",
                seed,
                "--json",
            ],
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("course.sqlite");
    check(
        "btm-build-course-1",
        &[
            "btm",
            "build",
            "--scene",
            "course",
            "--robot",
            "crawler",
            "--seed",
            "1",
            "--out",
            map.to_str().unwrap(),
            "--json",
        ],
    );
}

#[test]
fn maxq_training_and_evaluation_are_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let policy = dir.path().join("policy.json");
    let policy = policy.to_str().unwrap();
    check(
        "maxq-train-30",
        &[
            "maxq",
            "train",
            "--trials",
            "30",
            "--no-flat",
            "--seed",
            "1",
            "--out",
            policy,
            "--json",
        ],
    );
    check(
        "maxq-eval-30",
        &[
            "maxq",
            "eval",
            "--policy",
            policy,
            "--reps",
            "1",
            "--max-steps",
            "1500",
            "--json",
        ],
    );
}

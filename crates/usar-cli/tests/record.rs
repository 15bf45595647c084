//! `--record FILE.mcap` on the commands that run robots: the file is complete and reads back
//! (here through `usar log import`, which reads MCAP as a rosbag2), or there is no file.

use super::{assert_bad_input, usar, usar_json};

#[test]
fn team_explore_and_btm_runs_are_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let team = dir.path().join("team.mcap");
    usar_json(&[
        "team",
        "run",
        "--scene",
        "office",
        "--robots",
        "2",
        "--minutes",
        "1",
        "--record",
        team.to_str().unwrap(),
        "--json",
    ]);
    // One scan a simulated second per robot, the first step included; the busiest laser
    // topic is read.
    let v = usar_json(&["log", "import", team.to_str().unwrap(), "--json"]);
    assert_eq!(v["scans"], 61, "{v}");
    assert_eq!(v["beams_max"], 360);

    let explore = dir.path().join("explore.mcap");
    usar_json(&[
        "explore",
        "--scene",
        "office",
        "--robots",
        "1",
        "--minutes",
        "0.5",
        "--record",
        explore.to_str().unwrap(),
        "--json",
    ]);
    assert!(explore.is_file());

    let btm = dir.path().join("btm.mcap");
    usar_json(&[
        "btm",
        "build",
        "--scene",
        "course",
        "--max-minutes",
        "0.5",
        "--out",
        dir.path().join("c.sqlite").to_str().unwrap(),
        "--record",
        btm.to_str().unwrap(),
        "--json",
    ]);
    let v = usar_json(&["log", "import", btm.to_str().unwrap(), "--json"]);
    assert_eq!(v["scans"], 30, "{v}");
    // Nothing is left half-written.
    let partials = std::fs::read_dir(dir.path())
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .to_string_lossy()
                .ends_with(".partial")
        })
        .count();
    assert_eq!(partials, 0);
}

#[test]
fn a_recording_that_cannot_be_made_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("no/such/dir/run.mcap");
    let out = usar(&[
        "team",
        "run",
        "--scene",
        "office",
        "--robots",
        "1",
        "--minutes",
        "0.1",
        "--record",
        bad.to_str().unwrap(),
    ]);
    assert_bad_input(&out, "--record");
}

/// Messages per topic of an MCAP file, every one read.
fn topics(path: &std::path::Path) -> std::collections::BTreeMap<String, usize> {
    let bytes = std::fs::read(path).unwrap();
    let mut counts = std::collections::BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        *counts.entry(m.unwrap().channel.topic.clone()).or_default() += 1;
    }
    counts
}

/// One run of a MAXQ evaluation, replayed into a recording: a pose every primitive step, the
/// cell map and the possible victims every ten.
#[test]
fn a_maxq_evaluation_run_is_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let policy = dir.path().join("p.json");
    usar_json(&[
        "maxq",
        "train",
        "--trials",
        "30",
        "--seed",
        "3",
        "--out",
        policy.to_str().unwrap(),
        "--json",
    ]);
    let rec = dir.path().join("maxq.mcap");
    let args = |run: &str| {
        vec![
            "maxq".to_string(),
            "eval".into(),
            "--policy".into(),
            policy.to_str().unwrap().into(),
            "--reps".into(),
            "1".into(),
            "--record".into(),
            rec.to_str().unwrap().into(),
            "--record-run".into(),
            run.into(),
            "--json".into(),
        ]
    };
    let a = args("2");
    usar_json(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let counts = topics(&rec);
    let poses = counts["/tf"];
    assert_eq!(counts["/clock"], poses);
    assert!(poses > 50, "{counts:?}");
    assert_eq!(counts["/rescuer/map"], poses.div_ceil(10));
    let a = args("999");
    let out = usar(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_bad_input(&out, "--record-run 999: expected a run index below 36");
}

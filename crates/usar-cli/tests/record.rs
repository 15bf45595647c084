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

//! `usar campaign`: killed and resumed, sharded and merged, reported and exported, bad input.

use super::{assert_bad_input, usar};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use usar_campaign::Store;

fn digest(dir: &Path) -> String {
    Store::open(&Store::path_in(dir))
        .unwrap()
        .results_digest()
        .unwrap()
}

/// Runs stored so far (0 while the database does not exist or is busy).
fn stored(dir: &Path) -> usize {
    Store::open(&Store::path_in(dir))
        .ok()
        .and_then(|s| s.finished_ids().ok())
        .map_or(0, |ids| ids.len())
}

fn ok(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn smoke_killed_midway_resumes_to_the_same_results_as_shards_merged() {
    let tmp = tempfile::tempdir().unwrap();
    let killed = tmp.path().join("killed");
    let mut child = Command::new(env!("CARGO_BIN_EXE_usar"))
        .args([
            "campaign", "run", "--preset", "smoke", "--jobs", "2", "--json", "--out",
        ])
        .arg(&killed)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while stored(&killed) < 6 && started.elapsed() < Duration::from_secs(300) {
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let before = stored(&killed);
    assert!(
        (6..30).contains(&before),
        "killed after {before} of 30 runs"
    );
    let resumed = usar(&[
        "campaign",
        "run",
        "--preset",
        "smoke",
        "--json",
        "--out",
        killed.to_str().unwrap(),
    ]);
    ok(&resumed);
    let v: serde_json::Value = serde_json::from_slice(&resumed.stdout).unwrap();
    assert_eq!(v["report"]["skipped"], before as u64);
    assert_eq!(v["report"]["done"], 30 - before as u64);
    assert_eq!(v["report"]["stored"], 30);

    // The same campaign in two shards, merged.
    let (s1, s2, merged) = (
        tmp.path().join("s1"),
        tmp.path().join("s2"),
        tmp.path().join("m"),
    );
    for (shard, dir) in [("1/2", &s1), ("2/2", &s2)] {
        let out = usar(&[
            "campaign",
            "run",
            "--preset",
            "smoke",
            "--jobs",
            "1",
            "--json",
            "--shard",
            shard,
            "--out",
            dir.to_str().unwrap(),
        ]);
        ok(&out);
        assert_eq!(stored(dir), 15);
    }
    ok(&usar(&[
        "campaign",
        "merge",
        s1.to_str().unwrap(),
        s2.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]));
    assert_eq!(stored(&merged), 30);
    assert_eq!(digest(&killed), digest(&merged));

    report_agrees_with_a_recomputation_from_the_csv(&merged, &tmp.path().join("runs.csv"));
}

/// The report's table cells and t-tests, recomputed from the exported CSV with plain formulas
/// and statrs' distributions directly.
fn report_agrees_with_a_recomputation_from_the_csv(dir: &Path, csv_path: &Path) {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    // A report killed while writing left a temporary file: the next report removes it.
    std::fs::create_dir_all(dir.join("report")).unwrap();
    let stale = dir.join("report").join(".report.md.tmp-999999");
    std::fs::write(&stale, "half a report").unwrap();
    ok(&usar(&[
        "campaign",
        "export",
        dir.to_str().unwrap(),
        "--csv",
        csv_path.to_str().unwrap(),
    ]));
    let rep = usar(&["campaign", "report", dir.to_str().unwrap(), "--json"]);
    ok(&rep);
    let rep: serde_json::Value = serde_json::from_slice(&rep.stdout).unwrap();
    let mut reader = csv::Reader::from_path(csv_path).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    for col in [
        "run_id",
        "config_index",
        "repetition",
        "seed",
        "robot",
        "robots",
        "scene",
        "coverage",
        "victims_seen",
    ] {
        assert!(
            header.contains(&col.to_string()),
            "column {col} missing: {header:?}"
        );
    }
    let rows: Vec<BTreeMap<String, String>> = reader
        .records()
        .map(|r| {
            header
                .iter()
                .cloned()
                .zip(r.unwrap().iter().map(String::from))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), 30);
    let values = |robots: &str, robot: Option<&str>| -> Vec<f64> {
        rows.iter()
            .filter(|r| r["robots"] == robots && robot.is_none_or(|b| r["robot"] == b))
            .map(|r| r["coverage"].parse().unwrap())
            .collect()
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let var = |v: &[f64]| {
        let m = mean(v);
        v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (v.len() - 1) as f64
    };
    let table = &rep["report"]["tables"][0];
    assert_eq!(table["metric"], "coverage");
    for (i, robots) in ["1", "2", "3"].iter().enumerate() {
        for (j, robot) in ["wheeled", "crawler"].iter().enumerate() {
            let v = values(robots, Some(robot));
            let cell = &table["cells"][i][j];
            assert!((cell["mean"].as_f64().unwrap() - mean(&v)).abs() < 1e-6);
            assert!((cell["sd"].as_f64().unwrap() - var(&v).sqrt()).abs() < 1e-6);
        }
    }
    // Welch, robots 3 > 1 (the third comparison of the smoke campaign).
    let (a, b) = (values("3", None), values("1", None));
    let (va, vb) = (var(&a) / a.len() as f64, var(&b) / b.len() as f64);
    let t = (mean(&a) - mean(&b)) / (va + vb).sqrt();
    let df = (va + vb).powi(2) / (va * va / (a.len() - 1) as f64 + vb * vb / (b.len() - 1) as f64);
    let p = 1.0 - StudentsT::new(0.0, 1.0, df).unwrap().cdf(t);
    let welch = &rep["report"]["tests"][2];
    assert_eq!(welch["test"], "welch");
    assert!((welch["statistic"].as_f64().unwrap() - t).abs() < 1e-6);
    assert!((welch["df"][0].as_f64().unwrap() - df).abs() < 1e-6);
    assert!((welch["p"].as_f64().unwrap() - p).abs() < 1e-6);
    assert!(dir.join("report").join("series_coverage.svg").is_file());
    assert!(!stale.exists(), "the stale temporary file is removed");
}

#[test]
fn bad_campaign_files_and_databases_exit_2_and_leave_results_untouched() {
    let tmp = tempfile::tempdir().unwrap();
    let smoke = include_str!("../../../campaigns/smoke.toml");
    for (name, text, needle) in [
        (
            "unknown-factor.toml",
            smoke.replace("robots = [1, 2, 3]", "robotz = [1, 2, 3]"),
            "unknown factor `robotz`",
        ),
        (
            "typo.toml",
            smoke.replace("base_seed = 1", "base_sede = 1"),
            "unknown field `base_sede`",
        ),
        (
            "bad-level.toml",
            smoke.replace("robots = [1, 2, 3]", "robots = [1, 0]"),
            "robots` level 0",
        ),
    ] {
        let f = tmp.path().join(name);
        std::fs::write(&f, text).unwrap();
        let out = usar(&[
            "campaign",
            "run",
            f.to_str().unwrap(),
            "--out",
            tmp.path().join("o").to_str().unwrap(),
        ]);
        assert_bad_input(&out, needle);
    }
    assert!(
        !tmp.path().join("o").exists(),
        "nothing written for a bad campaign"
    );

    let corrupt = tmp.path().join("corrupt");
    std::fs::create_dir(&corrupt).unwrap();
    let db = corrupt.join("results.sqlite");
    let junk = b"SQLite format 3\0 but not really".repeat(64);
    std::fs::write(&db, &junk).unwrap();
    for args in [
        vec![
            "campaign",
            "run",
            "--preset",
            "smoke",
            "--out",
            corrupt.to_str().unwrap(),
        ],
        vec!["campaign", "report", corrupt.to_str().unwrap()],
    ] {
        assert_bad_input(&usar(&args), "not a usar campaign result database");
    }
    assert_eq!(std::fs::read(&db).unwrap(), junk);
}

#[test]
fn every_preset_parses_against_its_runner() {
    let out = usar(&["campaign", "list", "--json"]);
    ok(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let runs: BTreeMap<&str, u64> = v["presets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            assert!(p["error"].is_null(), "broken preset: {p}");
            (p["name"].as_str().unwrap(), p["runs"].as_u64().unwrap())
        })
        .collect();
    // The papers' designs: Tables 4-7 of paper 002 and §VI-B of paper 000.
    assert_eq!(runs["team-tables"], 720);
    assert_eq!(runs["maxq-eval"], 216);
    assert_eq!(runs["smoke"], 30);
}

#[test]
fn output_into_a_closed_pipe_ends_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_usar"))
        .args(["campaign", "list"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away, like `| head -0`
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_folder_in_use_is_refused_at_once_with_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("busy");
    std::fs::create_dir(&dir).unwrap();
    // This process holds the folder as a run would.
    let lock = usar_campaign::FolderLock::exclusive(&dir, "campaign run").unwrap();
    let busy = format!(
        "{}: another `usar campaign run` (pid {}) is using this folder",
        dir.display(),
        std::process::id()
    );
    let run = || {
        usar(&[
            "campaign",
            "run",
            "--preset",
            "smoke",
            "--out",
            dir.to_str().unwrap(),
        ])
    };
    assert_bad_input(&run(), &busy);
    assert!(!Store::path_in(&dir).exists(), "nothing created");
    let merged = tmp.path().join("m");
    assert_bad_input(
        &usar(&[
            "campaign",
            "merge",
            dir.to_str().unwrap(),
            "--out",
            merged.to_str().unwrap(),
        ]),
        &busy,
    );
    drop(lock);
    // Released: the run goes ahead, an empty results file (an older version's interrupted
    // creation) notwithstanding.
    std::fs::write(Store::path_in(&dir), b"").unwrap();
    let out = usar(&[
        "campaign",
        "run",
        "--preset",
        "smoke",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    ok(&out);
    assert_eq!(stored(&dir), 30);
}

#[test]
fn a_campaign_name_that_is_not_a_plain_folder_name_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let smoke = include_str!("../../../campaigns/smoke.toml");
    for name in ["../../../escaped", "/tmp/escaped", ".."] {
        let f = tmp.path().join("c.toml");
        std::fs::write(
            &f,
            smoke.replace("name = \"smoke\"", &format!("name = {name:?}")),
        )
        .unwrap();
        let out = usar(&["campaign", "run", f.to_str().unwrap()]);
        assert_bad_input(
            &out,
            &format!(
                "{}: line 3: name = {name:?}, expected a plain folder name",
                f.display()
            ),
        );
    }
}

#[test]
fn slurm_scripts_run_each_shard_into_its_own_folder_and_status_follows_them() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("tt");
    let dir = out.to_str().unwrap();
    let o = usar(&[
        "campaign", "slurm", "--preset", "smoke", "--out", dir, "--tasks", "3", "--time",
        "00:10:00", "--json",
    ]);
    ok(&o);
    let array = std::fs::read_to_string(out.join("slurm/array.sbatch")).unwrap();
    assert!(array.contains("#SBATCH --array=1-3"), "{array}");
    assert!(array.contains("#SBATCH --time=00:10:00"), "{array}");
    assert!(
        array.contains("--shard \"${SLURM_ARRAY_TASK_ID}/3\""),
        "{array}"
    );
    let merge = std::fs::read_to_string(out.join("slurm/merge.sbatch")).unwrap();
    assert!(merge.contains("campaign merge"), "{merge}");
    let submit = std::fs::read_to_string(out.join("slurm/submit.sh")).unwrap();
    assert!(submit.contains("--dependency=afterok"), "{submit}");
    // Nothing run yet: every shard missing. Shard 2 run by hand (as its task would): done.
    let status = |o: &std::process::Output| -> serde_json::Value {
        ok(o);
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let s = status(&usar(&["campaign", "status", dir, "--json"]));
    assert!(
        s["shards"]
            .as_array()
            .unwrap()
            .iter()
            .all(|x| x["state"] == "missing"),
        "{s}"
    );
    let shard2 = out.join("shards/2");
    ok(&usar(&[
        "campaign",
        "run",
        "--preset",
        "smoke",
        "--shard",
        "2/3",
        "--out",
        shard2.to_str().unwrap(),
        "--json",
    ]));
    let s = status(&usar(&["campaign", "status", dir, "--json"]));
    let states: Vec<&str> = s["shards"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x["state"].as_str().unwrap())
        .collect();
    assert_eq!(states, ["missing", "done", "missing"], "{s}");
    assert_eq!(s["merged"], false);
    // The same folder for another task count is refused; so are values that could break a
    // script's lines, and a task count out of range.
    assert_bad_input(
        &usar(&[
            "campaign", "slurm", "--preset", "smoke", "--out", dir, "--tasks", "4",
        ]),
        "expected a new --out folder",
    );
    let other = tmp.path().join("other");
    let other = other.to_str().unwrap();
    for (args, needle) in [
        (vec!["--tasks", "0"], "--tasks 0"),
        (vec!["--tasks", "2", "--time", "1:00\nrm -rf /"], "--time"),
        (vec!["--tasks", "2", "--partition", "a b"], "--partition"),
    ] {
        let mut all = vec!["campaign", "slurm", "--preset", "smoke", "--out", other];
        all.extend(args);
        assert_bad_input(&usar(&all), needle);
    }
    assert!(!tmp.path().join("other/slurm").exists());
    assert_bad_input(&usar(&["campaign", "status", other]), "usar campaign slurm");
}

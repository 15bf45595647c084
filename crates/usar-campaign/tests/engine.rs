//! The engine with the no-op runner: design expansion, errors, resume, shards and merge.

use std::path::Path;
use usar_campaign::{Design, NoopRunner, Shard, Store, merge, run_design};

const CAMPAIGN: &str = r#"
name = "noop"
runner = "noop"
runs = 4
base_seed = 10

[factors]
a = [1, 2, 3]
b = ["x", "y"]

[report]
rows = "a"
columns = "b"
"#;

fn design(text: &str) -> Design {
    Design::parse(text, "test.toml", &NoopRunner).unwrap()
}

fn run(dir: &Path, shard: Shard, jobs: usize) -> usar_campaign::RunReport {
    let d = design(CAMPAIGN);
    let mut store = Store::open_or_create(dir, &d).unwrap();
    run_design(&d, &NoopRunner, &mut store, shard, jobs, |_, _| {}).unwrap()
}

fn digest(dir: &Path) -> String {
    Store::open(&Store::path_in(dir))
        .unwrap()
        .results_digest()
        .unwrap()
}

#[test]
fn the_design_is_the_full_factorial_with_shared_seeds() {
    let d = design(CAMPAIGN);
    assert_eq!(d.configs.len(), 6);
    assert_eq!(d.len(), 24);
    // Last factor fastest.
    assert_eq!(d.configs[0].describe(&[]), "a=1, b=x");
    assert_eq!(d.configs[1].describe(&[]), "a=1, b=y");
    assert_eq!(d.configs[5].describe(&[]), "a=3, b=y");
    let r = d.run(9);
    assert_eq!((r.config_index, r.repetition, r.seed), (2, 1, 11));
    // The report section does not change the design.
    let other = design(&CAMPAIGN.replace("columns = \"b\"", ""));
    assert_eq!(d.hash, other.hash);
    assert_ne!(
        d.hash,
        design(&CAMPAIGN.replace("runs = 4", "runs = 5")).hash
    );
}

#[test]
fn unknown_factors_and_keys_are_errors_naming_the_line() {
    let err = Design::parse(
        &CAMPAIGN.replace("a = [1, 2, 3]", "c = [1]"),
        "f.toml",
        &NoopRunner,
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("f.toml: line 8: unknown factor `c`"), "{err}");
    assert!(err.contains("expected one of a, b"), "{err}");
    let err = Design::parse(
        &CAMPAIGN.replace("runs = 4", "rusn = 4"),
        "f.toml",
        &NoopRunner,
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("f.toml: line 4, column 1:") && err.contains("rusn"),
        "{err}"
    );
    // A duplicate key is named as one (it used to read as a missing runner).
    let twice = CAMPAIGN.replace("runs = 4", "runs = 4\nruns = 5");
    let Err(err) = usar_campaign::design::runner_named(&twice, "f.toml", |_| None) else {
        panic!("a duplicate key was accepted");
    };
    let err = err.to_string();
    assert!(
        err.contains("f.toml: line 5, column 1: duplicate key `runs`"),
        "{err}"
    );
    let err = Design::parse(&CAMPAIGN.replace("\"y\"", "\"w\""), "f.toml", &NoopRunner)
        .unwrap_err()
        .to_string();
    assert!(err.contains("level w, expected one of x, y, z"), "{err}");
    let err = Design::parse(
        &CAMPAIGN.replace("rows = \"a\"", "rows = \"q\""),
        "f.toml",
        &NoopRunner,
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("report rows = `q`"), "{err}");
}

#[test]
fn a_resumed_campaign_runs_only_what_is_missing_and_ends_like_an_uninterrupted_one() {
    let whole = tempfile::tempdir().unwrap();
    let r = run(whole.path(), Shard::ALL, 2);
    assert_eq!((r.done, r.skipped, r.stored), (24, 0, 24));
    let again = run(whole.path(), Shard::ALL, 2);
    assert_eq!((again.done, again.skipped, again.stored), (0, 24, 24));

    // An interrupted campaign: a third of the runs, then the rest.
    let resumed = tempfile::tempdir().unwrap();
    let part = run(resumed.path(), Shard { index: 2, count: 3 }, 1);
    assert_eq!(part.done, 8);
    let rest = run(resumed.path(), Shard::ALL, 2);
    assert_eq!((rest.done, rest.skipped, rest.stored), (16, 8, 24));
    assert_eq!(digest(whole.path()), digest(resumed.path()));
}

#[test]
fn shards_merged_equal_one_unsharded_run() {
    let whole = tempfile::tempdir().unwrap();
    run(whole.path(), Shard::ALL, 1);
    let (s1, s2, out) = (
        tempfile::tempdir().unwrap(),
        tempfile::tempdir().unwrap(),
        tempfile::tempdir().unwrap(),
    );
    assert_eq!(run(s1.path(), Shard { index: 1, count: 2 }, 2).done, 12);
    assert_eq!(run(s2.path(), Shard { index: 2, count: 2 }, 2).done, 12);
    let merged = out.path().join("m");
    let (inputs, runs) = merge(&[s1.path().into(), s2.path().into()], &merged).unwrap();
    assert_eq!((inputs, runs), (2, 24));
    assert_eq!(digest(whole.path()), digest(&merged));
    // Merging again into the same folder is refused and leaves it as it was.
    assert!(merge(&[s1.path().into()], &merged).is_err());
    assert_eq!(digest(whole.path()), digest(&merged));
}

#[test]
fn a_database_of_another_design_is_refused_and_left_untouched() {
    let dir = tempfile::tempdir().unwrap();
    run(dir.path(), Shard::ALL, 1);
    let before = std::fs::read(Store::path_in(dir.path())).unwrap();
    let other = design(&CAMPAIGN.replace("runs = 4", "runs = 2"));
    let err = Store::open_or_create(dir.path(), &other).err().unwrap();
    assert!(err.is_input());
    assert!(
        err.to_string().contains("holds results of another design"),
        "{err}"
    );
    assert_eq!(before, std::fs::read(Store::path_in(dir.path())).unwrap());
    // Merging shards of different designs is refused.
    let o = tempfile::tempdir().unwrap();
    {
        let mut s = Store::open_or_create(o.path(), &other).unwrap();
        run_design(&other, &NoopRunner, &mut s, Shard::ALL, 1, |_, _| {}).unwrap();
    }
    let out = tempfile::tempdir().unwrap();
    let err = merge(&[dir.path().into(), o.path().into()], &out.path().join("m")).unwrap_err();
    assert!(err.to_string().contains("cannot be merged"), "{err}");
    assert!(!out.path().join("m").join("results.sqlite").exists());
}

#[test]
fn corrupt_and_foreign_files_are_refused_and_left_untouched() {
    let d = design(CAMPAIGN);
    // (An empty file is what an interrupted creation leaves: it is created anew, see
    // folders.rs; a file with content is never deleted.)
    for (what, bytes) in [
        (
            "garbage",
            b"this is not a database at all, just some text".repeat(200),
        ),
        (
            "garbage with a SQLite header",
            b"SQLite format 3\0 but not really".repeat(64),
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let path = Store::path_in(dir.path());
        std::fs::write(&path, &bytes).unwrap();
        let err = Store::open_or_create(dir.path(), &d).err().expect(what);
        assert!(err.is_input(), "{what}: {err}");
        assert!(
            err.to_string()
                .contains("not a usar campaign result database"),
            "{what}: {err}"
        );
        assert_eq!(std::fs::read(&path).unwrap(), bytes, "{what}");
    }
    // A real SQLite database of something else.
    let dir = tempfile::tempdir().unwrap();
    let path = Store::path_in(dir.path());
    {
        let c = rusqlite::Connection::open(&path).unwrap();
        c.execute_batch("CREATE TABLE t (x); INSERT INTO t VALUES (1);")
            .unwrap();
    }
    let before = std::fs::read(&path).unwrap();
    let err = Store::open_or_create(dir.path(), &d).err().unwrap();
    assert!(
        err.to_string()
            .contains("not a usar campaign result database"),
        "{err}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), before);
}

#[test]
fn shard_syntax() {
    assert_eq!(Shard::parse("2/3"), Ok(Shard { index: 2, count: 3 }));
    assert!(Shard::parse("0/3").is_err());
    assert!(Shard::parse("4/3").is_err());
    assert!(Shard::parse("1").is_err());
}

/// A runner that fails run 2 of configuration a = 2, as the user's fault or its own.
struct Failing(usar_campaign::RunError);

impl usar_campaign::Runner for Failing {
    fn name(&self) -> &str {
        "noop"
    }
    fn factors(&self) -> Vec<usar_campaign::FactorSpec> {
        NoopRunner.factors()
    }
    fn metrics(&self) -> Vec<usar_campaign::MetricSpec> {
        NoopRunner.metrics()
    }
    fn series_x(&self) -> &str {
        "step"
    }
    fn run(
        &self,
        config: &usar_campaign::Config,
        seed: u64,
    ) -> Result<usar_campaign::RunOutput, usar_campaign::RunError> {
        if config.int("a") == Some(2) {
            return Err(self.0.clone());
        }
        NoopRunner.run(config, seed)
    }
}

#[test]
fn a_failed_run_says_whether_its_configuration_or_the_run_is_at_fault() {
    use usar_campaign::{RunError, Runner};
    for (error, input) in [
        (
            RunError::Input("scene nowhere.json does not exist".into()),
            true,
        ),
        (RunError::Failed("the simulator gave up".into()), false),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let d = design(CAMPAIGN);
        let mut store = Store::open_or_create(dir.path(), &d).unwrap();
        let runner = Failing(error.clone());
        assert_eq!(runner.name(), "noop");
        let err = run_design(&d, &runner, &mut store, Shard::ALL, 1, |_, _| {}).unwrap_err();
        assert_eq!(err.is_input(), input, "{err}");
        assert!(err.to_string().contains(&error.to_string()), "{err}");
        assert!(err.to_string().contains("a=2"), "{err}");
    }
}

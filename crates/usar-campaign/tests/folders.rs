//! Campaign output folders: one writer at a time (locks), leftovers of interrupted creations
//! and reports, campaign names that must stay inside `out/campaigns`.

use std::path::Path;
use usar_campaign::report::{ReportFolder, is_report_temporary};
use usar_campaign::{Design, NoopRunner, Shard, Store, merge, run_design};

const CAMPAIGN: &str = r#"
name = "noop"
runner = "noop"
runs = 2

[factors]
a = [1, 2]
"#;

fn design() -> Design {
    Design::parse(CAMPAIGN, "test.toml", &NoopRunner).unwrap()
}

fn run(dir: &Path) -> u64 {
    let d = design();
    let mut store = Store::open_or_create(dir, &d).unwrap();
    run_design(&d, &NoopRunner, &mut store, Shard::ALL, 1, |_, _| {})
        .unwrap()
        .stored
}

fn in_use(err: &usar_campaign::CampaignError, dir: &Path, command: &str) {
    let text = err.to_string();
    assert!(err.is_input(), "{text}");
    let expected = format!(
        "{}: another `usar {command}` (pid {}) is using this folder",
        dir.display(),
        std::process::id()
    );
    assert!(text.contains(&expected), "{text}");
    assert_eq!(text.lines().count(), 1, "{text}");
}

#[test]
fn a_folder_in_use_by_a_run_is_refused_at_once_to_a_second_run_and_to_merge() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let d = design();
    let held = Store::open_or_create(&dir, &d).unwrap();
    // A second run on the folder (another opener of its lock file: flock locks belong to the
    // open file, so this is what a second process sees).
    let err = Store::open_or_create(&dir, &d).err().expect("refused");
    in_use(&err, &dir, "campaign run");
    // Merging it while it is being run, or merging into it, is refused too.
    let err = merge(std::slice::from_ref(&dir), &tmp.path().join("m")).unwrap_err();
    in_use(&err, &dir, "campaign run");
    assert!(!tmp.path().join("m").exists(), "nothing written");
    drop(held);
    // Released with the store: the folder is usable again.
    assert_eq!(run(&dir), 4);
    let other = tmp.path().join("other");
    assert_eq!(run(&other), 4);
    let held = Store::open_or_create(&other, &d).unwrap();
    let err = merge(std::slice::from_ref(&dir), &other).unwrap_err();
    assert!(
        err.to_string().contains("already exists"),
        "an output folder with results is refused first: {err}"
    );
    drop(held);
    let fresh = tmp.path().join("fresh");
    std::fs::create_dir(&fresh).unwrap();
    let lock = usar_campaign::FolderLock::exclusive(&fresh, "campaign merge").unwrap();
    let err = merge(std::slice::from_ref(&dir), &fresh).unwrap_err();
    in_use(&err, &fresh, "campaign merge");
    drop(lock);
    assert_eq!(merge(std::slice::from_ref(&dir), &fresh).unwrap(), (1, 4));
}

#[test]
fn an_empty_or_half_created_results_file_is_created_anew_and_a_foreign_one_is_kept() {
    let d = design();
    let tmp = tempfile::tempdir().unwrap();
    // An empty file (a creation killed before SQLite wrote a page).
    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    std::fs::write(Store::path_in(&empty), b"").unwrap();
    let err = Store::open(&Store::path_in(&empty)).err().unwrap();
    assert!(err.to_string().contains("an empty file"), "{err}");
    assert_eq!(run(&empty), 4);
    // Tables created but no design recorded (two creations racing in an older version).
    let half = tmp.path().join("half");
    std::fs::create_dir(&half).unwrap();
    {
        let c = rusqlite::Connection::open(Store::path_in(&half)).unwrap();
        c.execute_batch(
            "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
             CREATE TABLE runs (id INTEGER PRIMARY KEY, config_index INTEGER NOT NULL,
                 repetition INTEGER NOT NULL, seed INTEGER NOT NULL, config TEXT NOT NULL);
             INSERT INTO meta VALUES ('format', 'usar-campaign');",
        )
        .unwrap();
    }
    assert_eq!(run(&half), 4);
    // A half-created file with results in it, or with a table of someone else's, is not ours
    // to delete.
    for (name, sql) in [
        (
            "with-results",
            "CREATE TABLE runs (id INTEGER PRIMARY KEY, config_index, repetition, seed, config);
             INSERT INTO runs VALUES (0, 0, 0, 1, '{}');",
        ),
        (
            "foreign",
            "CREATE TABLE meta (key, value); CREATE TABLE t (x);",
        ),
    ] {
        let dir = tmp.path().join(name);
        std::fs::create_dir(&dir).unwrap();
        {
            let c = rusqlite::Connection::open(Store::path_in(&dir)).unwrap();
            c.execute_batch(sql).unwrap();
        }
        let before = std::fs::read(Store::path_in(&dir)).unwrap();
        let err = Store::open_or_create(&dir, &d).err().expect(name);
        assert!(
            err.to_string()
                .contains("not a usar campaign result database"),
            "{name}: {err}"
        );
        assert_eq!(
            std::fs::read(Store::path_in(&dir)).unwrap(),
            before,
            "{name}"
        );
    }
}

#[test]
fn a_campaign_name_must_be_one_plain_folder_name() {
    for bad in [
        "../../../x",
        "/tmp/x",
        "a/b",
        "a\\b",
        "..",
        ".",
        "",
        "x y",
        "naïve",
    ] {
        let text = CAMPAIGN.replace("name = \"noop\"", &format!("name = {bad:?}"));
        let err = Design::parse(&text, "c.toml", &NoopRunner)
            .err()
            .unwrap_or_else(|| panic!("{bad:?} accepted"))
            .to_string();
        assert!(err.starts_with("c.toml: line 2: name = "), "{err}");
        assert!(err.contains("expected a plain folder name"), "{err}");
    }
    for good in ["smoke", "team-fig13-14", "run_2.v1", "..x"] {
        let text = CAMPAIGN.replace("name = \"noop\"", &format!("name = {good:?}"));
        assert!(
            Design::parse(&text, "c.toml", &NoopRunner).is_ok(),
            "{good}"
        );
    }
}

#[test]
fn a_report_folder_is_written_by_one_report_and_cleared_of_a_killed_reports_temporaries() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("report");
    std::fs::create_dir(&dir).unwrap();
    let stale = [
        ".report.md.tmp-4242",
        ".report.html.tmp-1",
        ".series_coverage.png.tmp-77",
        ".bars_victims_seen.svg.tmp-77",
    ];
    let kept = [
        "report.md",
        "series_coverage.png",
        ".notes.txt.tmp-1",
        ".report.md.tmp-",
        ".report.md.tmp-12x",
        "report.md.tmp-1",
        ".usar-campaign.lock",
    ];
    for name in stale.iter().chain(&kept) {
        std::fs::write(dir.join(name), b"x").unwrap();
    }
    let folder = ReportFolder::open(&dir).unwrap();
    let mut removed: Vec<String> = folder
        .removed
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    removed.sort();
    let mut expected: Vec<String> = stale.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(removed, expected);
    for name in kept {
        assert!(dir.join(name).exists(), "{name} removed");
        assert!(!is_report_temporary(name), "{name}");
    }
    // A second report into the same folder is refused while the first one writes.
    let err = ReportFolder::open(&dir).unwrap_err();
    in_use(&err, &dir, "campaign report");
    drop(folder);
    assert!(ReportFolder::open(&dir).unwrap().removed.is_empty());
}

#[test]
fn write_folder_writes_plots_then_the_report() {
    use usar_campaign::report::{Format, write_folder};
    let tmp = tempfile::tempdir().unwrap();
    run(tmp.path());
    let store = Store::open(&Store::path_in(tmp.path())).unwrap();
    let campaign = store.campaign().unwrap();
    let runs = store.runs().unwrap();
    let dir = tmp.path().join("report");
    let written = write_folder(&dir, &campaign, &runs, &NoopRunner, Format::Html).unwrap();
    assert_eq!(written.file, dir.join("report.html"));
    assert!(written.file.exists());
    assert_eq!(written.report.runs, 4);
    for plot in &written.plots {
        assert!(plot.exists(), "{}", plot.display());
    }
    let json = serde_json::to_value(&written).unwrap();
    let keys: Vec<&String> = json.as_object().unwrap().keys().collect();
    assert_eq!(keys, ["file", "plots", "report"]);
}

#[test]
fn summarize_lists_a_campaign_or_why_it_is_broken() {
    use usar_campaign::design::{Summary, summarize};
    let noop = |name: &str| (name == "noop").then_some(&NoopRunner as &dyn usar_campaign::Runner);
    let ok = summarize("noop", "preset noop", CAMPAIGN, noop);
    assert_eq!(
        ok,
        Summary::Ready {
            description: String::new(),
            name: "noop".into(),
            runner: "noop".into(),
            runs: 4,
        }
    );
    assert_eq!(
        serde_json::to_string(&ok).unwrap(),
        r#"{"description":"","name":"noop","runner":"noop","runs":4}"#
    );
    let broken = summarize("bad", "preset bad", "runs = 2", noop);
    assert_eq!(broken.name(), "bad");
    match broken {
        Summary::Broken { error, .. } => {
            assert!(error.starts_with("preset bad: missing `runner"), "{error}")
        }
        other => panic!("{other:?}"),
    }
}

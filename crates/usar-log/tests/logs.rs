//! usar-log on the real robot logs of `../shared/datasets/` (read in place, never copied): what
//! each holds as its PROVENANCE states it, maps built from them, a rosbag2 written by an
//! independent tool (the Python `rosbags` package; `./test.sh` installs it and sets
//! `USAR_PYTHON`), and bad logs refused with their line.

use std::path::{Path, PathBuf};
use usar_log::mapping::{MapParams, Matcher, build_map};
use usar_log::no_return::Source;
use usar_log::{LogError, LogEvent, LogFormat, parse_log, read_log};

fn dataset(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/datasets")
        .join(path)
}

const INTEL: &str = "intel_lab_carmen/intel-corrected.log.gz";
const DUKE: &str = "duke_dpslam_loop5/loop5.log";
const CMU: &str = "cmu_wean_robotdata1/ascii-robotdata1.log";

#[test]
fn the_real_logs_hold_what_their_provenance_says() {
    let intel = read_log(&dataset(INTEL), None).unwrap();
    let s = intel.summary();
    assert_eq!(s.format, LogFormat::Carmen);
    assert_eq!((s.scans, s.odometry_readings), (910, 14_541));
    assert_eq!((s.beams_min, s.beams_max), (180, 180));
    assert_eq!(s.backward_steps, 4);
    assert_eq!(s.no_return_source, Source::Spike);
    assert!((s.no_return_m.unwrap() - 81.83).abs() < 1e-3);
    assert!((s.longest_return_m - 25.38).abs() < 1e-3);
    assert!((s.t_first_s - 32.9).abs() < 0.1 && (s.t_last_s - 2683.8).abs() < 0.1);

    let duke = read_log(&dataset(DUKE), None).unwrap();
    let s = duke.summary();
    assert_eq!(s.format, LogFormat::DpSlam);
    assert_eq!((s.scans, s.odometry_readings, s.beams_max), (551, 551, 181));
    assert!((s.field_of_view_deg - 180.0).abs() < 1e-9);
    // The SICK's 8 m mode saturates at 8.183-8.191 m.
    assert!((8.1..8.183).contains(&s.no_return_m.unwrap()));
    assert!(
        (s.odometry_path_m - 56.0).abs() < 0.5,
        "{}",
        s.odometry_path_m
    );

    let cmu = read_log(&dataset(CMU), None).unwrap();
    let s = cmu.summary();
    assert_eq!(s.format, LogFormat::Thrun);
    assert_eq!(
        (s.scans, s.odometry_readings, s.beams_max),
        (713, 1_505, 180)
    );
    // 8183 cm, in metres.
    assert!((s.no_return_m.unwrap() - 81.83).abs() < 1e-3);
    assert!(
        (s.odometry_path_m - 41.0).abs() < 1.0,
        "{}",
        s.odometry_path_m
    );
    // The laser 25 cm ahead of the robot's centre.
    let scans = cmu.scans().unwrap();
    assert!(
        (scans[0].mount.x - 0.25).abs() < 0.01,
        "{:?}",
        scans[0].mount
    );
}

/// The Intel log's FLASER poses are GMapping's corrected ones; its raw odometry drifts tens of
/// metres from them. The map built by correlative matching stays within a metre of them
/// everywhere; odometry alone does not.
#[test]
fn the_intel_map_follows_the_corrected_poses_and_odometry_does_not() {
    let log = read_log(&dataset(INTEL), None).unwrap();
    let map = build_map(&log, &MapParams::default()).unwrap();
    let d = map.drift.estimate_vs_logged.unwrap();
    assert!(d.max_m < 1.5 && d.mean_m < 0.5, "{d:?}");
    let o = map.drift.odometry_vs_logged.unwrap();
    assert!(o.max_m > 10.0, "{o:?}");
    assert!((map.drift.path_m - 500.0).abs() < 10.0);
    // A map of the floor, about 26 m a side.
    let g = map.grid.geometry();
    let (w, h) = (
        f64::from(g.width) * g.resolution_m,
        f64::from(g.height) * g.resolution_m,
    );
    assert!(
        (25.0..50.0).contains(&w) && (25.0..50.0).contains(&h),
        "{w} x {h}"
    );
    let odometry = MapParams {
        matcher: Matcher::Odometry,
        ..MapParams::default()
    };
    let drifted = build_map(&log, &odometry).unwrap();
    assert_eq!(drifted.matched, 0);
    assert!(drifted.drift.estimate_vs_logged.unwrap().max_m > 10.0);
}

/// The map as it was at a time of the log holds only the scans up to it, and has frontiers.
#[test]
fn a_map_until_a_time_holds_the_scans_until_then() {
    let log = read_log(&dataset(CMU), None).unwrap();
    let params = MapParams {
        until_s: Some(30.0),
        ..MapParams::default()
    };
    let early = build_map(&log, &params).unwrap();
    let all = build_map(&log, &MapParams::default()).unwrap();
    assert!(early.scans < all.scans && early.scans > 50);
    assert!(early.trajectory.iter().all(|t| t.t_s <= 30.0));
    assert!(!early.frontiers(0.5).is_empty());
    assert!(early.grid.known_area_m2() < all.grid.known_area_m2());
}

/// A rosbag2 (MCAP storage) written by `rosbags` from the Duke log reads back as the same
/// scans and odometry, the laser's mount from /tf_static and `range_max` as the no-return value.
#[test]
fn a_rosbag2_written_by_rosbags_reads_as_the_log_it_came_from() {
    let python = std::env::var("USAR_PYTHON")
        .expect("USAR_PYTHON: a Python with rosbags; ./test.sh sets one up");
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("duke_bag");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/write_bag.py");
    let out = std::process::Command::new(&python)
        .arg(script)
        .arg(dataset(DUKE))
        .arg(&bag)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let from_bag = read_log(&bag, None).unwrap();
    let from_text = read_log(&dataset(DUKE), None).unwrap();
    assert_eq!(from_bag.format, LogFormat::Rosbag2);
    let (a, b) = (from_bag.scans().unwrap(), from_text.scans().unwrap());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.scan.ranges_m.len(), y.scan.ranges_m.len());
        for (&r, &q) in x.scan.ranges_m.iter().zip(&y.scan.ranges_m) {
            // Below range_min (0.05 m) the bag's reading is no reading.
            assert!(r == q || (q < 0.05 && r.is_nan()), "{r} vs {q}");
        }
        assert!((x.odometry.x - y.odometry.x).abs() < 1e-9);
        assert!((x.odometry.theta - y.odometry.theta).abs() < 1e-9);
        assert!((x.mount.x - 0.2).abs() < 1e-12);
        assert_eq!(x.scan.range_max_m, Some(8.1f32 as f64));
    }
    assert!((a[3].scan.t_s - 1.6).abs() < 1e-9);
    // The same bag as its .mcap file alone.
    let file = std::fs::read_dir(&bag)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "mcap"))
        .unwrap();
    assert_eq!(read_log(&file, None).unwrap().scan_count(), 551);
}

/// What `usar log import --out` writes reads back as the log: every scan with its odometry.
#[test]
fn a_log_exported_to_mcap_reads_back() {
    let log = read_log(&dataset(DUKE), None).unwrap();
    let mut bytes = std::io::Cursor::new(Vec::new());
    let n = usar_log::export::write_mcap(&log, &mut bytes).unwrap();
    assert_eq!(n, 1 + 4 * 551);
    let back = parse_log(bytes.get_ref(), "duke.mcap", LogFormat::Rosbag2).unwrap();
    let (a, b) = (back.scans().unwrap(), log.scans().unwrap());
    assert_eq!(a.len(), b.len());
    let threshold = log.summary().no_return_m.unwrap();
    for (x, y) in a.iter().zip(&b) {
        for (&r, &q) in x.scan.ranges_m.iter().zip(&y.scan.ranges_m) {
            assert!(
                r == q || (f64::from(q) >= threshold && r == f32::INFINITY),
                "{r} {q}"
            );
        }
        assert!((x.odometry.y - y.odometry.y).abs() < 1e-9);
    }
}

fn refused(text: &str, format: LogFormat) -> String {
    match parse_log(text.as_bytes(), "bad.log", format) {
        Err(e @ LogError::Record { .. }) => e.to_string(),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn bad_records_are_refused_with_their_line_and_what_was_expected() {
    let e = refused(
        "ODOM 0 0 0 0 0 0 1 h 1\nFLASER 3 1.0 2.0\n",
        LogFormat::Carmen,
    );
    assert!(e.starts_with("bad.log:2: FLASER:"), "{e}");
    assert!(e.contains("ends before"), "{e}");
    let e = refused("FLASER 99999999999 1\n", LogFormat::Carmen);
    assert!(
        e.contains("beam count") && e.contains("expected a whole number"),
        "{e}"
    );
    let e = refused("Odometry 1 x 0\n", LogFormat::DpSlam);
    assert!(e.contains("odometry y is \"x\""), "{e}");
    let e = refused("Laser 2 1 2 3\n", LogFormat::DpSlam);
    assert!(e.contains("more than the 2 readings"), "{e}");
    let e = refused("O 1 2 3 4\nQ 1\n", LogFormat::Thrun);
    assert!(
        e.starts_with("bad.log:2:") && e.contains("expected O or L"),
        "{e}"
    );
    let e = refused("ODOM nan 0 0 0 0 0 1 h 1\n", LogFormat::Carmen);
    assert!(e.contains("finite"), "{e}");
    // A log with no scan is refused as a whole.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("odometry_only.log");
    std::fs::write(&path, "ODOM 0 0 0 0 0 0 1 h 1\n").unwrap();
    assert!(matches!(
        read_log(&path, None),
        Err(LogError::NoScans { .. })
    ));
    std::fs::write(&path, "hello\nworld\n").unwrap();
    assert!(matches!(
        read_log(&path, None),
        Err(LogError::Unknown { .. })
    ));
    // Not an MCAP file.
    let e = parse_log(b"not a bag", "x.mcap", LogFormat::Rosbag2).unwrap_err();
    assert!(e.to_string().starts_with("x.mcap: not an MCAP file"), "{e}");
}

/// Readings of no value (0, NaN) are neither returns nor free space; a log's events keep
/// their file order.
#[test]
fn invalid_readings_draw_nothing() {
    let text = "Odometry 0 0 0\nLaser 3 0 nan 2.0\n";
    let log = parse_log(text.as_bytes(), "t.log", LogFormat::DpSlam).unwrap();
    assert!(matches!(log.events[0], LogEvent::Odometry { .. }));
    let map = build_map(&log, &MapParams::default()).unwrap();
    // One beam (the third, straight ahead at +90°) drew 2 m of free space and its hit.
    let known = map.grid.known_area_m2();
    assert!(known > 0.05 && known < 0.5, "{known}");
}

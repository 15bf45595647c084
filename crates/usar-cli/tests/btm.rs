//! `usar btm`: export, plan (robot limits, exit 3), merge, show, bad input.

use super::{assert_bad_input, usar, usar_json};

/// Start 1 — T junction 2 — slope 3 (20°, a 0.6 m wide passage) — dead end 4; and a wide detour
/// 2 — 5 — 4 with a 0.3 m step.
const MAP: &str = r#"{
  "format": "usar-btm", "version": 1,
  "nodes": [
    {"id": 1, "x_m": 0.0, "y_m": 0.0, "kind": "terminal", "subtype": "start"},
    {"id": 2, "x_m": 5.0, "y_m": 0.0, "kind": "divergence", "subtype": "t_junction"},
    {"id": 3, "x_m": 9.0, "y_m": 0.0, "kind": "obstacle", "subtype": "slope", "slope_inclination_rad": 0.349},
    {"id": 4, "x_m": 13.0, "y_m": 0.0, "kind": "divergence", "subtype": "dead_end"},
    {"id": 5, "x_m": 9.0, "y_m": 4.0, "kind": "divergence", "subtype": "corner"}
  ],
  "links": [
    {"id": 1, "start": 1, "end": 2, "searched": true, "direction_rad": 0.0, "length_m": 5.0, "min_width_m": 1.5},
    {"id": 2, "start": 2, "end": 3, "searched": true, "direction_rad": 0.0, "length_m": 4.0, "min_width_m": 0.6, "max_inclination_rad": 0.349},
    {"id": 3, "start": 3, "end": 4, "searched": true, "direction_rad": 0.0, "length_m": 4.0, "min_width_m": 0.6},
    {"id": 4, "start": 2, "end": 5, "searched": true, "direction_rad": 0.785, "length_m": 5.7, "min_width_m": 1.5},
    {"id": 5, "start": 5, "end": 4, "searched": true, "direction_rad": -0.785, "length_m": 5.7, "min_width_m": 1.5, "max_step_m": 0.3}
  ]
}"#;

#[test]
fn plan_respects_each_robots_limits_and_exits_3_without_a_route() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("m.json");
    std::fs::write(&json, MAP).unwrap();
    let db = dir.path().join("m.sqlite");
    let out = usar(&[
        "btm",
        "export",
        json.to_str().unwrap(),
        "--out",
        db.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["links_searched"], 5);
    assert_eq!(v["nodes"][1]["links"], 3);
    // The crawler climbs the slope (0.6 m passage, 20°): the short way.
    let plan = |robot: &str| {
        usar(&[
            "btm",
            "plan",
            db.to_str().unwrap(),
            "--robot",
            robot,
            "--from",
            "1",
            "--to",
            "13,0",
            "--json",
        ])
    };
    let crawler = plan("crawler");
    assert!(
        crawler.status.success(),
        "{}",
        String::from_utf8_lossy(&crawler.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&crawler.stdout).unwrap();
    assert_eq!(v["route"]["nodes"], serde_json::json!([1, 2, 3, 4]));
    // The wheeled robot can take neither the slope nor the step.
    let wheeled = plan("wheeled");
    assert_eq!(wheeled.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&wheeled.stderr);
    assert!(stderr.contains("no route for robot wheeled"), "{stderr}");
    assert!(
        stderr.contains("slope") || stderr.contains("inclines"),
        "{stderr}"
    );
}

#[test]
fn merge_show_and_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.json");
    std::fs::write(&a, MAP).unwrap();
    let merged = dir.path().join("g.graphml");
    let out = usar(&[
        "btm",
        "merge",
        a.to_str().unwrap(),
        a.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (v["nodes"].as_u64(), v["links"].as_u64()),
        (Some(5), Some(5))
    );
    assert!(
        std::fs::read_to_string(&merged)
            .unwrap()
            .contains("<graphml")
    );
    for ext in ["png", "svg"] {
        let f = dir.path().join(format!("m.{ext}"));
        let out = usar(&[
            "btm",
            "show",
            a.to_str().unwrap(),
            "--out",
            f.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(std::fs::metadata(&f).unwrap().len() > 100);
    }
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, MAP.replace("\"end\": 4", "\"end\": 44")).unwrap();
    assert_bad_input(
        &usar(&["btm", "export", bad.to_str().unwrap(), "--json"]),
        "bad.json: link 3 field `end`: found node 44, which does not exist",
    );
    let junk = dir.path().join("junk.sqlite");
    std::fs::write(&junk, "junk").unwrap();
    assert_bad_input(
        &usar(&["btm", "export", junk.to_str().unwrap()]),
        "not a BTM database",
    );
}

fn count(v: &serde_json::Value, key: &str) -> u64 {
    v["nodes_by_kind"][key].as_u64().unwrap_or(0)
}

#[test]
fn build_on_the_course_reports_nodes_links_and_a_map_100_times_smaller_than_the_grid() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("course.sqlite");
    let png = dir.path().join("course.png");
    let trace = dir.path().join("trace.csv");
    let v = usar_json(&[
        "btm",
        "build",
        "--scene",
        "course",
        "--robot",
        "crawler",
        "--seed",
        "2",
        "--out",
        db.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
        "--trace",
        trace.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["stop"], "explored");
    assert_eq!(v["links_unsearched"], 0);
    assert!(v["links_searched"].as_u64().unwrap() >= 10);
    for kind in [
        "divergence/t_junction",
        "divergence/crossing",
        "divergence/corner",
        "divergence/dead_end",
        "free_space/entrance",
        "free_space/exit",
        "obstacle/slope",
        "obstacle/stairs",
        "terminal/start",
        "terminal/end",
    ] {
        assert!(
            count(&v, kind) >= 1,
            "no {kind} node: {}",
            v["nodes_by_kind"]
        );
    }
    // Every node has id, kind, x, y; every link its ends, status and measures.
    for n in v["nodes"].as_array().unwrap() {
        assert!(n["id"].is_u64() && n["kind"].is_string() && n["x_m"].is_f64());
    }
    for l in v["links"].as_array().unwrap() {
        assert!(l["end"].is_u64() && l["searched"] == true && l["min_width_m"].is_f64());
    }
    let bytes = &v["bytes"];
    assert!(
        bytes["grid_over_binary"].as_f64().unwrap() >= 100.0,
        "{bytes}"
    );
    // The database is complete (no .partial left) and holds the same map.
    assert!(!dir.path().join("course.sqlite.partial").exists());
    let exported = usar_json(&["btm", "export", db.to_str().unwrap(), "--json"]);
    assert_eq!(exported["nodes"], v["nodes"]);
    assert_eq!(exported["links"], v["links"]);
    // The binary form round-trips to the same topology.
    let btmb = dir.path().join("course.btmb");
    usar_json(&[
        "btm",
        "export",
        db.to_str().unwrap(),
        "--out",
        btmb.to_str().unwrap(),
        "--json",
    ]);
    let back = usar_json(&["btm", "export", btmb.to_str().unwrap(), "--json"]);
    assert_eq!(back["nodes_by_kind"], v["nodes_by_kind"]);
    assert_eq!(
        back["links"].as_array().unwrap().len(),
        v["links"].as_array().unwrap().len()
    );
    assert_eq!(
        std::fs::metadata(&btmb).unwrap().len(),
        bytes["btm_binary"].as_u64().unwrap()
    );
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
    let csv = std::fs::read_to_string(&trace).unwrap();
    assert!(csv.starts_with("time_s,est_x_m"));
    assert!(csv.lines().count() > 100);
}

/// Corridor junctions of the Willow Garage floor (read off `willow-full.pgm`, 0.1 m pixels,
/// origin at its lower-left corner; a pixel is free at 206 and above, as the loader reads it):
/// - the south corridor (y ≈ 20.9 m, x 13–38 m) meets the west corridor running north at
///   x ≈ 20.8 m and crosses the corridor at x ≈ 35.7 m running south;
/// - the bottom corridor (y ≈ 9.7 m, x 2–34 m) meets the two lanes of the hall west of the
///   central block (x ≈ 16.9 m and x ≈ 19.4 m) that lead up to the south corridor;
/// - the north corridor (free from y 44.7 to 45.9 m at x = 40 m: centre 45.3 m) ends in the
///   lobby at the top of the east corridor (free from x 45.7 to 48.1 m at y = 41 m: centre
///   46.9 m);
/// - the east corridor meets the hall running west to the centre of the floor (free from
///   y 36.1 to 37.9 m at x = 44 m: centre 37.0 m);
/// - the south corridor, carried on through the open-plan room east of x ≈ 37 m, crosses the
///   east corridor's southern half (free from x 50.3 to 51.8 m at y = 16 m: centre 51.0 m;
///   the south corridor free from y 20.0 to 22.0 m at x = 25 m: centre 21.0 m);
/// - the east corridor meets the south-east hall at its southern end (the hall free from
///   y 9.0 to 12.0 m at x = 47–49 m: centre 10.5 m); the junction is as wide as the hall, and
///   the robot's node there lies on its west side (0.75 m from the centre with seed 1).
const WILLOW_JUNCTIONS: [(f64, f64); 8] = [
    (20.8, 20.9),
    (35.7, 20.8),
    (19.4, 9.7),
    (16.9, 9.7),
    (46.9, 45.3),
    (46.9, 37.0),
    (51.0, 21.0),
    (51.0, 10.5),
];

#[test]
fn build_on_the_real_willow_garage_floor_finds_its_corridor_junctions() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("willow.sqlite");
    let config = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/btm-real-floor.toml"
    );
    let v = usar_json(&[
        "btm",
        "build",
        "--scene",
        super::shared("ros/willow-full.pgm").to_str().unwrap(),
        "--resolution",
        "0.1",
        "--config",
        config,
        "--out",
        db.to_str().unwrap(),
        "--json",
    ]);
    let divergences: Vec<(f64, f64)> = v["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|n| n["kind"] == "divergence")
        .map(|n| (n["x_m"].as_f64().unwrap(), n["y_m"].as_f64().unwrap()))
        .collect();
    for (x, y) in WILLOW_JUNCTIONS {
        let nearest = divergences
            .iter()
            .map(|(a, b)| (a - x).hypot(b - y))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1.0,
            "junction ({x}, {y}): nearest divergence node {nearest:.2} m away"
        );
    }
    // A 2-D floor plan has walls and furniture, no slopes or stairs.
    let kinds = v["nodes_by_kind"].as_object().unwrap();
    assert!(
        kinds.keys().all(|k| !k.starts_with("obstacle")),
        "{kinds:?}"
    );
    // The robot maps the whole corridor network without touching anything: it localises on
    // its own map, takes only gaps a lane a little wider than itself runs through, and backs
    // out of passages too narrow to turn in (seed 1; seeds 2 and 3 measured 0 too, with
    // position errors of 0.26 and 0.21 m).
    assert_eq!(v["collisions"], 0, "collisions");
    assert!(
        v["links_searched"].as_u64().unwrap() >= 60,
        "{}",
        v["links_searched"]
    );
    assert_eq!(v["links_unsearched"], 0);
    assert!(v["max_position_error_m"].as_f64().unwrap() < 0.5);
    assert!(v["bytes"]["grid_over_binary"].as_f64().unwrap() >= 100.0);
}

#[test]
fn build_with_bad_input_is_an_error_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("x.sqlite");
    let config = dir.path().join("bad.toml");
    // An unknown field and an out-of-range value, each named in the error.
    for (text, field) in [
        ("passage_margin = 0.3\n", "passage_margin"),
        ("dt_s = -1.0\n", "dt_s"),
    ] {
        std::fs::write(&config, text).unwrap();
        let out = usar(&[
            "btm",
            "build",
            "--config",
            config.to_str().unwrap(),
            "--out",
            db.to_str().unwrap(),
        ]);
        assert_bad_input(&out, field);
    }
    // A start pose inside a wall of the course.
    let out = usar(&[
        "btm",
        "build",
        "--start",
        "0,0",
        "--out",
        db.to_str().unwrap(),
    ]);
    assert_bad_input(&out, "course");
    assert!(!db.exists());
    assert!(!dir.path().join("x.sqlite.partial").exists());
}

#[test]
fn a_bad_map_in_any_form_is_exit_2_with_one_line_naming_the_file_the_item_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    // A link of negative length (once planned through as a shortcut).
    let json = dir.path().join("negative.json");
    std::fs::write(
        &json,
        MAP.replace("\"length_m\": 5.0", "\"length_m\": -77.99"),
    )
    .unwrap();
    let out = usar(&[
        "btm",
        "plan",
        json.to_str().unwrap(),
        "--from",
        "1",
        "--to",
        "4",
    ]);
    assert_bad_input(
        &out,
        &format!(
            "{}: link 1 field `length_m`: found -77.99, expected a finite distance",
            json.display()
        ),
    );
    // An infinite coordinate in a database (once exported to a file that could not be read).
    let db = dir.path().join("inf.sqlite");
    let mut btm = usar_btm::exchange::from_json(MAP, "m.json").unwrap();
    btm.nodes[1].x_m = f64::INFINITY;
    usar_btm::BtmStore::create(&db)
        .unwrap()
        .put_all(&btm)
        .unwrap();
    let out = usar(&[
        "btm",
        "export",
        db.to_str().unwrap(),
        "--out",
        dir.path().join("x.json").to_str().unwrap(),
    ]);
    assert_bad_input(&out, "inf.sqlite: node 2 field `x_m`: found inf");
    assert!(!dir.path().join("x.json").exists());
    // A negative width and a link to a missing node in the binary form.
    let mut btm = usar_btm::exchange::from_json(MAP, "m.json").unwrap();
    btm.links[2].min_width_m = Some(-0.6);
    let btmb = dir.path().join("w.btmb");
    std::fs::write(&btmb, usar_btm::wire::encode(&btm)).unwrap();
    assert_bad_input(
        &usar(&[
            "btm",
            "show",
            btmb.to_str().unwrap(),
            "--out",
            dir.path().join("w.svg").to_str().unwrap(),
        ]),
        "w.btmb: link 3 field `min_width_m`: found -0.6",
    );
    // A binary map declaring a billion nodes in a few bytes.
    let huge = dir.path().join("huge.btmb");
    std::fs::write(&huge, b"BTMB\x01\x00\x80\x94\xeb\xdc\x03").unwrap();
    assert_bad_input(
        &usar(&["btm", "export", huge.to_str().unwrap(), "--json"]),
        "1000000000 nodes, expected at most 1000000",
    );
}

#[test]
fn export_json_has_the_fields_its_help_and_the_docs_name() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("m.json");
    std::fs::write(
        &json,
        MAP.replace(
            "\"kind\": \"divergence\", \"subtype\": \"corner\"",
            "\"kind\": \"gas_leak\"",
        ),
    )
    .unwrap();
    let out = usar(&["btm", "export", json.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let keys =
        |o: &serde_json::Value| -> Vec<String> { o.as_object().unwrap().keys().cloned().collect() };
    assert_eq!(
        keys(&v),
        [
            "links",
            "links_searched",
            "links_unsearched",
            "nodes",
            "nodes_by_kind"
        ]
    );
    assert_eq!(
        keys(&v["nodes"][0]),
        [
            "id",
            "kind",
            "link_angles_rad",
            "links",
            "max_robot_inclination_rad",
            "operator_note",
            "slope_inclination_rad",
            "step_height_m",
            "subtype",
            "x_m",
            "y_m"
        ]
    );
    assert_eq!(
        keys(&v["links"][0]),
        [
            "direction_rad",
            "end",
            "id",
            "length_m",
            "max_inclination_rad",
            "max_step_m",
            "min_width_m",
            "searched",
            "start"
        ]
    );
    assert_eq!(v["nodes_by_kind"]["gas_leak"], 1, "an unknown kind is kept");
    let help = usar(&["btm", "export", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout).replace(char::is_whitespace, "");
    for field in ["`kind`", "`x_m`", "`y_m`", "`searched`", "`nodes_by_kind`"] {
        assert!(help.contains(field), "{field} not in the help: {help}");
    }
    for old in ["type,", "x,y", "status"] {
        assert!(!help.contains(old), "{old} in the help: {help}");
    }
    let docs = include_str!("../../../docs/btm-format.md");
    for field in ["`x_m`", "`kind`", "`searched`", "`link_angles_rad`"] {
        assert!(docs.contains(field), "{field} not in docs/btm-format.md");
    }
    // The text summary names the kinds this version does not know.
    let out = usar(&["btm", "export", json.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("kept as read: gas_leak ×1"), "{text}");
}

//! `usar btm`: export, plan (robot limits, exit 3), merge, show, bad input.

use super::{assert_bad_input, usar};

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
        "node 44 does not exist",
    );
    let junk = dir.path().join("junk.sqlite");
    std::fs::write(&junk, "junk").unwrap();
    assert_bad_input(
        &usar(&["btm", "export", junk.to_str().unwrap()]),
        "not a BTM database",
    );
}

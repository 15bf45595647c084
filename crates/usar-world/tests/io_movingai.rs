//! MovingAI `.map` and `.scen` loading: the real benchmark files in `../shared/maps/movingai/`,
//! the row flip to our bottom-up convention, the scene conversion, and every error path.

use std::path::{Path, PathBuf};
use usar_world::io::movingai::{
    parse_movingai_map, parse_scenarios, read_movingai_map, read_scenarios,
};
use usar_world::{Cell, WorldError, obstacle};

/// The shared MovingAI folder (`/work/shared/maps/movingai` beside the repository).
fn movingai_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/maps/movingai")
}

fn map_err(text: &str) -> String {
    let err = parse_movingai_map(text, Path::new("bad.map")).expect_err("must be rejected");
    let message = err.to_string();
    assert!(message.starts_with("bad.map: "), "{message}");
    message
}

fn scen_err(text: &str) -> String {
    let err = parse_scenarios(text, Path::new("bad.scen")).expect_err("must be rejected");
    let message = err.to_string();
    assert!(message.starts_with("bad.scen: "), "{message}");
    message
}

#[test]
fn real_maps_load_with_the_top_file_row_as_our_top_row() {
    for (name, side) in [
        ("16room_000.map", 512),
        ("8room_000.map", 512),
        ("maze512-4-0.map", 512),
        ("maze-32-32-2.map", 32),
        ("room-32-32-4.map", 32),
    ] {
        let path = movingai_dir().join(name);
        let map = read_movingai_map(&path).unwrap();
        assert_eq!((map.width, map.height), (side, side), "{name}");
        // Compare every cell with the raw text, independently of the loader.
        let text = std::fs::read_to_string(&path).unwrap();
        let rows: Vec<&str> = text
            .lines()
            .skip(4)
            .map(|l| l.trim_end_matches('\r'))
            .collect();
        assert_eq!(rows.len(), side as usize, "{name}");
        let mut passable = 0;
        for (y, row) in rows.iter().enumerate() {
            for (x, ch) in row.chars().enumerate() {
                let free = matches!(ch, '.' | 'G');
                passable += usize::from(free);
                assert_eq!(
                    map.is_passable_at(x as u32, y as u32),
                    free,
                    "{name} ({x}, {y})"
                );
                assert_eq!(
                    map.passable[Cell::new(x as i32, side as i32 - 1 - y as i32)],
                    free
                );
            }
        }
        assert_eq!(
            map.passable.as_slice().iter().filter(|&&p| p).count(),
            passable,
            "{name}"
        );
        assert!(passable > 0, "{name}");
    }
}

#[test]
fn cell_of_flips_rows_and_keeps_columns() {
    let map = parse_movingai_map(
        "type octile\nheight 3\nwidth 2\nmap\n.@\n..\n@.\n",
        Path::new("m.map"),
    )
    .unwrap();
    assert_eq!(map.cell_of(0, 0), Cell::new(0, 2));
    assert_eq!(map.cell_of(1, 2), Cell::new(1, 0));
    assert!(!map.passable[Cell::new(1, 2)]);
    assert!(!map.passable[Cell::new(0, 0)]);
    assert!(map.passable[Cell::new(1, 0)]);
    assert!(!map.is_passable_at(5, 0));
    assert_eq!(map.blocked().as_slice().iter().filter(|&&b| b).count(), 2);
}

#[test]
fn crlf_line_endings_read_like_lf() {
    let lf = "type octile\nheight 2\nwidth 4\nmap\n.@TG\nOSW.\n";
    let crlf = lf.replace('\n', "\r\n");
    let a = parse_movingai_map(lf, Path::new("a.map")).unwrap();
    let b = parse_movingai_map(&crlf, Path::new("b.map")).unwrap();
    assert_eq!(a, b);
    // '.' and 'G' passable; '@', 'O', 'T', 'S', 'W' blocked.
    let free: Vec<bool> = (0..4).map(|x| a.is_passable_at(x, 0)).collect();
    assert_eq!(free, [true, false, false, true]);
    let free: Vec<bool> = (0..4).map(|x| a.is_passable_at(x, 1)).collect();
    assert_eq!(free, [false, false, false, true]);
}

#[test]
fn crlf_file_on_disk_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("crlf.map");
    std::fs::write(&path, "type octile\r\nheight 1\r\nwidth 2\r\nmap\r\n.@\r\n").unwrap();
    let map = read_movingai_map(&path).unwrap();
    assert!(map.is_passable_at(0, 0) && !map.is_passable_at(1, 0));
}

#[test]
fn bad_header_is_rejected_naming_the_line() {
    let m = map_err("type tile\nheight 1\nwidth 1\nmap\n.\n");
    assert!(m.contains("line 1") && m.contains("type octile"), "{m}");
    let m = map_err("type octile\nheight x\nwidth 1\nmap\n.\n");
    assert!(m.contains("line 2") && m.contains("height"), "{m}");
    let m = map_err("type octile\nheight 0\nwidth 1\nmap\n");
    assert!(m.contains("line 2"), "{m}");
    let m = map_err("type octile\nheight 1\ncolour 3\nmap\n.\n");
    assert!(m.contains("line 3") && m.contains("colour 3"), "{m}");
    let m = map_err("type octile\nheight 1\nmap\n.\n");
    assert!(m.contains("`width` is missing"), "{m}");
    let m = map_err("type octile\nheight 1\nwidth 1\n");
    assert!(m.contains("end of file") && m.contains("map"), "{m}");
    let m = map_err("");
    assert!(m.contains("type octile"), "{m}");
    let m = map_err("type octile\nheight 100000\nwidth 100000\nmap\n");
    assert!(m.contains("at most"), "{m}");
}

#[test]
fn short_or_long_row_is_rejected_naming_the_line() {
    let m = map_err("type octile\nheight 2\nwidth 3\nmap\n...\n..\n");
    assert!(
        m.contains("line 6") && m.contains("2 characters, expected 3"),
        "{m}"
    );
    let m = map_err("type octile\nheight 1\nwidth 3\nmap\n....\n");
    assert!(m.contains("line 5") && m.contains("4 characters"), "{m}");
}

#[test]
fn unknown_terrain_character_is_rejected_naming_line_and_column() {
    let m = map_err("type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n");
    assert!(m.contains("line 6, column 2") && m.contains("'x'"), "{m}");
}

#[test]
fn missing_and_extra_rows_are_rejected() {
    let m = map_err("type octile\nheight 3\nwidth 1\nmap\n.\n.\n");
    assert!(m.contains("found 2 map rows, expected 3"), "{m}");
    let m = map_err("type octile\nheight 1\nwidth 1\nmap\n.\n.\n");
    assert!(m.contains("line 6") && m.contains("more than 1"), "{m}");
    // Trailing blank lines are fine.
    parse_movingai_map(
        "type octile\nheight 1\nwidth 1\nmap\n.\n\n\n",
        Path::new("ok.map"),
    )
    .unwrap();
}

#[test]
fn missing_map_file_is_an_io_error_naming_it() {
    let err = read_movingai_map("/nonexistent/x.map").unwrap_err();
    assert!(matches!(err, WorldError::Io { .. }));
    assert!(err.to_string().contains("/nonexistent/x.map"));
}

#[test]
fn to_scene_walls_blocked_cells_and_starts_in_the_largest_component() {
    // Bottom row (our row 0) holds a one-cell pocket at x = 0, cut off by walls; the big region
    // is on the right. Row-major order (bottom row first) meets the pocket first.
    let text = "type octile\nheight 3\nwidth 5\nmap\n@@...\n@@...\n.@...\n";
    let map = parse_movingai_map(text, Path::new("m.map")).unwrap();
    let scene = map.to_scene("pocket", 0.5).unwrap();
    assert_eq!(scene.geometry().resolution_m, 0.5);
    assert_eq!((scene.geometry().width, scene.geometry().height), (5, 3));
    for (cell, &p) in map.passable.iter_cells() {
        let expected = if p { obstacle::NONE } else { obstacle::WALL };
        assert_eq!(scene.obstacle[cell], expected, "{cell:?}");
    }
    assert_eq!(scene.start_poses.len(), 1);
    let start = scene.start_poses[0];
    // First cell of the big component in row-major order: (2, 0), centre (1.25, 0.25).
    assert!(
        (start.x - 1.25).abs() < 1e-12 && (start.y - 0.25).abs() < 1e-12,
        "{start:?}"
    );
    assert_eq!(scene.provenance.source, "import");
    assert!((scene.reachable_area_m2() - 9.0 * 0.25).abs() < 1e-12);

    let err = map.to_scene("x", 0.0).unwrap_err().to_string();
    assert!(err.contains("resolution_m"), "{err}");
    let all_blocked =
        parse_movingai_map("type octile\nheight 1\nwidth 1\nmap\n@\n", Path::new("b"))
            .unwrap()
            .to_scene("b", 1.0)
            .unwrap();
    assert!(all_blocked.start_poses.is_empty());
}

#[test]
fn real_scenario_files_parse_completely() {
    for (name, count) in [
        ("16room_000.map.scen", 1860),
        ("8room_000.map.scen", 1940),
        ("maze-32-32-2-random-1.scen", 333),
        ("maze512-4-0.map.scen", 9730),
        ("room-32-32-4-random-1.scen", 341),
    ] {
        let scenarios = read_scenarios(movingai_dir().join(name)).unwrap();
        assert_eq!(scenarios.len(), count, "{name}");
        assert!(
            scenarios
                .iter()
                .all(|s| s.optimal_length >= 0.0 && s.line >= 2),
            "{name}"
        );
    }
    let maze = read_scenarios(movingai_dir().join("maze-32-32-2-random-1.scen")).unwrap();
    let first = &maze[0];
    assert_eq!(first.bucket, 16);
    assert_eq!(first.map, "maze-32-32-2.map");
    assert_eq!((first.width, first.height), (32, 32));
    assert_eq!((first.start, first.goal), ((15, 2), (1, 27)));
    assert_eq!(first.optimal_length, 64.31370850);
    assert_eq!(first.line, 2);
    let rooms = read_scenarios(movingai_dir().join("16room_000.map.scen")).unwrap();
    assert_eq!(rooms[0].map, "maps/rooms/16room_000.map");
}

#[test]
fn scenario_versions_one_and_one_point_zero_are_accepted() {
    let row = "0\tm.map\t4\t4\t0\t1\t2\t3\t3.5\n";
    for header in ["version 1\n", "version 1.0\n", "version 1\r\n"] {
        let s = parse_scenarios(&format!("{header}{row}"), Path::new("a.scen")).unwrap();
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].start, (0, 1));
        assert_eq!(s[0].goal, (2, 3));
    }
    let err = parse_scenarios(&format!("version 2\n{row}"), Path::new("a.scen")).unwrap_err();
    assert!(
        matches!(err, WorldError::UnsupportedVersion { .. }),
        "{err}"
    );
    let m = scen_err(&format!("0\tm.map\n{row}"));
    assert!(m.contains("line 1") && m.contains("version 1"), "{m}");
    let m = scen_err("");
    assert!(m.contains("version 1"), "{m}");
}

#[test]
fn bad_scenario_rows_are_rejected_naming_line_and_column() {
    let m = scen_err("version 1\n0\tm.map\t4\t4\t0\t1\t2\t3\t3.5\n0\tm.map\t4\t4\tx\t1\t2\t3\t1\n");
    assert!(
        m.contains("line 3, column 5 (start x)") && m.contains("`x`"),
        "{m}"
    );
    let m = scen_err("version 1\n0\tm.map\t4\t4\t0\t1\t2\t3\tlong\n");
    assert!(m.contains("line 2, column 9 (optimal length)"), "{m}");
    let m = scen_err("version 1\n0\tm.map\t4\t4\t0\t1\t2\n");
    assert!(m.contains("line 2") && m.contains("found 7"), "{m}");
    let m = scen_err("version 1\n0\tm.map\t4\t4\t0\t4\t2\t3\t1\n");
    assert!(
        m.contains("column 6 (start y)") && m.contains("below the map height 4"),
        "{m}"
    );
    let m = scen_err("version 1\n-1\tm.map\t4\t4\t0\t1\t2\t3\t1\n");
    assert!(m.contains("column 1 (bucket)"), "{m}");
    let m = scen_err("version 1\n0\t\t4\t4\t0\t1\t2\t3\t1\n");
    assert!(m.contains("column 2 (map)"), "{m}");
}

#[test]
fn missing_scenario_file_is_an_io_error_naming_it() {
    let err = read_scenarios("/nonexistent/y.scen").unwrap_err();
    assert!(err.to_string().contains("/nonexistent/y.scen"));
}

//! Maps read from files are checked on every load path (SQLite, JSON, `.btmb`): each class of
//! bad value is refused with one line naming the file, the node or link, the field, what was
//! found and what was expected; huge declared counts are refused before anything is allocated.

use std::path::Path;
use usar_btm::exchange::{read, to_json};
use usar_btm::model::{kind, subtype};
use usar_btm::validate::MAX_NODES;
use usar_btm::{Btm, BtmStore, Link, Node, wire};

/// Start 1 — T junction 2 — slope 3, and an un-searched branch at 2.
fn sample() -> Btm {
    let mut slope = Node::new(3, 9.0, 0.0, kind::OBSTACLE, Some(subtype::SLOPE));
    slope.slope_inclination_rad = Some(0.3);
    slope.max_robot_inclination_rad = Some(0.32);
    let searched = |id, start, end, len| Link {
        searched: true,
        end: Some(end),
        length_m: Some(len),
        min_width_m: Some(1.2),
        max_inclination_rad: Some(0.3),
        max_step_m: Some(0.0),
        ..Link::unsearched(id, start, 0.0)
    };
    Btm {
        nodes: vec![
            Node::new(1, 0.0, 0.0, kind::TERMINAL, Some(subtype::START)),
            Node::new(2, 5.0, 0.0, kind::DIVERGENCE, Some(subtype::T_JUNCTION)),
            slope,
        ],
        links: vec![
            searched(1, 1, 2, 5.0),
            searched(2, 2, 3, 4.0),
            Link::unsearched(3, 2, 1.57),
        ],
    }
}

/// Where a bad value can be stored: JSON cannot hold a non-finite number (its writer puts
/// `null`), SQLite neither NaN (it stores NULL) nor two rows with one id, and our store
/// enforces its foreign keys (links to missing nodes in a database written by another tool:
/// [`a_database_with_values_of_the_wrong_type_names_the_row_and_column`]).
#[derive(Clone, Copy, PartialEq)]
enum Holds {
    All,
    NotJson,
    NotJsonNorSqlite,
    NotSqlite,
}

type Mutation = fn(&mut Btm);

/// Every class of bad value: what to break, where it can be stored, and the start of the
/// message and what it expects.
fn broken() -> Vec<(Mutation, Holds, &'static str, &'static str)> {
    vec![
        (
            |b| b.links[0].length_m = Some(-77.99),
            Holds::All,
            "link 1 field `length_m`: found -77.9",
            "expected a finite distance from 0 to 1000000 m",
        ),
        (
            |b| b.nodes[1].x_m = f64::INFINITY,
            Holds::NotJson,
            "node 2 field `x_m`: found inf",
            "expected a finite coordinate within ±1000000 m",
        ),
        (
            |b| b.nodes[1].y_m = -3.0e7,
            Holds::All,
            "node 2 field `y_m`: found -30000000",
            "expected a finite coordinate",
        ),
        (
            |b| b.nodes[0].x_m = f64::NAN,
            Holds::NotJsonNorSqlite,
            "node 1 field `x_m`: found NaN",
            "expected a finite coordinate",
        ),
        (
            |b| b.links[1].min_width_m = Some(-0.5),
            Holds::All,
            "link 2 field `min_width_m`: found -0.5",
            "expected a finite distance",
        ),
        (
            |b| b.links[1].max_inclination_rad = Some(-0.1),
            Holds::All,
            "link 2 field `max_inclination_rad`: found -0.1",
            "expected a finite inclination from 0 to π rad",
        ),
        (
            |b| b.links[0].max_step_m = Some(f64::INFINITY),
            Holds::NotJson,
            "link 1 field `max_step_m`: found inf",
            "expected a finite distance",
        ),
        (
            |b| b.links[2].direction_rad = f64::NEG_INFINITY,
            Holds::NotJson,
            "link 3 field `direction_rad`: found -inf",
            "expected a finite angle",
        ),
        (
            |b| b.nodes[2].slope_inclination_rad = Some(2.0),
            Holds::All,
            "node 3 field `slope_inclination_rad`: found 2",
            "expected a finite inclination from 0 to π/2 rad",
        ),
        (
            |b| b.nodes[2].step_height_m = Some(-0.2),
            Holds::All,
            "node 3 field `step_height_m`: found -0.2",
            "expected a finite distance",
        ),
        (
            |b| b.nodes[0].kind = String::new(),
            Holds::All,
            "node 1 field `kind`: found \"\"",
            "expected a name of 1–64 ASCII letters, digits",
        ),
        (
            |b| b.nodes[1].subtype = Some("<b>t junction</b>".into()),
            Holds::All,
            "node 2 field `subtype`: found \"<b>t junction</b>\"",
            "expected a name",
        ),
        (
            |b| b.links[1].start = 99,
            Holds::NotSqlite,
            "link 2 field `start`: found node 99, which does not exist",
            "expected the id of a node of the map",
        ),
        (
            |b| b.links[0].end = Some(42),
            Holds::NotSqlite,
            "link 1 field `end`: found node 42, which does not exist",
            "expected the id of a node of the map",
        ),
        (
            |b| b.nodes[2].id = 1,
            Holds::NotSqlite,
            "node 1 field `id`: found a second node with this id",
            "expected unique node ids",
        ),
        (
            |b| b.links[2].id = 2,
            Holds::NotSqlite,
            "link 2 field `id`: found a second link with this id",
            "expected unique link ids",
        ),
    ]
}

fn write_sqlite(path: &Path, btm: &Btm) {
    let mut store = BtmStore::create(path).unwrap();
    store.put_all(btm).unwrap();
}

fn refused(path: &Path, start: &str, expected: &str) {
    let err = read(path).expect_err(start).to_string();
    assert!(
        err.starts_with(&format!("{}: ", path.display())),
        "names the file: {err}"
    );
    assert!(err.contains(start), "{start:?} not in {err}");
    assert!(err.contains(expected), "{expected:?} not in {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn every_class_of_bad_value_is_refused_on_every_load_path() {
    let dir = tempfile::tempdir().unwrap();
    // The sample itself loads from every form.
    let good = sample();
    let json = dir.path().join("good.json");
    std::fs::write(&json, to_json(&good)).unwrap();
    assert_eq!(read(&json).unwrap(), good);
    let db = dir.path().join("good.sqlite");
    write_sqlite(&db, &good);
    assert_eq!(read(&db).unwrap(), good);
    let btmb = dir.path().join("good.btmb");
    std::fs::write(&btmb, wire::encode(&good)).unwrap();
    assert_eq!(read(&btmb).unwrap().nodes.len(), 3);

    for (i, (mutate, holds, start, expected)) in broken().into_iter().enumerate() {
        let mut btm = sample();
        mutate(&mut btm);
        if !matches!(holds, Holds::NotJson | Holds::NotJsonNorSqlite) {
            let path = dir.path().join(format!("bad{i}.json"));
            std::fs::write(&path, to_json(&btm)).unwrap();
            refused(&path, start, expected);
        }
        if !matches!(holds, Holds::NotSqlite | Holds::NotJsonNorSqlite) {
            let path = dir.path().join(format!("bad{i}.sqlite"));
            write_sqlite(&path, &btm);
            refused(&path, start, expected);
        }
        let path = dir.path().join(format!("bad{i}.btmb"));
        std::fs::write(&path, wire::encode(&btm)).unwrap();
        refused(&path, start, expected);
    }
}

#[test]
fn a_database_with_values_of_the_wrong_type_names_the_row_and_column() {
    let dir = tempfile::tempdir().unwrap();
    for (i, (sql, start, expected)) in [
        (
            "UPDATE nodes SET x_m = 1e999 WHERE id = 2",
            "node 2 field `x_m`: found inf",
            "expected a finite coordinate",
        ),
        (
            "UPDATE nodes SET y_m = 'north' WHERE id = 3",
            "node 3 field `y_m`: found text \"north\"",
            "expected a number",
        ),
        (
            "UPDATE links SET searched = 7 WHERE id = 1",
            "link 1 field `searched`: found 7",
            "expected 0 or 1",
        ),
        (
            "UPDATE links SET \"end\" = -4 WHERE id = 2",
            "link 2 field `end`: found -4",
            "expected an id from 0 to 4294967295",
        ),
        (
            "UPDATE nodes SET id = -1 WHERE id = 1",
            "node in row 1 field `id`: found -1",
            "expected an id from 0 to 4294967295",
        ),
        (
            "UPDATE nodes SET extra = '[1, 2]' WHERE id = 1",
            "node 1 field `extra`: found text \"[1, 2]\"",
            "expected a JSON object",
        ),
        (
            "UPDATE links SET length_m = -77.99 WHERE id = 2",
            "link 2 field `length_m`: found -77.99",
            "expected a finite distance",
        ),
        (
            "UPDATE links SET start = 99 WHERE id = 2",
            "link 2 field `start`: found node 99, which does not exist",
            "expected the id of a node of the map",
        ),
        (
            "DELETE FROM nodes WHERE id = 3",
            "link 2 field `end`: found node 3, which does not exist",
            "expected the id of a node of the map",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let path = dir.path().join(format!("m{i}.sqlite"));
        write_sqlite(&path, &sample());
        // As another tool would (the sqlite3 shell does not enforce foreign keys).
        rusqlite::Connection::open(&path)
            .unwrap()
            .execute_batch(&format!("PRAGMA foreign_keys = OFF; {sql}"))
            .unwrap();
        refused(&path, start, expected);
    }
}

#[test]
fn unknown_kinds_load_and_are_kept_as_read() {
    let dir = tempfile::tempdir().unwrap();
    let mut btm = sample();
    btm.nodes[1].kind = "gas_leak".into();
    btm.nodes[1].subtype = Some("Level-3".into());
    assert!(!kind::is_known("gas_leak") && kind::is_known(kind::HAZARD));
    for ext in ["json", "sqlite", "btmb"] {
        let path = dir.path().join(format!("m.{ext}"));
        match ext {
            "json" => std::fs::write(&path, to_json(&btm)).unwrap(),
            "sqlite" => write_sqlite(&path, &btm),
            _ => std::fs::write(&path, wire::encode(&btm)).unwrap(),
        }
        let back = read(&path).unwrap();
        assert_eq!(back.nodes[1].kind, "gas_leak", "{ext}");
        assert_eq!(back.nodes[1].subtype.as_deref(), Some("Level-3"), "{ext}");
    }
}

#[test]
fn a_json_number_out_of_range_is_one_line_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.json");
    let text = to_json(&sample()).replacen("\"x_m\": 5.0", "\"x_m\": 1e999", 1);
    assert!(text.contains("1e999"));
    std::fs::write(&path, text).unwrap();
    let err = read(&path).unwrap_err().to_string();
    assert!(
        err.starts_with(&format!("{}: line ", path.display())),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
}

fn uv(out: &mut Vec<u8>, mut v: u64) {
    loop {
        let byte = (v & 0x7f) as u8;
        v >>= 7;
        if v == 0 {
            out.push(byte);
            return;
        }
        out.push(byte | 0x80);
    }
}

/// A `.btmb` header (no strings) followed by `rest`.
fn btmb(rest: &[u8]) -> Vec<u8> {
    let mut b = b"BTMB".to_vec();
    b.push(wire::WIRE_VERSION);
    b.extend_from_slice(rest);
    b
}

#[test]
fn huge_declared_counts_are_refused_before_anything_is_allocated() {
    // Node counts above the limit, or more than the bytes left can hold (12 bytes a node at
    // least), strings and string lengths beyond the data.
    let mut nodes_over_limit = vec![0]; // no strings
    uv(&mut nodes_over_limit, 1 << 40);
    let mut nodes_past_the_end = vec![0];
    uv(&mut nodes_past_the_end, MAX_NODES as u64);
    nodes_past_the_end.extend_from_slice(&[0; 64]);
    let mut strings = Vec::new();
    uv(&mut strings, u64::MAX);
    let mut length = vec![1];
    uv(&mut length, 1 << 62);
    let mut links = vec![0, 0]; // no strings, no nodes
    uv(&mut links, 3);
    links.extend_from_slice(&[0; 20]); // room for 2 links of 8 bytes, not 3
    for (rest, needle) in [
        (
            nodes_over_limit,
            "1099511627776 nodes, expected at most 1000000",
        ),
        (
            nodes_past_the_end,
            "1000000 nodes declared, but only 64 bytes are left",
        ),
        (strings, "18446744073709551615 strings declared"),
        (length, "4611686018427387904 string bytes declared"),
        (links, "3 links declared, but only 20 bytes are left"),
    ] {
        let err = wire::decode(&btmb(&rest)).unwrap_err().to_string();
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
    // A file past the file-size limit is refused before it is read (a sparse file: no disk
    // used).
    let dir = tempfile::tempdir().unwrap();
    let max = usar_world::limits::limits().max_file_bytes;
    for ext in ["btmb", "json"] {
        let path = dir.path().join(format!("huge.{ext}"));
        std::fs::File::create(&path)
            .unwrap()
            .set_len(max + 1)
            .unwrap();
        let err = read(&path).unwrap_err().to_string();
        assert!(err.contains("huge.") && err.contains("file size"), "{err}");
        assert!(err.contains(&format!("at most {max} bytes")), "{err}");
    }
}

#[test]
fn graphml_is_not_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.graphml");
    std::fs::write(&path, usar_btm::exchange::to_graphml(&sample())).unwrap();
    let err = read(&path).unwrap_err().to_string();
    assert!(err.contains("GraphML is an export format only"), "{err}");
}

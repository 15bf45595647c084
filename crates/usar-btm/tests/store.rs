//! The BTM tables in SQLite, JSON and GraphML.

use std::f64::consts::FRAC_PI_2;
use usar_btm::exchange::{from_json, to_graphml, to_json};
use usar_btm::model::{kind, subtype};
use usar_btm::{Btm, BtmStore, Link, Node};

/// A T junction (node 2) reached from the start (node 1), with a searched link to a dead end
/// (node 3), one un-searched branch, and a slope node carrying an extension attribute.
fn sample() -> Btm {
    let mut start = Node::new(1, 0.0, 0.0, kind::TERMINAL, Some(subtype::START));
    start.operator_note = Some("dust on the floor".into());
    let t = Node::new(2, 5.0, 0.0, kind::DIVERGENCE, Some(subtype::T_JUNCTION));
    let dead = Node::new(3, 5.0, 4.0, kind::DIVERGENCE, Some(subtype::DEAD_END));
    let mut slope = Node::new(4, 9.0, 0.0, kind::OBSTACLE, Some(subtype::SLOPE));
    slope.slope_inclination_rad = Some(0.35);
    slope.max_robot_inclination_rad = Some(0.36);
    slope.extra.insert("surface".into(), "gravel".into());
    let searched = |id, start, end, dir: f64, len| Link {
        searched: true,
        end: Some(end),
        length_m: Some(len),
        min_width_m: Some(1.2),
        max_inclination_rad: Some(0.02),
        ..Link::unsearched(id, start, dir)
    };
    Btm {
        nodes: vec![start, t, dead, slope],
        links: vec![
            searched(1, 1, 2, 0.0, 5.0),
            searched(2, 2, 3, FRAC_PI_2, 4.0),
            searched(3, 2, 4, 0.0, 4.0),
            Link::unsearched(4, 2, -FRAC_PI_2),
        ],
    }
}

#[test]
fn link_angles_are_the_gaps_between_adjacent_links_counter_clockwise() {
    let btm = sample();
    // Node 2: links towards 1 (west, π), 3 (north), 4 (east, 0) and the un-searched south.
    let angles = btm.link_angles(2);
    assert_eq!(angles.len(), 4);
    for a in angles {
        assert!((a - FRAC_PI_2).abs() < 1e-12);
    }
    assert!(btm.link_angles(3).is_empty());
    assert_eq!(btm.links_of(2).count(), 4);
    assert_eq!(btm.unsearched().count(), 1);
}

/// A new database holding `btm`, written node by node and link by link as a robot would.
fn written(path: &std::path::Path, btm: &Btm) -> BtmStore {
    let store = BtmStore::create(path).unwrap();
    for n in &btm.nodes {
        store.put_node(n).unwrap();
    }
    for l in &btm.links {
        store.put_link(l).unwrap();
    }
    store
}

#[test]
fn the_database_round_trips_every_field_and_extension() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("btm.sqlite");
    let btm = sample();
    {
        written(&path, &btm);
    }
    let loaded = BtmStore::open(&path).unwrap().load().unwrap();
    assert_eq!(loaded, btm);
    // Updating a link (searched while driving) replaces it.
    let store = BtmStore::open(&path).unwrap();
    let mut l = btm.links[3].clone();
    l.searched = true;
    l.end = Some(3);
    store.put_link(&l).unwrap();
    assert!(store.load().unwrap().links[3].searched);
    assert!(BtmStore::create(&path).is_err(), "never overwrites a map");
}

#[test]
fn foreign_and_newer_databases_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let junk = dir.path().join("junk.sqlite");
    std::fs::write(&junk, b"not sqlite").unwrap();
    let err = BtmStore::open(&junk).err().unwrap().to_string();
    assert!(err.contains("not a BTM database"), "{err}");
    let newer = dir.path().join("newer.sqlite");
    {
        let s = BtmStore::create(&newer).unwrap();
        drop(s);
        let c = rusqlite_update(&newer);
        assert!(c);
    }
    let err = BtmStore::open(&newer).err().unwrap().to_string();
    assert!(
        err.contains("schema version 2, expected 1 or older"),
        "{err}"
    );
}

fn rusqlite_update(path: &std::path::Path) -> bool {
    let c = rusqlite::Connection::open(path).unwrap();
    c.execute(
        "UPDATE meta SET value = '2' WHERE key = 'schema_version'",
        [],
    )
    .unwrap()
        == 1
}

#[test]
fn json_round_trips_and_keeps_unknown_kinds() {
    let mut btm = sample();
    btm.nodes.push(Node::new(5, 2.0, 1.0, kind::VICTIM, None));
    btm.nodes[4].kind = "gas_leak".into();
    let text = to_json(&btm);
    assert!(text.contains("\"link_angles_rad\""));
    let back = from_json(&text, "m.json").unwrap();
    assert_eq!(back, btm);
    let err = from_json(&text.replace("\"start\": 2", "\"start\": 99"), "m.json")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("m.json: link 2 field `start`: found node 99, which does not exist"),
        "{err}"
    );
    let err = from_json(&text.replace("\"version\": 1", "\"version\": 7"), "m.json")
        .unwrap_err()
        .to_string();
    assert!(err.contains("field `version`: found 7"), "{err}");
}

#[test]
fn graphml_has_every_node_and_link() {
    let g = to_graphml(&sample());
    assert_eq!(g.matches("<node id=\"n").count(), 4);
    assert_eq!(g.matches("<edge ").count(), 4);
    assert!(
        g.contains("<node id=\"u4\">"),
        "the un-searched link ends at an open-end node"
    );
    assert!(g.contains("{&quot;surface&quot;:&quot;gravel&quot;}"));
}

#[test]
fn a_deleted_link_is_gone_from_the_database() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("btm.sqlite");
    let btm = sample();
    let store = written(&path, &btm);
    store.delete_link(4).unwrap();
    store.delete_link(99).unwrap();
    let loaded = store.load().unwrap();
    assert_eq!(loaded.links.len(), btm.links.len() - 1);
    assert!(loaded.links.iter().all(|l| l.id != 4));
}

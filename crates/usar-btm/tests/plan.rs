//! Planning for robots of other abilities, and merging local maps.

use usar_btm::merge::{MATCH_RADIUS_M, merge};
use usar_btm::model::{kind, subtype};
use usar_btm::plan::{NoRoute, RobotLimits, plan};
use usar_btm::{Btm, Link, Node};

fn link(id: u32, start: u32, end: u32, width: f64, len: f64) -> Link {
    Link {
        end: Some(end),
        searched: true,
        length_m: Some(len),
        min_width_m: Some(width),
        max_inclination_rad: Some(0.0),
        ..Link::unsearched(id, start, 0.0)
    }
}

/// 1 —(narrow, 4 m)— 2 —— 4 ;  1 —(wide, 6 m)— 3 (slope 20°) —— 4
fn diamond() -> Btm {
    let mut slope = Node::new(3, 3.0, -3.0, kind::OBSTACLE, Some(subtype::SLOPE));
    slope.slope_inclination_rad = Some(20f64.to_radians());
    Btm {
        nodes: vec![
            Node::new(1, 0.0, 0.0, kind::TERMINAL, Some(subtype::START)),
            Node::new(2, 3.0, 3.0, kind::DIVERGENCE, Some(subtype::CORNER)),
            slope,
            Node::new(4, 6.0, 0.0, kind::DIVERGENCE, Some(subtype::DEAD_END)),
        ],
        links: vec![
            link(1, 1, 2, 0.5, 4.0),
            link(2, 2, 4, 1.5, 4.0),
            link(3, 1, 3, 1.5, 6.0),
            link(4, 3, 4, 1.5, 6.0),
        ],
    }
}

const CRAWLER: RobotLimits = RobotLimits {
    width_m: 0.45,
    max_inclination_rad: 0.6,
    max_step_m: 0.2,
};

#[test]
fn a_robot_wider_than_a_link_never_uses_it() {
    let btm = diamond();
    let r = plan(&btm, &CRAWLER, 1, 4).unwrap();
    assert_eq!((r.nodes.clone(), r.length_m), (vec![1, 2, 4], 8.0));
    let wide = RobotLimits {
        width_m: 0.6,
        ..CRAWLER
    };
    let r = plan(&btm, &wide, 1, 4).unwrap();
    assert_eq!(r.nodes, vec![1, 3, 4]);
    assert!(!r.links.contains(&1));
}

#[test]
fn no_route_says_which_limit_closes_it() {
    let btm = diamond();
    let wide_and_flat = RobotLimits {
        width_m: 0.6,
        max_inclination_rad: 15f64.to_radians(),
        max_step_m: 0.05,
    };
    let err = plan(&btm, &wide_and_flat, 1, 4).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err, NoRoute::Closed { .. }), "{text}");
    assert!(text.contains("link 1 is 0.50 m wide"), "{text}");
    let mut cut = diamond();
    cut.links.retain(|l| l.end != Some(4));
    cut.links.push(Link::unsearched(9, 2, 0.0));
    let err = plan(&cut, &CRAWLER, 1, 4).unwrap_err();
    assert!(
        matches!(err, NoRoute::NotConnected { unsearched: 1, .. }),
        "{err}"
    );
    assert!(matches!(
        plan(&btm, &CRAWLER, 1, 77),
        Err(NoRoute::UnknownNode(77))
    ));
}

#[test]
fn merged_maps_share_nodes_and_keep_the_most_restrictive_values() {
    // Robot A mapped 1–2 (width 1.2) and left an un-searched link from 2 heading east; robot B
    // mapped the same corner (0.4 m off) and its link east to a dead end, narrower.
    let a = Btm {
        nodes: vec![
            Node::new(1, 0.0, 0.0, kind::TERMINAL, Some(subtype::START)),
            Node::new(2, 5.0, 0.0, kind::DIVERGENCE, Some(subtype::CORNER)),
        ],
        links: vec![link(1, 1, 2, 1.2, 5.0), Link::unsearched(2, 2, 0.05)],
    };
    let mut b_corner = Node::new(7, 5.4, 0.0, kind::DIVERGENCE, Some(subtype::CORNER));
    b_corner.operator_note = Some("slippery".into());
    let b = Btm {
        nodes: vec![
            b_corner,
            Node::new(8, 9.0, 0.0, kind::DIVERGENCE, Some(subtype::DEAD_END)),
            Node::new(9, 0.3, 0.2, kind::TERMINAL, Some(subtype::START)),
        ],
        links: vec![link(5, 7, 8, 0.8, 3.6), link(6, 9, 7, 0.9, 5.2)],
    };
    let m = merge(&[a, b], MATCH_RADIUS_M);
    assert_eq!(m.nodes.len(), 3, "{:?}", m.nodes);
    let corner = &m.nodes[1];
    assert!((corner.x_m - 5.2).abs() < 1e-9);
    assert_eq!(corner.operator_note.as_deref(), Some("slippery"));
    // 1–2 seen by both: the narrower width and the longer length win.
    let l12 = m
        .links
        .iter()
        .find(|l| l.end == Some(2) || (l.start == 2 && l.end == Some(1)))
        .unwrap();
    assert_eq!((l12.min_width_m, l12.length_m), (Some(0.9), Some(5.2)));
    // A's un-searched link east was explored by B.
    assert_eq!(m.unsearched().count(), 0);
    assert_eq!(m.links.len(), 2);
}

#[test]
fn nodes_are_named_by_id_or_by_the_nearest_position() {
    use usar_btm::plan::{NodeRefError, find_node};
    let map = diamond();
    assert_eq!(find_node(&map, " 7 "), Ok(7));
    assert_eq!(find_node(&map, "5.9, 0.2"), Ok(4));
    assert_eq!(
        find_node(&map, "north"),
        Err(NodeRefError::Malformed("north".into()))
    );
    assert_eq!(
        find_node(&Btm::default(), "1,2"),
        Err(NodeRefError::EmptyMap)
    );
}

#[test]
fn reports_count_unknown_kinds_and_name_the_partial_file() {
    use usar_btm::report::{describe, partial_path, unknown_kinds};
    let mut map = diamond();
    assert!(unknown_kinds(&map).is_empty());
    map.nodes.push(Node::new(9, 1.0, 1.0, "ladder", None));
    assert_eq!(unknown_kinds(&map).get("ladder"), Some(&1));
    let v = describe(&map);
    assert_eq!(v["links_searched"], 4);
    assert_eq!(v["nodes"].as_array().map(Vec::len), Some(5));
    assert_eq!(
        partial_path(std::path::Path::new("out/map.btm")),
        std::path::Path::new("out/map.btm.partial")
    );
}

//! Joining local BTMs of several robots into one global BTM (paper 004 §II: "the local BTMs
//! created by the different robots are combined to have a global BTM at a central operation
//! station").
//!
//! Nodes of the same kind and subtype closer than `match_radius_m` are one node, placed at the
//! mean of their positions. Where attributes conflict the most restrictive value wins: the
//! steepest slope, the highest step, the largest robot inclination, the narrowest link width,
//! the longest link length; operator notes are all kept. A link present in several maps (same
//! two merged ends) becomes one link, searched if any robot searched it. An un-searched link
//! that points (within 30°) along a searched link of the same merged node was explored by
//! another robot and is dropped. Ids are renumbered from 1, nodes in input order.

use crate::model::{Btm, Link, Node};
use std::f64::consts::PI;

/// Default distance within which nodes of the same kind are the same place, metres.
pub const MATCH_RADIUS_M: f64 = 1.0;
/// Un-searched links within this angle of a searched one are the same passage.
const SAME_DIRECTION_RAD: f64 = PI / 6.0;

fn max_opt(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.max(y)),
        (x, y) => x.or(y),
    }
}

fn min_opt(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    }
}

/// Merges `maps` (in order) into one.
pub fn merge(maps: &[Btm], match_radius_m: f64) -> Btm {
    let mut out = Btm::default();
    // Members of each merged node, for the mean position.
    let mut members: Vec<Vec<(f64, f64)>> = Vec::new();
    // (map index, old id) → new node id.
    let mut ids: Vec<std::collections::BTreeMap<u32, u32>> = vec![Default::default(); maps.len()];
    for (m, btm) in maps.iter().enumerate() {
        for n in &btm.nodes {
            let found = out.nodes.iter().position(|o| {
                o.kind == n.kind
                    && o.subtype == n.subtype
                    && (o.x_m - n.x_m).hypot(o.y_m - n.y_m) <= match_radius_m
            });
            let k = match found {
                Some(k) => {
                    let o = &mut out.nodes[k];
                    o.slope_inclination_rad =
                        max_opt(o.slope_inclination_rad, n.slope_inclination_rad);
                    o.step_height_m = max_opt(o.step_height_m, n.step_height_m);
                    o.max_robot_inclination_rad =
                        max_opt(o.max_robot_inclination_rad, n.max_robot_inclination_rad);
                    o.operator_note = match (o.operator_note.take(), &n.operator_note) {
                        (Some(a), Some(b)) if a != *b => Some(format!("{a}; {b}")),
                        (a, b) => a.or_else(|| b.clone()),
                    };
                    for (key, v) in &n.extra {
                        o.extra.entry(key.clone()).or_insert_with(|| v.clone());
                    }
                    members[k].push((n.x_m, n.y_m));
                    let len = members[k].len() as f64;
                    o.x_m = members[k].iter().map(|p| p.0).sum::<f64>() / len;
                    o.y_m = members[k].iter().map(|p| p.1).sum::<f64>() / len;
                    k
                }
                None => {
                    let mut node = n.clone();
                    node.id = out.nodes.len() as u32 + 1;
                    out.nodes.push(node);
                    members.push(vec![(n.x_m, n.y_m)]);
                    out.nodes.len() - 1
                }
            };
            ids[m].insert(n.id, out.nodes[k].id);
        }
    }
    for (m, btm) in maps.iter().enumerate() {
        for l in btm.links.iter().filter(|l| l.searched) {
            let (Some(&a), Some(&b)) = (ids[m].get(&l.start), l.end.and_then(|e| ids[m].get(&e)))
            else {
                continue;
            };
            let same = out
                .links
                .iter_mut()
                .find(|o| (o.start == a && o.end == Some(b)) || (o.start == b && o.end == Some(a)));
            match same {
                Some(o) => {
                    o.min_width_m = min_opt(o.min_width_m, l.min_width_m);
                    o.length_m = max_opt(o.length_m, l.length_m);
                    o.max_inclination_rad = max_opt(o.max_inclination_rad, l.max_inclination_rad);
                    o.max_step_m = max_opt(o.max_step_m, l.max_step_m);
                    for (key, v) in &l.extra {
                        o.extra.entry(key.clone()).or_insert_with(|| v.clone());
                    }
                }
                None => {
                    let mut link = l.clone();
                    link.id = out.links.len() as u32 + 1;
                    link.start = a;
                    link.end = Some(b);
                    out.links.push(link);
                }
            }
        }
    }
    for (m, btm) in maps.iter().enumerate() {
        for l in btm.links.iter().filter(|l| !l.searched) {
            let Some(&a) = ids[m].get(&l.start) else {
                continue;
            };
            let explored = out
                .links_of(a)
                .filter(|o| o.searched || o.end.is_none())
                .any(|o| {
                    let gap =
                        usar_world::normalize_angle(direction_from(&out, o, a) - l.direction_rad);
                    gap.abs() < SAME_DIRECTION_RAD
                });
            if !explored {
                let link = Link {
                    id: out.links.len() as u32 + 1,
                    start: a,
                    ..l.clone()
                };
                out.links.push(link);
            }
        }
    }
    out
}

/// Direction of link `o` leaving merged node `a`.
fn direction_from(btm: &Btm, o: &Link, a: u32) -> f64 {
    let node = |id: u32| btm.node(id).map(|n: &Node| (n.x_m, n.y_m));
    let other = if o.start == a { o.end } else { Some(o.start) };
    match (node(a), other.and_then(node)) {
        (Some(p), Some(q)) => (q.1 - p.1).atan2(q.0 - p.0),
        _ => o.direction_rad,
    }
}

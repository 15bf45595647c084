//! Planning on the BTM itself: the shortest chain of searched links from a node to the
//! nearest node that still has an un-searched link (the depth-first order of exploration
//! drives back along it when a branch ends).

use crate::model::Btm;
use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};

/// Links leaving a node that the robot may still explore (un-searched and not given up).
pub fn open_links(btm: &Btm, node: u32) -> impl Iterator<Item = &crate::Link> {
    btm.links.iter().filter(move |l| {
        l.start == node && !l.searched && !l.extra.contains_key(super::BLOCKED_FOR)
    })
}

/// Whether node `id` may be driven through (an obstacle this robot could not cross may not).
fn passable(btm: &Btm, id: u32) -> bool {
    btm.node(id)
        .is_none_or(|n| !n.extra.contains_key(super::IMPASSABLE_FOR))
}

/// The links to drive, in order, from `from` to the nearest node (by driven length) with an
/// un-searched link, and that node; ties go to the lower node id. `None` when no such node
/// is reachable; `Some((vec![], from))` when `from` itself has one.
pub fn route_to_unsearched(btm: &Btm, from: u32) -> Option<(Vec<u32>, u32)> {
    // Dijkstra on lengths in millimetres (integers keep the order total and deterministic).
    let mut best: BTreeMap<u32, (u64, Option<(u32, u32)>)> = BTreeMap::new();
    let mut heap = BinaryHeap::new();
    best.insert(from, (0, None));
    heap.push(Reverse((0u64, from)));
    while let Some(Reverse((d, node))) = heap.pop() {
        if best.get(&node).is_some_and(|b| b.0 < d) {
            continue;
        }
        if open_links(btm, node).next().is_some() {
            let mut links = Vec::new();
            let mut at = node;
            while let Some((_, Some((prev, link)))) = best.get(&at) {
                links.push(*link);
                at = *prev;
            }
            links.reverse();
            return Some((links, node));
        }
        if node != from && !passable(btm, node) {
            continue;
        }
        for l in btm.links.iter().filter(|l| l.searched) {
            let Some(end) = l.end else { continue };
            let next = if l.start == node {
                end
            } else if end == node {
                l.start
            } else {
                continue;
            };
            let nd = d + (l.length_m.unwrap_or(0.0) * 1000.0).round().max(1.0) as u64;
            if best.get(&next).is_none_or(|b| nd < b.0) {
                best.insert(next, (nd, Some((node, l.id))));
                heap.push(Reverse((nd, next)));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Link, Node, kind};

    #[test]
    fn the_route_leads_to_the_nearest_node_with_an_unsearched_link() {
        let node = |id, x| Node::new(id, x, 0.0, kind::DIVERGENCE, None);
        let searched = |id, a, b, len| Link {
            searched: true,
            end: Some(b),
            length_m: Some(len),
            ..Link::unsearched(id, a, 0.0)
        };
        let btm = Btm {
            nodes: vec![node(1, 0.0), node(2, 5.0), node(3, 9.0), node(4, -3.0)],
            links: vec![
                searched(1, 1, 2, 5.0),
                searched(2, 2, 3, 4.0),
                searched(3, 4, 1, 3.0),
                Link::unsearched(4, 3, 1.0),
                Link::unsearched(5, 4, 2.0),
            ],
        };
        assert_eq!(route_to_unsearched(&btm, 2), Some((vec![2], 3)));
        assert_eq!(route_to_unsearched(&btm, 1), Some((vec![3], 4)));
        assert_eq!(route_to_unsearched(&btm, 3), Some((vec![], 3)));
        let done = Btm {
            links: btm.links[..3].to_vec(),
            ..btm
        };
        assert_eq!(route_to_unsearched(&done, 2), None);
    }
}

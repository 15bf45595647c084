//! Planning on a BTM for a robot that did not build it (paper 004 §II-B): a link is usable
//! when it was searched and is wide, gentle and low-stepped enough for the robot; an obstacle
//! node is passable when its slope and steps are within the robot's limits. Routes minimise
//! the links' driven length (Dijkstra). When there is none, the planner says why: the map does
//! not connect the two nodes, or which limit — width, inclination, step — cuts every route,
//! naming the links or nodes that do.

use crate::model::{Btm, Link, Node};
use serde::Serialize;

/// What a robot can do, as far as a BTM is concerned.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RobotLimits {
    pub width_m: f64,
    pub max_inclination_rad: f64,
    pub max_step_m: f64,
}

impl RobotLimits {
    /// The limits of a simulated robot model: its width, steepest inclination and highest step.
    pub fn of(robot: &usar_sim::RobotSpec) -> Self {
        RobotLimits {
            width_m: robot.width_m,
            max_inclination_rad: robot.max_inclination_rad,
            max_step_m: robot.max_step_m,
        }
    }
}

/// A route: node ids from start to goal, the links between them, and its length.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Route {
    pub nodes: Vec<u32>,
    pub links: Vec<u32>,
    pub length_m: f64,
}

/// Why a link or node is closed to a robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Limit {
    Width,
    Inclination,
    Step,
}

impl Limit {
    const ALL: [Limit; 3] = [Limit::Width, Limit::Inclination, Limit::Step];
}

/// Why no route exists.
#[derive(Clone, Debug, PartialEq, Serialize, thiserror::Error)]
pub enum NoRoute {
    #[error("node {0} is not in the map")]
    UnknownNode(u32),
    #[error(
        "the map does not connect node {from} and node {to} through searched links ({unsearched} un-searched links remain)"
    )]
    NotConnected {
        from: u32,
        to: u32,
        unsearched: usize,
    },
    #[error("no route is open to this robot; the shortest route ignoring its limits is closed where {}", reasons.join("; "))]
    Closed { reasons: Vec<String> },
}

fn length(btm: &Btm, l: &Link) -> f64 {
    l.length_m.unwrap_or_else(
        || match (btm.node(l.start), l.end.and_then(|e| btm.node(e))) {
            (Some(a), Some(b)) => (a.x_m - b.x_m).hypot(a.y_m - b.y_m),
            _ => f64::INFINITY,
        },
    )
}

/// The limits `link` exceeds for `robot` (empty: usable).
pub fn link_violations(l: &Link, robot: &RobotLimits) -> Vec<(Limit, String)> {
    let mut v = Vec::new();
    if let Some(w) = l.min_width_m
        && w < robot.width_m
    {
        v.push((
            Limit::Width,
            format!(
                "link {} is {w:.2} m wide at its narrowest, the robot {:.2} m",
                l.id, robot.width_m
            ),
        ));
    }
    if let Some(i) = l.max_inclination_rad
        && i > robot.max_inclination_rad
    {
        v.push((
            Limit::Inclination,
            format!(
                "link {} inclines {:.1}°, the robot climbs {:.1}°",
                l.id,
                i.to_degrees(),
                robot.max_inclination_rad.to_degrees()
            ),
        ));
    }
    if let Some(s) = l.max_step_m
        && s > robot.max_step_m
    {
        v.push((
            Limit::Step,
            format!(
                "link {} has a {s:.2} m step, the robot climbs {:.2} m",
                l.id, robot.max_step_m
            ),
        ));
    }
    v
}

/// The limits obstacle node `n` exceeds for `robot`.
pub fn node_violations(n: &Node, robot: &RobotLimits) -> Vec<(Limit, String)> {
    let mut v = Vec::new();
    if let Some(i) = n.slope_inclination_rad
        && i > robot.max_inclination_rad
    {
        v.push((
            Limit::Inclination,
            format!(
                "node {} ({}) is a {:.1}° slope, the robot climbs {:.1}°",
                n.id,
                n.subtype.as_deref().unwrap_or(&n.kind),
                i.to_degrees(),
                robot.max_inclination_rad.to_degrees()
            ),
        ));
    }
    if let Some(s) = n.step_height_m
        && s > robot.max_step_m
    {
        v.push((
            Limit::Step,
            format!(
                "node {} has {s:.2} m steps, the robot climbs {:.2} m",
                n.id, robot.max_step_m
            ),
        ));
    }
    v
}

/// Dijkstra over searched links, ignoring the limits in `relaxed`.
fn shortest(
    btm: &Btm,
    robot: &RobotLimits,
    from: u32,
    to: u32,
    relaxed: &[Limit],
) -> Option<Route> {
    let open = |v: Vec<(Limit, String)>| v.iter().all(|(l, _)| relaxed.contains(l));
    let node_ok = |id: u32| {
        id == from
            || id == to
            || btm
                .node(id)
                .is_some_and(|n| open(node_violations(n, robot)))
    };
    let (path, _) = pathfinding::prelude::dijkstra(
        &from,
        |&id| {
            btm.links_of(id)
                .filter(|l| l.searched && l.end.is_some() && open(link_violations(l, robot)))
                .filter_map(|l| {
                    let other = if l.start == id { l.end? } else { l.start };
                    node_ok(other).then(|| (other, ordered(length(btm, l))))
                })
                .collect::<Vec<_>>()
        },
        |&id| id == to,
    )?;
    // The links along the node path: the shortest one between each pair.
    let mut links = Vec::new();
    let mut total = 0.0;
    for w in path.windows(2) {
        let l = btm
            .links
            .iter()
            .filter(|l| {
                l.searched
                    && open(link_violations(l, robot))
                    && ((l.start == w[0] && l.end == Some(w[1]))
                        || (l.start == w[1] && l.end == Some(w[0])))
            })
            .min_by(|a, b| {
                length(btm, a)
                    .total_cmp(&length(btm, b))
                    .then(a.id.cmp(&b.id))
            })
            .expect("dijkstra used a link");
        total += length(btm, l);
        links.push(l.id);
    }
    Some(Route {
        nodes: path,
        links,
        length_m: total,
    })
}

/// Lengths as totally ordered integers (micrometres) for Dijkstra.
fn ordered(len: f64) -> u64 {
    (len.max(0.0) * 1e6).round() as u64
}

/// The shortest route from node `from` to node `to` usable by `robot`, or why there is none.
pub fn plan(btm: &Btm, robot: &RobotLimits, from: u32, to: u32) -> Result<Route, NoRoute> {
    for id in [from, to] {
        if btm.node(id).is_none() {
            return Err(NoRoute::UnknownNode(id));
        }
    }
    if let Some(r) = shortest(btm, robot, from, to, &[]) {
        return Ok(r);
    }
    let Some(relaxed) = shortest(btm, robot, from, to, &Limit::ALL) else {
        return Err(NoRoute::NotConnected {
            from,
            to,
            unsearched: btm.unsearched().count(),
        });
    };
    // Name what closes the shortest route the robot could take if it had no limits.
    let mut reasons = Vec::new();
    for w in relaxed.links.iter() {
        let l = btm.links.iter().find(|l| l.id == *w).expect("route link");
        reasons.extend(link_violations(l, robot).into_iter().map(|(_, r)| r));
    }
    for id in &relaxed.nodes {
        let n = btm.node(*id).expect("route node");
        reasons.extend(node_violations(n, robot).into_iter().map(|(_, r)| r));
    }
    reasons.dedup();
    Err(NoRoute::Closed { reasons })
}

/// The node nearest to (x, y).
pub fn nearest_node(btm: &Btm, x: f64, y: f64) -> Option<&Node> {
    btm.nodes.iter().min_by(|a, b| {
        (a.x_m - x)
            .hypot(a.y_m - y)
            .total_cmp(&(b.x_m - x).hypot(b.y_m - y))
    })
}

/// Why a node named by a user could not be found ([`find_node`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NodeRefError {
    /// Neither a node id nor "x,y".
    #[error("{0:?}: expected a node id or \"x,y\" in metres")]
    Malformed(String),
    /// A position was given and the map has no nodes.
    #[error("the map has no nodes")]
    EmptyMap,
}

/// A node named as a user names one: its id, or "x,y" in metres (the nearest node). An id is
/// not checked against the map ([`plan`] says when it is not there).
pub fn find_node(btm: &Btm, s: &str) -> Result<u32, NodeRefError> {
    if let Ok(id) = s.trim().parse::<u32>() {
        return Ok(id);
    }
    let xy = s
        .split_once(',')
        .and_then(|(x, y)| Some((x.trim().parse::<f64>().ok()?, y.trim().parse::<f64>().ok()?)));
    let Some((x, y)) = xy else {
        return Err(NodeRefError::Malformed(s.to_string()));
    };
    nearest_node(btm, x, y)
        .map(|n| n.id)
        .ok_or(NodeRefError::EmptyMap)
}

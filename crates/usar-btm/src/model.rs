//! The Behavioral Trace Map (paper 004 §II-A, Tables I–II): nodes at places with special
//! features, links between them.
//!
//! Units are SI (metres, radians) although the paper's tables use millimetres and degrees.
//! Node kinds and subtypes are open names: the paper's ([`kind`], [`subtype`]) and new ones
//! (a `victim`, a `hazard`, …) coexist, and attributes a reader does not know travel in
//! `extra`, so maps written by newer versions still load. A kind this version does not know
//! ([`kind::is_known`]) is kept as read; what a map read from a file must be (names, finite
//! measures, links between existing nodes) is in [`crate::validate`].

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The paper's node kinds.
pub mod kind {
    /// Start or end of a search session.
    pub const TERMINAL: &str = "terminal";
    /// Dead end, corner, T junction or crossing.
    pub const DIVERGENCE: &str = "divergence";
    /// Entrance or exit of a room-like open space.
    pub const FREE_SPACE: &str = "free_space";
    /// A three-dimensional obstacle: slope or stairs.
    pub const OBSTACLE: &str = "obstacle";
    /// Extensions beyond the paper.
    pub const VICTIM: &str = "victim";
    pub const HAZARD: &str = "hazard";

    /// The kinds this version knows (the paper's and its extensions).
    pub const KNOWN: [&str; 6] = [TERMINAL, DIVERGENCE, FREE_SPACE, OBSTACLE, VICTIM, HAZARD];

    /// Whether this version knows `kind`. Other kinds (written by a newer version or another
    /// tool) load and are kept; they are drawn in the colour of extensions and planned through
    /// by their measured attributes like any node.
    pub fn is_known(kind: &str) -> bool {
        KNOWN.contains(&kind)
    }
}

/// The paper's subtypes (divergence features, free-space ends, obstacle shapes).
pub mod subtype {
    pub const START: &str = "start";
    pub const END: &str = "end";
    pub const DEAD_END: &str = "dead_end";
    pub const CORNER: &str = "corner";
    pub const T_JUNCTION: &str = "t_junction";
    pub const CROSSING: &str = "crossing";
    pub const ENTRANCE: &str = "entrance";
    pub const EXIT: &str = "exit";
    pub const SLOPE: &str = "slope";
    pub const STAIRS: &str = "stairs";
}

/// Attributes of extensions: name → any JSON value.
pub type Extra = BTreeMap<String, serde_json::Value>;

/// A node (Table I). The number of links and the angles between adjacent links are derived
/// from the links ([`Btm::link_angles`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub id: u32,
    pub x_m: f64,
    pub y_m: f64,
    /// One of [`kind`] or an extension.
    pub kind: String,
    /// One of [`subtype`] or an extension; `None` when the kind has none.
    pub subtype: Option<String>,
    /// Inclination of a slope, radians.
    pub slope_inclination_rad: Option<f64>,
    /// Height of a step of stairs, metres.
    pub step_height_m: Option<f64>,
    /// Largest inclination of the robot's body measured at the node, radians.
    pub max_robot_inclination_rad: Option<f64>,
    /// Why the operator had to intervene here, if they did.
    pub operator_note: Option<String>,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub extra: Extra,
}

impl Node {
    /// A node of `kind` / `subtype` at (x, y) with no attributes yet.
    pub fn new(id: u32, x_m: f64, y_m: f64, kind: &str, subtype: Option<&str>) -> Self {
        Self {
            id,
            x_m,
            y_m,
            kind: kind.into(),
            subtype: subtype.map(Into::into),
            slope_inclination_rad: None,
            step_height_m: None,
            max_robot_inclination_rad: None,
            operator_note: None,
            extra: Extra::new(),
        }
    }
}

/// A link (Table II). An un-searched link has a start node and a direction only: what lies at
/// its other end is unknown.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Link {
    pub id: u32,
    pub start: u32,
    pub end: Option<u32>,
    pub searched: bool,
    /// Direction leaving the start node, radians (counter-clockwise from +x).
    pub direction_rad: f64,
    /// Length driven along the link, metres.
    pub length_m: Option<f64>,
    /// Narrowest free width measured along the link, metres.
    pub min_width_m: Option<f64>,
    /// Largest inclination of the robot's body along the link, radians.
    pub max_inclination_rad: Option<f64>,
    /// Highest step crossed along the link, metres.
    pub max_step_m: Option<f64>,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub extra: Extra,
}

impl Link {
    /// An un-searched link leaving `start` in direction `direction_rad`.
    pub fn unsearched(id: u32, start: u32, direction_rad: f64) -> Self {
        Self {
            id,
            start,
            end: None,
            searched: false,
            direction_rad,
            length_m: None,
            min_width_m: None,
            max_inclination_rad: None,
            max_step_m: None,
            extra: Extra::new(),
        }
    }
}

/// A whole map: nodes and links by id.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Btm {
    pub nodes: Vec<Node>,
    pub links: Vec<Link>,
}

impl Btm {
    pub fn node(&self, id: u32) -> Option<&Node> {
        self.nodes.iter().find(|n| n.id == id)
    }

    /// Links touching node `id`.
    pub fn links_of(&self, id: u32) -> impl Iterator<Item = &Link> {
        self.links
            .iter()
            .filter(move |l| l.start == id || l.end == Some(id))
    }

    /// Direction of `link` leaving node `id` (reversed for links that end there).
    fn direction_from(&self, link: &Link, id: u32) -> f64 {
        if link.start == id {
            return link.direction_rad;
        }
        match (self.node(link.start), self.node(id)) {
            (Some(a), Some(b)) => (a.y_m - b.y_m).atan2(a.x_m - b.x_m),
            _ => link.direction_rad + std::f64::consts::PI,
        }
    }

    /// Table I's "list of angles between adjacent links" of node `id`: the links' directions
    /// sorted counter-clockwise, and the angle from each to the next (they sum to 2π; empty
    /// for a node with fewer than two links).
    pub fn link_angles(&self, id: u32) -> Vec<f64> {
        let tau = std::f64::consts::TAU;
        let mut dirs: Vec<f64> = self
            .links_of(id)
            .map(|l| self.direction_from(l, id).rem_euclid(tau))
            .collect();
        if dirs.len() < 2 {
            return Vec::new();
        }
        dirs.sort_by(f64::total_cmp);
        (0..dirs.len())
            .map(|i| {
                let next = dirs[(i + 1) % dirs.len()];
                (next - dirs[i]).rem_euclid(tau)
            })
            .collect()
    }

    /// Links still to be explored.
    pub fn unsearched(&self) -> impl Iterator<Item = &Link> {
        self.links.iter().filter(|l| !l.searched)
    }

    /// The next free node id.
    pub fn next_node_id(&self) -> u32 {
        self.nodes.iter().map(|n| n.id + 1).max().unwrap_or(1)
    }

    /// The next free link id.
    pub fn next_link_id(&self) -> u32 {
        self.links.iter().map(|l| l.id + 1).max().unwrap_or(1)
    }
}

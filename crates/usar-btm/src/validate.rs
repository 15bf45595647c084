//! What a map read from outside must be before anything plans on, draws or exports it. Every
//! load path — the SQLite database ([`crate::store::BtmStore::load`]), JSON
//! ([`crate::exchange::from_json`]) and the binary wire form ([`crate::wire::decode`]) — checks
//! the map with [`check`] and refuses it with one line naming the node or link, the field, what
//! was found and what was expected. GraphML is written only, never read.
//!
//! - Node and link ids are unique; every link starts at a node of the map, and ends at one if
//!   it has an end.
//! - Coordinates are finite and within ±[`MAX_ABS_M`]; lengths, widths, step heights are
//!   finite, not negative and at most [`MAX_ABS_M`]; a slope's inclination is within
//!   [0, π/2], a robot's body inclination within [0, π]; a link's direction is a finite angle.
//! - Kinds and subtypes are open (paper 004's and any extension: a map written by a newer
//!   version still loads), but each is a name: 1–[`MAX_NAME_LEN`] ASCII letters, digits, `_`
//!   or `-`, starting with a letter. A node of a kind this version does not know
//!   ([`crate::model::kind::is_known`]) is kept as read, drawn in the colour of extensions and
//!   planned through by its measured attributes like any other node.
//! - At most [`MAX_NODES`] nodes and [`MAX_LINKS`] links, checked before anything is
//!   allocated for them (the wire form's declared counts, a database's row counts); `.json`
//!   and `.btmb` files are read under the process's file-size limit
//!   ([`usar_world::limits`], `usar --max-file-mb`).

use crate::model::{Btm, Link, Node};
use std::collections::BTreeSet;
use std::f64::consts::{FRAC_PI_2, PI};

/// Largest coordinate, length, width or step height, metres (1 000 km).
pub const MAX_ABS_M: f64 = 1.0e6;
/// Largest absolute direction of a link, radians (directions need not be normalised).
pub const MAX_ABS_DIRECTION_RAD: f64 = 1.0e6;
/// Most nodes a map may have.
pub const MAX_NODES: usize = 1_000_000;
/// Most links a map may have.
pub const MAX_LINKS: usize = 4_000_000;
/// Longest kind or subtype name.
pub const MAX_NAME_LEN: usize = 64;

/// Why a map was refused: `node 7 field `x_m`: found inf, expected …`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} field `{field}`: found {found}, expected {expected}")]
pub struct Invalid {
    /// `node 7`, `link 3`, `map`.
    pub what: String,
    pub field: &'static str,
    pub found: String,
    pub expected: String,
}

impl Invalid {
    pub fn new(what: impl Into<String>, field: &'static str, found: impl Into<String>) -> Self {
        Self {
            what: what.into(),
            field,
            found: found.into(),
            expected: String::new(),
        }
    }

    pub fn expected(mut self, expected: impl Into<String>) -> Self {
        self.expected = expected.into();
        self
    }
}

/// A found text for messages: quoted, escaped, cut after 40 characters.
pub fn quoted(s: &str) -> String {
    let mut cut: String = s.chars().take(40).collect();
    if cut.len() < s.len() {
        cut.push('…');
    }
    format!("{cut:?}")
}

/// Whether `s` is a kind or subtype name.
pub fn is_name(s: &str) -> bool {
    s.len() <= MAX_NAME_LEN
        && s.as_bytes().first().is_some_and(u8::is_ascii_alphabetic)
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
}

fn name(what: &str, field: &'static str, s: &str) -> Result<(), Invalid> {
    if is_name(s) {
        return Ok(());
    }
    Err(Invalid::new(what, field, quoted(s)).expected(format!(
        "a name of 1–{MAX_NAME_LEN} ASCII letters, digits, `_` or `-` starting with a letter (e.g. divergence, t_junction)"
    )))
}

fn within(
    what: &str,
    field: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    expected: &str,
) -> Result<(), Invalid> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        return Ok(());
    }
    Err(Invalid::new(what, field, v.to_string()).expected(expected))
}

fn coordinate(what: &str, field: &'static str, v: f64) -> Result<(), Invalid> {
    within(
        what,
        field,
        v,
        -MAX_ABS_M,
        MAX_ABS_M,
        "a finite coordinate within ±1000000 m",
    )
}

fn distance(what: &str, field: &'static str, v: Option<f64>) -> Result<(), Invalid> {
    v.map_or(Ok(()), |v| {
        within(
            what,
            field,
            v,
            0.0,
            MAX_ABS_M,
            "a finite distance from 0 to 1000000 m",
        )
    })
}

fn angle(what: &str, field: &'static str, v: Option<f64>, hi: f64) -> Result<(), Invalid> {
    let expected = if hi == FRAC_PI_2 {
        "a finite inclination from 0 to π/2 rad"
    } else {
        "a finite inclination from 0 to π rad"
    };
    v.map_or(Ok(()), |v| within(what, field, v, 0.0, hi, expected))
}

/// Checks one node's fields (not its id's uniqueness).
pub fn check_node(n: &Node) -> Result<(), Invalid> {
    let what = format!("node {}", n.id);
    coordinate(&what, "x_m", n.x_m)?;
    coordinate(&what, "y_m", n.y_m)?;
    name(&what, "kind", &n.kind)?;
    if let Some(s) = &n.subtype {
        name(&what, "subtype", s)?;
    }
    angle(
        &what,
        "slope_inclination_rad",
        n.slope_inclination_rad,
        FRAC_PI_2,
    )?;
    distance(&what, "step_height_m", n.step_height_m)?;
    angle(
        &what,
        "max_robot_inclination_rad",
        n.max_robot_inclination_rad,
        PI,
    )?;
    Ok(())
}

/// Checks one link's own fields (not its ends or its id's uniqueness).
pub fn check_link(l: &Link) -> Result<(), Invalid> {
    let what = format!("link {}", l.id);
    within(
        &what,
        "direction_rad",
        l.direction_rad,
        -MAX_ABS_DIRECTION_RAD,
        MAX_ABS_DIRECTION_RAD,
        "a finite angle in radians",
    )?;
    distance(&what, "length_m", l.length_m)?;
    distance(&what, "min_width_m", l.min_width_m)?;
    angle(&what, "max_inclination_rad", l.max_inclination_rad, PI)?;
    distance(&what, "max_step_m", l.max_step_m)?;
    Ok(())
}

/// Checks a whole map: counts, every node and link, unique ids, links between nodes of the
/// map. The first problem found is the error (nodes first, in order, then links).
pub fn check(btm: &Btm) -> Result<(), Invalid> {
    if btm.nodes.len() > MAX_NODES {
        return Err(
            Invalid::new("map", "nodes", format!("{} nodes", btm.nodes.len()))
                .expected(format!("at most {MAX_NODES}")),
        );
    }
    if btm.links.len() > MAX_LINKS {
        return Err(
            Invalid::new("map", "links", format!("{} links", btm.links.len()))
                .expected(format!("at most {MAX_LINKS}")),
        );
    }
    let mut nodes = BTreeSet::new();
    for n in &btm.nodes {
        if !nodes.insert(n.id) {
            return Err(
                Invalid::new(format!("node {}", n.id), "id", "a second node with this id")
                    .expected("unique node ids"),
            );
        }
        check_node(n)?;
    }
    let mut links = BTreeSet::new();
    for l in &btm.links {
        if !links.insert(l.id) {
            return Err(
                Invalid::new(format!("link {}", l.id), "id", "a second link with this id")
                    .expected("unique link ids"),
            );
        }
        check_link(l)?;
        let ends = [("start", Some(l.start)), ("end", l.end)];
        for (field, end) in ends {
            if let Some(id) = end.filter(|id| !nodes.contains(id)) {
                return Err(Invalid::new(
                    format!("link {}", l.id),
                    field,
                    format!("node {id}, which does not exist"),
                )
                .expected("the id of a node of the map"));
            }
        }
    }
    Ok(())
}

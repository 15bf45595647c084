//! The ideal number of robots i(p) for a candidate location (paper 002 §3.3, Fig. 1–2,
//! Algorithms 1–2), by Mamdani inference ([`crate::fuzzy`]).
//!
//! The paper's figures with the membership functions are missing from the text and it lists
//! only sample rules, so both are designed here and documented:
//!
//! - **Membership functions** (three terms LOW/SMALL, MEDIUM, HIGH/BIG per input): room size on
//!   the label thresholds of the generators (small < 30 m², big > 60 m² — a 20 m laser sees a
//!   whole small room from its door), doors 1 / 2 / 3+, visibility (free fraction of the room)
//!   0.5 / 0.7 / 0.9, already-perceived fraction 0.2 / 0.5 / 0.8; corridor size 15 / 35 / 70 m²,
//!   doors 2 / 4 / 6+, intersecting corridors 0 / 1–2 / 3+. Output terms are triangles centred
//!   on 1, 2, 3 (and 4 for VERY_HIGH) robots.
//! - **Rule bases** (all 81 combinations each): the consequent follows an additive score of
//!   the antecedent levels (0, 1, 2), fitted so that every sample rule of Algorithms 1–2 is
//!   reproduced exactly —
//!   rooms: score = size + doors + visibility − perceived; ≤ 0 LOW, 1–3 MEDIUM, ≥ 4 HIGH
//!   ("if the room is large, the number of its doors is large, its visibility is large, and the
//!   already perceived area is small, then more robots are allocated");
//!   corridors: score = 2·size + doors + intersections − 3·perceived; ≤ 0 LOW, 1–3 MEDIUM,
//!   4–6 HIGH, ≥ 7 VERY_HIGH (Algorithm 2 needs the perceived area to weigh more than doors and
//!   intersections together: its rule 1 gives LOW to a small corridor with many doors and half
//!   seen, its rule 2 MEDIUM to a small unseen one);
//!   in both, an already-perceived area that is HIGH gives LOW whatever the rest, as Algorithm 1's
//!   rule 2 does for a big room. Without it, a big open room with three doors, 90 % seen, got
//!   three robots for the frontiers its furniture shadows: on the mall, MRv1 sent two or three
//!   robots to big rooms already ≥ 80 % known in 116 of its 312 allocations (seed 1).
//!
//! The crisp result is the centroid rounded to the nearest integer, clamped to
//! [1, `max_robots`] (the paper's experiments: 1–3).

use crate::fuzzy::{Mamdani, Membership, Rule, Variable};

fn tri(a: f64, b: f64, c: f64) -> Membership {
    Membership::Triangle { a, b, c }
}

fn trap(a: f64, b: f64, c: f64, d: f64) -> Membership {
    Membership::Trapezoid { a, b, c, d }
}

fn var(name: &str, terms: [(&str, Membership); 3]) -> Variable {
    Variable {
        name: name.into(),
        terms: terms.iter().map(|(n, m)| (n.to_string(), *m)).collect(),
    }
}

fn output(levels: &[&str]) -> Variable {
    Variable {
        name: "#Robots".into(),
        terms: levels
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let c = i as f64 + 1.0;
                (n.to_string(), tri(c - 1.0, c, c + 1.0))
            })
            .collect(),
    }
}

const INF: f64 = f64::INFINITY;

/// The level of AlreadyPercArea (HIGH) at which any room or corridor needs one robot: what is
/// left of it is small, and a second robot there only overlaps the first.
const MOSTLY_PERCEIVED: usize = 2;

fn perceived() -> Variable {
    var(
        "AlreadyPercArea",
        [
            ("LOW", trap(-INF, 0.0, 0.2, 0.5)),
            ("MEDIUM", tri(0.2, 0.5, 0.8)),
            ("HIGH", trap(0.5, 0.8, 1.0, INF)),
        ],
    )
}

/// Every combination of three-level antecedents. The last input is AlreadyPercArea: at
/// [`MOSTLY_PERCEIVED`] the consequent is the lowest, whatever the rest; otherwise it comes
/// from `consequent`.
fn rules(inputs: usize, consequent: impl Fn(&[usize]) -> usize) -> Vec<Rule> {
    (0..3usize.pow(inputs as u32))
        .map(|k| {
            let levels: Vec<usize> = (0..inputs).map(|i| k / 3usize.pow(i as u32) % 3).collect();
            Rule {
                consequent: if levels[inputs - 1] == MOSTLY_PERCEIVED {
                    0
                } else {
                    consequent(&levels)
                },
                antecedents: levels,
            }
        })
        .collect()
}

/// The room system: inputs (room size m², doors, visibility fraction, perceived fraction).
pub fn room_system() -> Mamdani {
    Mamdani {
        inputs: vec![
            var(
                "RoomSize",
                [
                    ("SMALL", trap(-INF, 0.0, 15.0, 30.0)),
                    ("MEDIUM", tri(15.0, 40.0, 65.0)),
                    ("BIG", trap(45.0, 70.0, INF, INF)),
                ],
            ),
            var(
                "#Doors",
                [
                    ("LOW", trap(-INF, 0.0, 1.0, 2.0)),
                    ("MEDIUM", tri(1.0, 2.0, 3.0)),
                    ("HIGH", trap(2.0, 3.0, INF, INF)),
                ],
            ),
            var(
                "Visibility",
                [
                    ("LOW", trap(-INF, 0.0, 0.5, 0.7)),
                    ("MEDIUM", tri(0.5, 0.7, 0.9)),
                    ("HIGH", trap(0.7, 0.9, 1.0, INF)),
                ],
            ),
            perceived(),
        ],
        output: output(&["LOW", "MEDIUM", "HIGH"]),
        output_range: (0.0, 4.0),
        rules: rules(4, |l| {
            let score = (l[0] + l[1] + l[2]) as i64 - l[3] as i64;
            match score {
                ..=0 => 0,
                1..=3 => 1,
                _ => 2,
            }
        }),
    }
}

/// The corridor system: inputs (corridor size m², doors, intersecting corridors, perceived).
pub fn corridor_system() -> Mamdani {
    Mamdani {
        inputs: vec![
            var(
                "CorridorSize",
                [
                    ("SMALL", trap(-INF, 0.0, 15.0, 35.0)),
                    ("MEDIUM", tri(15.0, 35.0, 70.0)),
                    ("BIG", trap(35.0, 70.0, INF, INF)),
                ],
            ),
            var(
                "#Doors",
                [
                    ("LOW", trap(-INF, 0.0, 2.0, 4.0)),
                    ("MEDIUM", tri(2.0, 4.0, 6.0)),
                    ("HIGH", trap(4.0, 6.0, INF, INF)),
                ],
            ),
            var(
                "#IntersectingCorridors",
                [
                    ("LOW", trap(-INF, 0.0, 0.0, 1.5)),
                    ("MEDIUM", tri(0.0, 1.5, 3.0)),
                    ("HIGH", trap(1.5, 3.0, INF, INF)),
                ],
            ),
            perceived(),
        ],
        output: output(&["LOW", "MEDIUM", "HIGH", "VERY_HIGH"]),
        output_range: (0.0, 5.0),
        rules: rules(4, |l| {
            let score = 2 * l[0] as i64 + l[1] as i64 + l[2] as i64 - 3 * l[3] as i64;
            match score {
                ..=0 => 0,
                1..=3 => 1,
                4..=6 => 2,
                _ => 3,
            }
        }),
    }
}

/// The crisp team size: the centroid rounded, clamped to [1, max_robots]; 1 when no rule fires.
pub fn ideal_robots(system: &Mamdani, inputs: &[f64], max_robots: usize) -> usize {
    system
        .infer(inputs)
        .map_or(1, |c| (c.round().max(1.0) as usize).min(max_robots.max(1)))
}

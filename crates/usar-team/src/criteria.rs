//! The criteria of paper 002's MCDM strategies (§3.2) for a candidate p and a robot r:
//!
//! - A(p): expected free area beyond p's frontier, the frontier's length in cells (benefit);
//! - d(p, r): Euclidean distance from r to p (cost);
//! - b(p, r): energy to reach p, proportional to the time to follow the planned path at the
//!   robot's linear and angular speeds: length / v + Σ|turns| / ω (cost);
//! - S(p): relevance of p's semantic label under the *a priori* hypothesis on where victims
//!   are (benefit) — hypotheses are data ([`Hypothesis`]);
//! - ND(p): number of doors of the room p lies in (benefit).
//!
//! [`utilities`] normalises each criterion linearly over the pairs compared and combines them
//! with the Choquet integral of a strategy's fuzzy measure.

use crate::mcdm::{FuzzyMeasure, Sense, normalize};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use usar_world::{Point2, RoomLabel};

/// A priori knowledge of where victims are: relevance S ∈ [0, 1] per label.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hypothesis {
    pub name: String,
    pub relevance: BTreeMap<RoomLabel, f64>,
}

impl Hypothesis {
    /// "Victims are in big rooms": big 1, small 0, corridor 0.15 (paper 002 §3.2). Medium rooms,
    /// which §3.2 does not rate, are not where the victims are believed to be: 0, like small
    /// rooms. (S runs from 0, not relevant, to 1, relevant; the relevant area of Tables 4 and 6
    /// is the big rooms' area only, and only corridors get an intermediate value, "as corridors
    /// are usually important to reach relevant rooms".)
    pub fn big_rooms() -> Self {
        Self::of(
            "big",
            [
                (RoomLabel::BigRoom, 1.0),
                (RoomLabel::MediumRoom, 0.0),
                (RoomLabel::SmallRoom, 0.0),
            ],
        )
    }

    /// "Victims are in small rooms": small 1, big 0, medium 0, corridor 0.15.
    pub fn small_rooms() -> Self {
        Self::of(
            "small",
            [
                (RoomLabel::SmallRoom, 1.0),
                (RoomLabel::MediumRoom, 0.0),
                (RoomLabel::BigRoom, 0.0),
            ],
        )
    }

    /// A built-in hypothesis by name: `big` or `small`.
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "big" => Some(Self::big_rooms()),
            "small" => Some(Self::small_rooms()),
            _ => None,
        }
    }

    fn of(name: &str, rooms: [(RoomLabel, f64); 3]) -> Self {
        let mut relevance: BTreeMap<RoomLabel, f64> = rooms.into_iter().collect();
        relevance.insert(RoomLabel::Corridor, 0.15);
        Self {
            name: name.into(),
            relevance,
        }
    }

    /// S(p) for a candidate with perceived label `label` (0 when unlabelled or unrated).
    pub fn relevance(&self, label: Option<RoomLabel>) -> f64 {
        label
            .and_then(|l| self.relevance.get(&l).copied())
            .unwrap_or(0.0)
    }

    /// Whether cells with `label` count as relevant area (S = 1).
    pub fn is_relevant(&self, label: Option<RoomLabel>) -> bool {
        self.relevance(label) >= 1.0
    }
}

/// What is known about a candidate location.
#[derive(Clone, Debug, PartialEq)]
pub struct CandidateInfo {
    pub position: Point2,
    /// Frontier length, cells: the cluster's, or the whole room's with one candidate per room.
    pub frontier_cells: usize,
    pub label: Option<RoomLabel>,
    pub doors: usize,
}

/// b(p, r): time to follow `path` (metres between waypoints, headings turned) from a robot at
/// heading `theta` with speeds `v` (m/s) and `omega` (rad/s), seconds.
pub fn travel_time_s(path: &[Point2], theta: f64, v: f64, omega: f64) -> f64 {
    let mut heading = theta;
    let (mut length, mut turning) = (0.0, 0.0);
    for w in path.windows(2) {
        let d = w[0].distance(w[1]);
        if d < 1e-9 {
            continue;
        }
        let h = w[0].bearing_to(w[1]);
        turning += usar_world::normalize_angle(h - heading).abs();
        heading = h;
        length += d;
    }
    length / v + turning / omega
}

/// A criterion of the MCDM strategies, by the name the fuzzy measures use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Criterion {
    A,
    D,
    B,
    S,
    Nd,
}

impl Criterion {
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "A" => Criterion::A,
            "d" => Criterion::D,
            "b" => Criterion::B,
            "S" => Criterion::S,
            "ND" => Criterion::Nd,
            _ => return None,
        })
    }

    fn sense(self) -> Sense {
        match self {
            Criterion::D | Criterion::B => Sense::Cost,
            _ => Sense::Benefit,
        }
    }
}

/// u(p, r) for every robot and candidate: `travel[r][p]` is b(p, r) in seconds (`None`:
/// unreachable). Criteria come from the measure's names (A, d, b, S, ND); unknown names are an
/// error.
pub fn utilities(
    measure: &FuzzyMeasure,
    robots: &[Point2],
    candidates: &[CandidateInfo],
    travel: &[Vec<Option<f64>>],
    hypothesis: &Hypothesis,
) -> Result<Vec<Vec<Option<f64>>>, String> {
    let criteria: Vec<Criterion> = measure
        .criteria
        .iter()
        .map(|c| {
            Criterion::from_name(c)
                .ok_or_else(|| format!("unknown criterion `{c}`, expected A, d, b, S or ND"))
        })
        .collect::<Result<_, _>>()?;
    let pairs: Vec<(usize, usize)> = (0..robots.len())
        .flat_map(|r| (0..candidates.len()).map(move |p| (r, p)))
        .collect();
    // Raw values per criterion over all pairs (None where the robot cannot reach p).
    let columns: Vec<Vec<Option<f64>>> = criteria
        .iter()
        .map(|c| {
            let raw: Vec<Option<f64>> = pairs
                .iter()
                .map(|&(r, p)| {
                    let t = travel[r][p]?;
                    let cand = &candidates[p];
                    Some(match c {
                        Criterion::A => cand.frontier_cells as f64,
                        Criterion::D => robots[r].distance(cand.position),
                        Criterion::B => t,
                        Criterion::S => hypothesis.relevance(cand.label),
                        Criterion::Nd => cand.doors as f64,
                    })
                })
                .collect();
            normalize(&raw, c.sense())
        })
        .collect();
    let mut out = vec![vec![None; candidates.len()]; robots.len()];
    for (k, &(r, p)) in pairs.iter().enumerate() {
        let u: Option<Vec<f64>> = columns.iter().map(|col| col[k]).collect();
        out[r][p] = u.map(|u| measure.choquet(&u));
    }
    Ok(out)
}

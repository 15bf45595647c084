//! The robots' bids u(p, r) at an auction (paper 002 §3.2–3.3) under each strategy, and the
//! ideal team size i(p) of each candidate location from its perceived label.

use crate::config::Strategy;
use crate::criteria::{CandidateInfo, Hypothesis, utilities};
use crate::fuzzy::Mamdani;
use crate::mcdm::{FuzzyMeasure, Sense, normalize};
use crate::semantic_map::RoomFacts;
use crate::team_size::{corridor_system, ideal_robots, room_system};
use rand::Rng;
use rand_pcg::Pcg64Mcg;
use usar_world::{Point2, RoomLabel};

/// What a robot's planner knows of its way to each candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Travel {
    /// Length of the planned path, metres.
    pub length_m: f64,
    /// Time to follow it at the robot's linear and angular speeds, seconds (b(p, r)).
    pub time_s: f64,
}

/// The measures of the two MCDM strategies, completed once per mission.
#[derive(Clone, Debug)]
pub struct Measures {
    pub s_mcdm: FuzzyMeasure,
    pub d_mcdm: FuzzyMeasure,
}

/// u(p, r) for each bidding robot (rows) and candidate (columns); `None` where the robot cannot
/// reach the candidate (or may not have it).
pub fn bids(
    strategy: Strategy,
    measures: &Measures,
    hypothesis: &Hypothesis,
    robots: &[Point2],
    candidates: &[CandidateInfo],
    travel: &[Vec<Option<Travel>>],
    rng: &mut Pcg64Mcg,
) -> Vec<Vec<Option<f64>>> {
    match strategy {
        // Random: a fresh uniform draw per pair and auction.
        Strategy::Random => travel
            .iter()
            .map(|row| row.iter().map(|t| t.map(|_| rng.random::<f64>())).collect())
            .collect(),
        // Distance (and the baseline when it is auctioned): shorter paths are better.
        Strategy::Distance | Strategy::Nearest => {
            let flat: Vec<Option<f64>> = travel
                .iter()
                .flatten()
                .map(|t| t.map(|t| t.length_m))
                .collect();
            let u = normalize(&flat, Sense::Cost);
            let n = candidates.len();
            (0..travel.len())
                .map(|r| u[r * n..(r + 1) * n].to_vec())
                .collect()
        }
        Strategy::DMcdm | Strategy::SMcdm => {
            let measure = if strategy == Strategy::SMcdm {
                &measures.s_mcdm
            } else {
                &measures.d_mcdm
            };
            let times: Vec<Vec<Option<f64>>> = travel
                .iter()
                .map(|row| row.iter().map(|t| t.map(|t| t.time_s)).collect())
                .collect();
            utilities(measure, robots, candidates, &times, hypothesis)
                .expect("measures are checked when the mission starts")
        }
    }
}

/// The Mamdani systems of i(p), built once per mission.
#[derive(Clone, Debug)]
pub struct TeamSizer {
    room: Mamdani,
    corridor: Mamdani,
    max_robots: usize,
}

impl TeamSizer {
    pub fn new(max_robots: usize) -> Self {
        Self {
            room: room_system(),
            corridor: corridor_system(),
            max_robots,
        }
    }

    /// i(p) for a candidate in `room` (None: outside every room, 1) perceived as `label`,
    /// `perceived` of the room known: the corridor system (size, doors, intersecting
    /// corridors, perceived area) for a corridor, the room system (size, doors, visibility,
    /// perceived area) otherwise.
    pub fn ideal(
        &self,
        room: Option<&RoomFacts>,
        label: Option<RoomLabel>,
        perceived: f64,
    ) -> usize {
        let Some(room) = room else {
            return 1;
        };
        if label == Some(RoomLabel::Corridor) {
            ideal_robots(
                &self.corridor,
                &[
                    room.area_m2,
                    room.doors as f64,
                    room.intersecting_corridors as f64,
                    perceived,
                ],
                self.max_robots,
            )
        } else {
            ideal_robots(
                &self.room,
                &[room.area_m2, room.doors as f64, room.visibility, perceived],
                self.max_robots,
            )
        }
    }
}

//! `usar-team` runs multirobot exploration missions (paper 002): robots scan with their 2-D
//! lasers, a base station merges their occupancy grids, frontier clusters give candidate
//! locations, candidates are assigned to robots, robots follow A*/distance-field paths, and the
//! mission records coverage, explored area, distance and victims seen over time.
//!
//! Two ways to hand out candidates: the baseline explorer (`Strategy::Nearest`: each robot to
//! its nearest candidate, one robot per candidate; what `demo` and `explore` run), and paper
//! 002's auctions (every 5 s and when a robot arrives) with the Random, Distance, D-MCDM or
//! S-MCDM strategy and SR, MRv1 or MRv2 coordination, over one candidate per room by default
//! (`room_candidates`; one per frontier cluster as §3.1 has it on request), on a semantic map whose labels may be perceived with errors; the mission
//! then also measures the explored relevant area. Maps
//! without a room layer get one from `usar_map::segmentation` (`scene_prep`).

pub mod assignment;
pub mod base_station;
pub mod bids;
mod config;
pub mod coordination;
pub mod coverage;
pub mod criteria;
pub mod driver;
pub mod fuzzy;
pub mod mcdm;
mod mission;
mod outcome;
pub mod paper_run;
pub mod report;
pub mod room_candidates;
pub mod runner;
pub mod scene_prep;
pub mod semantic_map;
pub mod setup;
pub mod team_size;
pub mod travel_time;
pub mod tuning;

pub use self::config::{
    Exploration, Localization, Radio, RobotFailure, Semantics, Strategy, TeamConfig, Timing,
};
pub use self::mission::{
    Allocate, Auction, ConfigError, MissionError, NearestFrontier, TeamController, TeamEvaluation,
    TeamMission, VictimReport,
};
pub use self::outcome::{Allocation, Finish, RobotOutcome, Sample, TeamOutcome, VictimSighting};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! `usar-team` runs multirobot exploration missions (paper 002): robots scan with their 2-D
//! lasers, a base station merges their occupancy grids, frontier clusters give candidate
//! locations, candidates are assigned to robots, robots follow A*/distance-field paths, and the
//! mission records coverage, explored area, distance and victims seen over time.
//!
//! The strategy implemented so far is the baseline *Distance* strategy with single-robot
//! coordination: each robot goes to its nearest frontier candidate.

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
pub mod semantic_map;
pub mod team_size;

pub use self::config::{Exploration, Radio, RobotFailure, Strategy, TeamConfig, Timing};
pub use self::mission::{MissionError, TeamMission};
pub use self::outcome::{Finish, RobotOutcome, Sample, TeamOutcome, VictimSighting};

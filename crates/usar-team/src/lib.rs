//! `usar-team` runs multirobot exploration missions (paper 002): robots scan with their 2-D
//! lasers, a base station merges their occupancy grids, frontier clusters give candidate
//! locations, candidates are assigned to robots, robots follow A*/distance-field paths, and the
//! mission records coverage, explored area, distance and victims seen over time.
//!
//! The strategy implemented so far is the baseline *Distance* strategy with single-robot
//! coordination: each robot goes to its nearest frontier candidate.

pub mod assignment;
pub mod base_station;
mod config;
pub mod coordination;
pub mod coverage;
pub mod criteria;
pub mod driver;
pub mod fuzzy;
pub mod mcdm;
mod mission;
mod outcome;
pub mod report;
pub mod team_size;

pub use self::config::{TeamConfig, Timing};
pub use self::mission::{MissionError, TeamMission};
pub use self::outcome::{Finish, RobotOutcome, Sample, TeamOutcome, VictimSighting};

//! `usar-mission`: the whole mission in one world. Paper 002's wheeled explorers, paper 004's
//! crawler and paper 000's MAXQ rescuer run as controllers on one host — one physics: they see
//! each other in their lasers and block each other. The crawler builds a Behavioral Trace Map
//! and sends it over the radio; the team's base station closes to its wheeled robots every link
//! and node the crawler measured too steep, too narrow or too high a step for them. The rescuer
//! searches a rubble zone of the floor; one operator answers every hand-off ([`board`] holds
//! the team's victim reports). The evaluation follows every controller from outside (ground
//! truth never reaches a controller), and [`report`] writes the report folder.
//!
//! ```
//! use std::sync::Arc;
//! use usar_mission::{MissionConfig, run_mission};
//! use usar_world::generate::{SceneKind, generate};
//!
//! let scene = Arc::new(generate(SceneKind::Office, 1));
//! let config = MissionConfig { minutes: 0.5, ..MissionConfig::default() };
//! let outcome = run_mission(scene, &config, 1, None, |_| {}).unwrap();
//! assert_eq!(outcome.team.robots, 4);
//! assert!(outcome.team.explored_area_m2 > 0.0);
//! assert!(outcome.crawler.as_ref().unwrap().nodes > 0);
//! assert!(outcome.rescuer.is_some());
//! ```

pub mod board;
pub mod config;
pub mod controllers;
pub mod live;
mod mission;
mod outcome;
pub mod report;
mod rescuer;
pub mod runner;
mod tally;
mod zone;

pub use self::config::{CrawlerPart, MissionConfig, RescuerPart, TeamPart};
pub use self::live::{LiveMission, MissionHook, Operator};
pub use self::mission::{run_mission, run_mission_live};
pub use self::outcome::{
    CrawlerFigures, MissionOutcome, MissionSample, OperatorFigures, RescuerFigures, TeamFigures,
    VictimFigures, VictimRow,
};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

use usar_btm::build::BuildError;
use usar_sim::PlacementError;
use usar_team::MissionError as TeamError;

/// Why a mission could not run.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// A field of the mission file holds a value outside what it accepts.
    #[error("mission field {field}: {message}")]
    Config { field: String, message: String },
    #[error("the scene has room for {available} robots, the mission has {requested}")]
    NotEnoughRoom { available: usize, requested: usize },
    #[error(transparent)]
    Team(#[from] TeamError),
    /// A `[team]` setting named something unknown or held a value out of range.
    #[error("mission field team.{0}")]
    TeamSetting(#[from] usar_team::setup::SetupError),
    #[error(transparent)]
    Placement(#[from] PlacementError),
    #[error(transparent)]
    Build(#[from] BuildError),
    #[error(transparent)]
    Robot(#[from] usar_sim::SimError),
}

impl MissionError {
    /// Whether the mission's input is at fault (a bad file or value) rather than something
    /// that failed while it ran (writing the crawler's map to its store).
    pub fn is_input(&self) -> bool {
        !matches!(self, MissionError::Build(BuildError::Store(_)))
    }
}

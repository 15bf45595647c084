//! `usar-record`: runs recorded as MCAP files of ROS 2 messages, for Foxglove, Lichtblick,
//! Rerun or `ros2 bag play`: [`cdr`] encodes, [`msgs`] defines the message types,
//! [`Recording`] writes the file, [`MissionRecorder`] records a mission as it runs (see its
//! module for the topics).
//!
//! ```
//! use std::sync::Arc;
//! use usar_mission::{MissionConfig, Operator, run_mission_live};
//! use usar_record::{MissionRecorder, Recording};
//! use usar_world::generate::{SceneKind, generate};
//!
//! let scene = Arc::new(generate(SceneKind::Office, 1));
//! let mut config = MissionConfig { minutes: 0.1, ..MissionConfig::default() };
//! config.rescuer.train_trials = 20;
//! let mut recorder = MissionRecorder::new(Recording::new(std::io::Cursor::new(Vec::new())).unwrap());
//! run_mission_live(scene, &config, 1, None, Operator::Simulated, |_| {}, &mut recorder).unwrap();
//! assert!(recorder.finish().unwrap() > 100);
//! ```

mod btm;
pub mod cdr;
mod mission;
pub mod msgs;
mod recording;
mod rescue;
mod team;

pub use self::btm::BtmRecorder;
pub use self::mission::MissionRecorder;
pub use self::recording::Recording;
pub use self::rescue::RescueRecorder;
pub use self::team::TeamRecorder;

/// Why a recording failed.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// Writing the file failed (the disk, or the MCAP writer).
    #[error("recording: {0}")]
    Mcap(#[from] mcap::McapError),
}

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

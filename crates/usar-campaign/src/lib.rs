//! `usar-campaign`: the experiment engine every controller uses.
//!
//! A campaign file ([`design`]) names a runner, factors and levels; the engine ([`engine`])
//! expands the full factorial design and runs it in parallel, committing each run to a SQLite
//! database ([`store`]) so that a killed campaign resumes where it stopped, shards run on
//! several machines and merge. [`stats`] holds the tests the papers use, [`report`] the tables
//! and plots, [`export`] the CSV for analysis elsewhere. Controllers plug in as [`Runner`]s.

pub mod design;
pub mod engine;
pub mod error;
pub mod export;
pub mod lock;
pub mod report;
pub mod runner;
pub mod slurm;
pub mod stats;
pub mod store;

pub use self::design::{CampaignFile, Config, Design, Level};
pub use self::engine::{RunReport, Shard, run_design};
pub use self::error::{CampaignError, Result};
pub use self::lock::FolderLock;
pub use self::runner::{
    FactorKind, FactorSpec, MetricSpec, NoopRunner, RunError, RunOutput, Runner, SeriesPoint,
};
pub use self::store::{Store, merge};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! `usar-btm`: Behavioral Trace Maps (paper 004). The node and link tables ([`model`]), their
//! SQLite database written while a robot drives ([`store`]), JSON / GraphML exchange
//! ([`exchange`]), the compact binary form for radio links ([`wire`]), autonomous generation by a robot exploring in the simulator ([`build`])
//! and its locomotion behaviours ([`locomotion`]). Every map read from a file is checked
//! ([`validate`]) before it is used. [`report`] has what the `usar btm` commands write and show
//! (a map built into its file, its drawing, the trajectory CSV, sizes, the JSON view).

pub mod build;
pub mod exchange;
pub mod locomotion;
pub mod merge;
pub mod model;
pub mod plan;
pub mod render;
pub mod report;
pub mod store;
pub mod validate;
pub mod wire;

pub use self::build::{BuildConfig, BuildError, BuildOutcome, StopReason, build_btm};
pub use self::model::{Btm, Link, Node};
pub use self::store::{BtmError, BtmStore};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

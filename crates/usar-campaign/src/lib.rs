//! `usar-campaign`: the experiment engine.
pub mod stats;

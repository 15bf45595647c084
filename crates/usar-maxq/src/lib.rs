//! `usar-maxq`: paper 000's learning machinery. A generic MAXQ-Q engine ([`maxq`]) over any
//! [`Domain`] and [`Hierarchy`], flat Q-learning for comparison ([`flat_q`]), the learning-rate
//! and exploration schedules ([`schedule`]), and Dietterich's Taxi domain ([`taxi`]) as the
//! engine's correctness check. The USAR hierarchy of paper 000 (Root → NUR, VI, HC; NG → F, B,
//! rotate) builds on the same engine.

pub mod flat_q;
pub mod maxq;
pub mod schedule;
pub mod stepper;
pub mod taxi;

pub use self::flat_q::{FlatQ, SparseFlatQ};
pub use self::maxq::{
    Domain, Episode, Hierarchy, LearningParams, MaxqQ, Node, NodeId, NodeKind, Observed,
};
pub use self::schedule::{ParamError, Schedule};
pub use self::stepper::{Delegation, GreedyStepper, Next};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

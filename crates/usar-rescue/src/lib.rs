//! `usar-rescue`: paper 000's learning-based semi-autonomous controller for a rescue robot
//! exploring an unknown rubble scene while searching for victims (Doroodgar, Liu, Nejat 2014).
//!
//! - [`hierarchy`]: the MAXQ task graph Root → {NUR, VI, HC₂}, NUR → {Exit, NG, HC₃},
//!   VI → {Tag, NG, HC₃}, NG → {F, B, rotate θ}, with the state abstractions of §IV-A;
//! - [`domain`]: the robot, its cell map ([`cell_map`]), its sensors ([`perception`]: D_xy
//!   plane fits, infrared, thermal victim probability), the rewards of Table I ([`rewards`]);
//! - [`exploration`]: the direction-based exploration of §V (eq. 7–10, Table II);
//! - [`operator`]: the hand-off interface and a simulated operator;
//! - [`training`], [`evaluation`], [`teleoperation`]: the experiments of §VI and §VII-B, and
//!   [`analysis`]: §VI-B's statistics over an evaluation, [`figures`]: their figures;
//! - [`policy`]: the versioned policy file;
//! - [`runner`]: the campaign runner `maxq-eval` (one §VI-B run per configuration and seed).
//!
//! ```
//! use usar_rescue::{DomainConfig, RescueDomain, RescueScene};
//! use usar_rescue::exploration::ExplorationWeights;
//! use usar_rescue::operator::{OperatorProfile, SimulatedOperator};
//! use usar_world::generate::{RubbleParams, generate_rubble};
//!
//! let scene = RescueScene::new(generate_rubble(1, &RubbleParams::default()));
//! let start = scene.start(0).unwrap();
//! let operator = SimulatedOperator::new(OperatorProfile::expert(), 1);
//! let weights = ExplorationWeights::named("travel").unwrap();
//! let domain = RescueDomain::new(&scene, start, weights, DomainConfig::default(), operator, 1);
//! assert!(domain.guidance().heading.is_some()); // there is something to explore
//! ```

pub mod agent;
pub mod analysis;
pub mod cell_map;
pub mod controller;
pub mod desk;
pub mod domain;
pub mod evaluation;
pub mod exploration;
pub mod figures;
pub mod hierarchy;
mod marks;
pub mod operator;
pub mod perception;
pub mod policy;
pub mod rewards;
pub mod runner;
pub mod state;
pub mod teleoperation;
pub mod training;
pub mod travel;

pub use self::agent::RescueAgent;
pub use self::controller::{RescueController, RescueLog};
pub use self::domain::{DomainConfig, RescueDomain, RescueScene, RunStats, VictimMark};
pub use self::hierarchy::RescueHierarchy;
pub use self::state::{RescueState, VictimStatus};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

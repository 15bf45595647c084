//! `usar-map` holds what a robot knows and how it plans: the log-odds occupancy grid built from
//! laser scans and merged at a base station, frontier cells and frontier clusters with their
//! candidate locations, grid A* (4- and 8-connected, octile, no corner cutting, inflated
//! obstacles), a generic A* for graphs, distance fields that price every goal at once, and
//! [`localization`]: odometry corrected by scan matching against a key scan or the robot's own
//! map.

pub mod frontier;
pub mod localization;
pub mod navigable;
pub mod occupancy;
pub mod planning;
pub mod segmentation;

pub use self::frontier::{FrontierCluster, FrontierTracker};
pub use self::navigable::NavigableMap;
pub use self::occupancy::{CellClass, OccupancyGrid, OccupancyParams};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! Configuration of a team mission.

use serde::{Deserialize, Serialize};
use usar_sim::{RobotSpec, SimConfig};

/// How often things happen during a mission, seconds of simulated time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// Each robot takes a laser scan this often.
    pub scan_period_s: f64,
    /// The base station merges the robots' maps this often (paper 002 §4.1: 2.5 s).
    pub merge_period_s: f64,
    /// Targets are reassigned this often, besides when a robot reaches its target (paper 002:
    /// auctions every 5 s).
    pub assignment_period_s: f64,
    /// Each robot reads its thermal camera this often.
    pub thermal_period_s: f64,
    /// Metrics are sampled this often for the time series.
    pub sample_period_s: f64,
}

impl Default for Timing {
    fn default() -> Self {
        Self {
            scan_period_s: 0.25,
            merge_period_s: 2.5,
            assignment_period_s: 5.0,
            thermal_period_s: 0.5,
            sample_period_s: 10.0,
        }
    }
}

/// A team mission: how many robots of which kind, for how long.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TeamConfig {
    pub robots: usize,
    pub robot: RobotSpec,
    /// Simulated time limit, seconds.
    pub duration_s: f64,
    /// Stop when this fraction of the reachable area is known (None: explore until the time
    /// limit or until no frontier is left).
    pub stop_at_coverage: Option<f64>,
    /// Stop when coverage grew by less than `stall_growth` during this long (None: never).
    /// Frontiers behind gaps narrower than the robot, or seen through glass-like noise, can
    /// stay forever; this ends the mission instead of running out the clock.
    pub stall_after_s: Option<f64>,
    /// See `stall_after_s`; a fraction of the reachable area.
    pub stall_growth: f64,
    /// Frontier clusters smaller than this many cells are ignored (sensor noise leaves specks).
    pub min_cluster_cells: usize,
    pub timing: Timing,
    pub sim: SimConfig,
}

impl Default for TeamConfig {
    fn default() -> Self {
        Self {
            robots: 4,
            robot: RobotSpec::wheeled(),
            duration_s: 20.0 * 60.0,
            stop_at_coverage: None,
            stall_after_s: Some(180.0),
            stall_growth: 0.002,
            min_cluster_cells: 3,
            timing: Timing::default(),
            sim: SimConfig::default(),
        }
    }
}

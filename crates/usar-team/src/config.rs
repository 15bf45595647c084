//! Configuration of a team mission.

use crate::coordination::{Coordination, DiscountParams};
use crate::criteria::Hypothesis;
use crate::mcdm::{MeasureSpec, d_mcdm_table_1, s_mcdm_table_1};
use crate::room_candidates::CandidateGrouping;
use crate::semantic_map::LabelErrors;
use serde::{Deserialize, Serialize};
use usar_sim::{RobotSpec, SimConfig};

/// How candidate locations are valued (paper 002 §3.2, §4.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    /// The baseline explorer: each robot to its nearest candidate by path cost, one robot per
    /// candidate, with commitment to its current target (what `demo` and `explore` run).
    #[default]
    Nearest,
    /// Utility drawn uniformly at random for each (robot, candidate) at each auction.
    Random,
    /// Utility = the normalised path length, shorter is better (Wurm et al. 2008).
    Distance,
    /// Choquet integral over {A, d, b} with [`Exploration::d_mcdm`] (Table 1, right).
    DMcdm,
    /// Choquet integral over {A, d, b, S, ND} with [`Exploration::s_mcdm`] (Table 1, left).
    SMcdm,
}

impl Strategy {
    pub const ALL: [Strategy; 5] = [
        Strategy::Nearest,
        Strategy::Random,
        Strategy::Distance,
        Strategy::DMcdm,
        Strategy::SMcdm,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Strategy::Nearest => "nearest",
            Strategy::Random => "random",
            Strategy::Distance => "distance",
            Strategy::DMcdm => "d-mcdm",
            Strategy::SMcdm => "s-mcdm",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.as_str() == name)
    }
}

/// Paper 002's exploration: strategy, coordination, hypothesis and their parameters. Used by
/// every strategy but [`Strategy::Nearest`], which keeps the baseline's own assignment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Exploration {
    pub strategy: Strategy,
    pub coordination: Coordination,
    /// A priori knowledge of where the victims are: S(p) and what counts as relevant area.
    pub hypothesis: Hypothesis,
    /// Fuzzy measure of S-MCDM (default: Table 1, left).
    pub s_mcdm: MeasureSpec,
    /// Fuzzy measure of D-MCDM (default: Table 1, right).
    pub d_mcdm: MeasureSpec,
    /// MRv2's discount curve (Fig. 3).
    pub discount: DiscountParams,
    /// Upper bound of i(p) (paper: 3).
    pub max_robots_per_candidate: usize,
    /// Semantic perception errors (§4.4).
    pub label_errors: LabelErrors,
    /// How the auctions' candidate locations come from frontier clusters: one per room
    /// (default) or one per cluster, as §3.1 has it (see `room_candidates`).
    pub candidates: CandidateGrouping,
    /// Bids price paths on a grid this many map cells a side per cell (path lengths for b(p, r)
    /// and the Distance strategy); the path a robot drives is planned on the map itself.
    pub bid_grid_factor: usize,
    /// Added to a robot's bid for the candidate it is already heading to (within 1 m of its
    /// target). Without it, bids renormalised at every 5 s auction make robots swap targets
    /// back and forth and never arrive; the paper does not say how its robots avoid this.
    pub commitment_bonus: f64,
}

impl Default for Exploration {
    fn default() -> Self {
        Self {
            strategy: Strategy::Nearest,
            coordination: Coordination::Sr,
            hypothesis: Hypothesis::big_rooms(),
            s_mcdm: s_mcdm_table_1(),
            d_mcdm: d_mcdm_table_1(),
            discount: DiscountParams::default(),
            max_robots_per_candidate: 3,
            label_errors: LabelErrors::Perfect,
            candidates: CandidateGrouping::Room,
            bid_grid_factor: 2,
            commitment_bonus: 0.1,
        }
    }
}

/// The link between robots and the base station. A robot's map reaches the base station, and
/// the robot takes part in an auction, only while it is linked: within `range_m` of the base
/// station (straight line; walls are not modelled) and its message not dropped.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Radio {
    /// Range in metres (None: unlimited, paper 002 §3.1).
    pub range_m: Option<f64>,
    /// Probability that one exchange (a map upload or a bid) is lost.
    pub drop_probability: f64,
}

/// A robot that stops working during the mission; the others carry on.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotFailure {
    /// Index of the robot in the team (0-based).
    pub robot: usize,
    /// When it fails, simulated seconds.
    pub at_s: f64,
}

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
    /// Cell side of the team's occupancy grids, metres (None: the scene's resolution). Paper
    /// 002's grid cells are about 0.9 m² (Tables 2–3); 0.2 m keeps doorways open for planning
    /// at a quarter of the cost of the scene's 0.1 m.
    pub map_resolution_m: Option<f64>,
    /// Paper 002's strategies and coordination.
    pub exploration: Exploration,
    /// Stop when this fraction of the relevant area is known (paper 002 §4.4: 0.9).
    pub stop_at_relevant: Option<f64>,
    pub radio: Radio,
    pub failures: Vec<RobotFailure>,
    /// Skip a robot's scan when it moved less than this (and turned less than
    /// `rescan_turn_rad`) since its last one: the world is static, the scan would add nothing.
    pub rescan_distance_m: f64,
    pub rescan_turn_rad: f64,
    /// Thresholds of driving, recovery and allocation the papers do not give.
    pub tuning: crate::tuning::Tuning,
    /// Where the robots believe they are when they map and drive.
    #[serde(default)]
    pub localization: Localization,
    /// Where the rooms, their labels, areas, doors and visibility come from.
    #[serde(default)]
    pub semantics: Semantics,
}

/// The source of paper 002's semantic knowledge (rooms and their labels).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Semantics {
    /// The semantic oracle: the scene's room layer. Paper 002 §3.1: "we assume the semantic
    /// map as available, because we are only interested in its use. In practice, we manually
    /// annotate with semantic labels the portions of the simulated environments"; its error
    /// models (§4.4) perturb these true labels.
    #[default]
    Oracle,
    /// The team's own estimate: a room segmentation of its merged map as it grows, before
    /// every auction whose map changed.
    Segmented,
}

impl Semantics {
    pub fn name(self) -> &'static str {
        match self {
            Self::Oracle => "oracle",
            Self::Segmented => "segmented",
        }
    }

    /// A source by name (`oracle`, `segmented`).
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "oracle" => Some(Self::Oracle),
            "segmented" => Some(Self::Segmented),
            _ => None,
        }
    }
}

impl TeamConfig {
    /// The oracles the team's controller is given on the host: the localization oracle under
    /// [`Localization::True`].
    pub fn oracles(&self) -> usar_sim::host::Oracles {
        usar_sim::host::Oracles {
            localization: self.localization == Localization::True,
        }
    }
}

/// The pose a team's robots map and drive at.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Localization {
    /// The localization oracle: the true pose. Paper 002 §3.1: "Since we are not interested
    /// in analyzing the quality of the resulting map, we assume that the mapping module is
    /// error-free."
    #[default]
    True,
    /// The robot's own estimate: odometry corrected by scan matching.
    Estimated,
}

impl Localization {
    pub fn name(self) -> &'static str {
        match self {
            Self::True => "true",
            Self::Estimated => "estimated",
        }
    }

    /// A localization by name (`true`, `estimated`).
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "true" => Some(Self::True),
            "estimated" => Some(Self::Estimated),
            _ => None,
        }
    }
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
            map_resolution_m: None,
            exploration: Exploration::default(),
            stop_at_relevant: None,
            radio: Radio::default(),
            failures: Vec::new(),
            rescan_distance_m: 0.0,
            rescan_turn_rad: 0.0,
            tuning: crate::tuning::Tuning::default(),
            localization: Localization::True,
            semantics: Semantics::Oracle,
        }
    }
}

impl TeamConfig {
    /// Paper 002's experimental set-up (§4.1) for `robots` robots exploring for `minutes`:
    /// maps merged every 2.5 s, auctions every 5 s (and when a robot reaches its target),
    /// metrics every simulated minute, no early stop when progress stalls.
    ///
    /// Simulation choices, made for speed and documented here: the team's maps at 0.2 m
    /// (the paper's cells are ~0.9 m², Tables 2–3); one laser scan per robot per second
    /// (0.5 m of travel at the wheeled robot's 0.5 m/s, with a 20 m range), skipped when the
    /// robot has not moved 0.1 m or turned 0.1 rad since its last one; thermal cameras read
    /// every 2 s.
    pub fn paper_002(robots: usize, minutes: f64, exploration: Exploration) -> Self {
        Self {
            robots,
            duration_s: minutes * 60.0,
            stall_after_s: None,
            timing: Timing {
                scan_period_s: 1.0,
                merge_period_s: 2.5,
                assignment_period_s: 5.0,
                thermal_period_s: 2.0,
                sample_period_s: 60.0,
            },
            map_resolution_m: Some(0.2),
            // 1 m of frontier at 0.2 m: a doorway seen from the corridor, not a speck.
            min_cluster_cells: 5,
            exploration,
            rescan_distance_m: 0.1,
            rescan_turn_rad: 0.1,
            ..Self::default()
        }
    }
}

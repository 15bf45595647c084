//! Autonomous generation of a Behavioral Trace Map (paper 004 §III–IV): one robot driven in
//! the simulator from the scene's first start pose builds the BTM while it explores, and
//! writes every new or changed node and link to the store at once.
//!
//! - [`divergence`]: Delaunay triangles of the laser points ahead → divergence nodes and
//!   the links leaving them;
//! - [`free_space`]: entrance and exit of open areas from L_l, L_r against C₁;
//! - [`obstacle`]: the tilted laser's obstacle profile → slope and stairs nodes;
//! - [`links`]: what is measured along a link, and the map writer;
//! - [`usar_map::localization`]: odometry corrected by scan matching against a key scan or
//!   the robot's own map (node coordinates), and the scan in the robot frame;
//! - [`planner`]: routes on the BTM back to un-searched links;
//! - [`crate::locomotion`]: the run modes of §IV and Fig. 8.
//!
//! Exploration is depth first: at a divergence node the robot takes the first un-searched
//! link counter-clockwise from the link it arrived by (§V-A); when a branch ends (a dead
//! end, an obstacle it cannot cross, a loop closed onto a known node) it drives back along
//! searched links to the nearest node that still has an un-searched one. When none is
//! reachable it makes its terminal end node.
//!
//! A loop is closed when a divergence is found within [`BuildConfig::merge_radius_m`] of a
//! known node: the link driven ends there and the known node's un-searched link that points
//! back along it is removed, in memory and in the store ([`BtmStore::delete_link`]).

pub mod config;
pub mod divergence;
mod explorer;
pub mod free_space;
pub mod links;
pub mod obstacle;
pub mod passive;
pub mod planner;

pub use self::config::BuildConfig;
pub use self::explorer::{CrawlerReadings, EstimatedSample, Explorer};

use crate::locomotion::RunMode;
use crate::model::Btm;
use crate::store::{BtmError, BtmStore};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;
use usar_sim::host::{Host, Oracles};
use usar_sim::{RobotSpec, SimConfig};
use usar_world::{Pose2, Scene};

/// Key in a node's `extra` naming the robot that found the obstacle impassable.
pub const IMPASSABLE_FOR: &str = "impassable_for";

/// Key in a link's `extra` naming the robot that gave the link (or the way to it) up after
/// stalling there: the link stays un-searched, for another robot or the operator.
pub const BLOCKED_FOR: &str = "blocked_for";

/// Why the build stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// No un-searched link was reachable any more: the terminal end node was made.
    Explored,
    /// [`BuildConfig::max_time_s`] ran out first.
    TimeLimit,
}

/// The robot at one step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrajectorySample {
    pub time_s: f64,
    /// Where the robot believes it is (odometry and scan matching).
    pub estimated: Pose2,
    /// Where it really is (simulator ground truth, for evaluation only).
    pub truth: Pose2,
    pub mode: RunMode,
    /// Whether the robot's bumper reported contact at this step (a reading the explorer acts
    /// on).
    pub contact: bool,
}

/// What a build produced.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BuildOutcome {
    pub btm: Btm,
    pub trajectory: Vec<TrajectorySample>,
    /// Nodes by "kind" or "kind/subtype".
    pub nodes_by_type: BTreeMap<String, usize>,
    pub searched_links: usize,
    pub unsearched_links: usize,
    pub time_s: f64,
    /// Distance the robot really drove, metres.
    pub distance_m: f64,
    pub collisions: u32,
    /// Largest distance between the estimated and the true position over the run, metres
    /// (evaluation only: the robot never reads its true pose).
    pub max_position_error_m: f64,
    /// Scans matched to a key scan, and matches rejected (odometry kept).
    pub scan_matches: u64,
    pub scan_match_rejections: u64,
    pub stop: StopReason,
}

/// Why a build could not run.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The scene has no start pose.
    #[error("scene {scene}: no start pose; expected at least one in `start_poses`")]
    NoStartPose { scene: String },
    /// The robot could not be placed or its spec is implausible.
    #[error("scene {scene}: {source}")]
    Placement {
        scene: String,
        source: usar_sim::PlacementError,
    },
    /// A configuration value is out of range.
    #[error("build configuration field `{field}`: found {found}")]
    Config { field: String, found: String },
    /// Writing the BTM failed.
    #[error(transparent)]
    Store(#[from] BtmError),
}

/// Drives one `robot` from the first start pose of `scene` and builds its BTM, writing each
/// new or changed node and link to `store` as it goes. A pure function of (scene, robot,
/// config, seed): `seed` drives the simulator's sensor and odometry noise.
pub fn build_btm(
    scene: Arc<Scene>,
    robot: RobotSpec,
    config: &BuildConfig,
    seed: u64,
    store: Option<&BtmStore>,
) -> Result<BuildOutcome, BuildError> {
    build_btm_observed(scene, robot, config, seed, store, &mut |_| {})
}

/// What [`build_btm_observed`] shows four times per simulated second.
pub struct BuildProgress<'a> {
    /// Simulated seconds.
    pub time_s: f64,
    /// The robot's pose as it estimates it (the frame of its map).
    pub estimated: Pose2,
    /// Its true pose (the evaluation's).
    pub truth: Pose2,
    /// The map built so far.
    pub btm: &'a Btm,
    /// Its last horizontal scan, in its frame.
    pub scan: &'a usar_map::localization::ScanView,
}

/// [`build_btm`], calling `on_progress` four times per simulated second with the time, the
/// robot's poses, its last scan and the map built so far ([`BuildProgress`]), e.g. for a
/// progress bar up to [`BuildConfig::max_time_s`], to show the robot and its map live as an
/// operator sees them, or to record the run.
pub fn build_btm_observed(
    scene: Arc<Scene>,
    robot: RobotSpec,
    config: &BuildConfig,
    seed: u64,
    store: Option<&BtmStore>,
    on_progress: &mut dyn FnMut(&BuildProgress<'_>),
) -> Result<BuildOutcome, BuildError> {
    config.validate()?;
    let start = *scene
        .start_poses
        .first()
        .ok_or_else(|| BuildError::NoStartPose {
            scene: scene.name.clone(),
        })?;
    let name = scene.name.clone();
    let sim = SimConfig {
        dt_s: config.dt_s,
        robots_collide: false,
        robots_in_lasers: false,
    };
    // The robot knows nothing but its readings: no oracle.
    let mut host = Host::new(scene, sim, seed, Oracles::default());
    let fleet = host
        .add_fleet(&[(robot.clone(), start)])
        .map_err(|source| BuildError::Placement {
            scene: name,
            source,
        })?;
    let id = host.fleet(fleet)[0];
    let mut explorer = explorer::Explorer::new(robot, config, start, store);
    let mut truth = Vec::new();
    let mut reported_s = 0.0;
    let stop = loop {
        host.decide(fleet, &mut explorer);
        let now = host.time_s();
        let pose = host.evaluator().robot(id).pose;
        truth.push(pose);
        if let Some(stop) = explorer.take_finished() {
            break stop?;
        }
        if now >= reported_s + 0.25 {
            reported_s = (now * 4.0).floor() / 4.0;
            on_progress(&BuildProgress {
                time_s: now,
                estimated: explorer.estimated_pose(),
                truth: pose,
                btm: explorer.btm(),
                scan: explorer.last_scan(),
            });
        }
        host.advance();
    };
    let evaluator = host.evaluator();
    let robot = evaluator.robot(id);
    let (scan_matches, scan_match_rejections) = explorer.scan_matches();
    let trajectory: Vec<TrajectorySample> = explorer
        .trajectory()
        .iter()
        .zip(&truth)
        .map(|(s, &truth)| TrajectorySample {
            time_s: s.time_s,
            estimated: s.estimated,
            truth,
            mode: s.mode,
            contact: s.contact,
        })
        .collect();
    let btm = explorer.into_btm();
    Ok(BuildOutcome {
        nodes_by_type: count_nodes(&btm),
        searched_links: btm.links.iter().filter(|l| l.searched).count(),
        unsearched_links: btm.links.iter().filter(|l| !l.searched).count(),
        time_s: evaluator.time_s(),
        distance_m: robot.distance_m,
        collisions: robot.collisions,
        max_position_error_m: trajectory
            .iter()
            .map(|s| s.estimated.position().distance(s.truth.position()))
            .fold(0.0, f64::max),
        scan_matches,
        scan_match_rejections,
        trajectory,
        stop,
        btm,
    })
}

pub fn count_nodes(btm: &Btm) -> BTreeMap<String, usize> {
    let mut counts = BTreeMap::new();
    for n in &btm.nodes {
        let key = match &n.subtype {
            Some(s) => format!("{}/{}", n.kind, s),
            None => n.kind.clone(),
        };
        *counts.entry(key).or_insert(0) += 1;
    }
    counts
}

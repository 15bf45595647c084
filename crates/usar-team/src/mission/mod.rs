//! A team exploration mission: the team ([`TeamController`]) runs on the host — its robots
//! scan, the base station merges their maps, frontier candidates are assigned, robots drive
//! their paths, the thermal cameras report warm regions — while the mission, holding the
//! ground truth, measures coverage, relevant area and victims found and stops the run by the
//! experiment's rules. A mission is a pure function of (scene, configuration, seed).

use crate::assignment::{Candidate, assign_nearest, candidates, path_costs};
use crate::base_station::BaseStation;
use crate::bids::{Measures, TeamSizer};
use crate::config::{Strategy, TeamConfig};
use crate::coverage::CoverageCounter;
use crate::driver::{PathFollower, Recovery, RecoveryStep};
use crate::mcdm::FuzzyMeasure;
use crate::outcome::{Finish, RobotOutcome, Sample, TeamOutcome, VictimSighting};
use crate::room_candidates::{CandidateGrouping, ClusterCandidate, group_by_room};
use crate::semantic_map::SemanticMap;
use crate::travel_time::TravelTimes;
use crate::tuning::Tuning;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::collections::BTreeMap;
use std::sync::Arc;
use usar_map::planning::{DistanceField, GridAStar, NavGrid};
use usar_map::{OccupancyGrid, OccupancyParams};
use usar_sim::host::{FleetId, Host, RadioSpec};
use usar_sim::sensors::{HeatTruth, LaserScan};
use usar_sim::{PlacementError, Simulation, Velocity, derive_seed};
use usar_world::{Cell, GridGeometry, Point2, Pose2, RoomLabel, Scene, normalize_angle};

mod allocation;
mod auction;
mod check;
pub use self::check::ConfigError;
mod controller;
mod discs;
mod driving;
mod evaluation;
mod live;

pub use self::allocation::{Allocate, Auction, NearestFrontier};
pub use self::controller::{Assignment, TeamController, VictimReport};

pub use self::evaluation::TeamEvaluation;

/// Random streams of the team (robots use streams 0, 1, … of the simulation's seed; the radio
/// (1 << 20) + 2).
const SEMANTIC_STREAM: u64 = 1 << 20;
const STRATEGY_STREAM: u64 = (1 << 20) + 1;
/// Fraction of the relevant area whose time is reported when no stop target is set (§4.4).
const DEFAULT_RELEVANT_TARGET: f64 = 0.9;

/// Why a mission could not start.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// The scene has fewer start poses than robots.
    #[error("scene {scene} has {available} start poses, {requested} robots were asked for")]
    NotEnoughStartPoses {
        scene: String,
        available: usize,
        requested: usize,
    },
    /// A robot could not be placed.
    #[error(transparent)]
    Placement(#[from] PlacementError),
    /// A setting of the configuration is invalid.
    #[error("invalid team configuration: {0}")]
    Config(#[from] ConfigError),
    /// A fuzzy measure of the configuration is invalid.
    #[error("invalid team configuration: {which} measure: {source}")]
    Measure {
        which: &'static str,
        source: crate::mcdm::MeasureError,
    },
    /// The semantic error model is invalid.
    #[error("invalid team configuration: {0}")]
    LabelErrors(#[from] crate::semantic_map::LabelErrorsError),
}

/// A team mission: the host with the team's robots, the team controller, and the evaluation.
pub struct TeamMission {
    config: TeamConfig,
    host: Host,
    fleet: FleetId,
    team: TeamController,
    eval: TeamEvaluation,
    samples: Vec<Sample>,
}

/// Whether step `step` is one of every `period_s` (rounded to steps of `dt_s`, at least 1).
fn every(period_s: f64, dt_s: f64, step: u64) -> bool {
    let n = (period_s / dt_s).round().max(1.0) as u64;
    step.is_multiple_of(n)
}

/// The grid of the team's maps: the scene's, or the same extent at `resolution_m`.
pub(crate) fn map_geometry(scene: &Scene, resolution_m: Option<f64>) -> GridGeometry {
    let g = *scene.geometry();
    match resolution_m {
        Some(r) if (r - g.resolution_m).abs() > 1e-12 => {
            let (w, h) = g.extent_m();
            GridGeometry::new((w / r).ceil() as u32, (h / r).ceil() as u32, r, g.origin)
        }
        _ => g,
    }
}

impl TeamMission {
    pub fn new(scene: Arc<Scene>, config: TeamConfig, seed: u64) -> Result<Self, MissionError> {
        if scene.start_poses.len() < config.robots {
            return Err(MissionError::NotEnoughStartPoses {
                scene: scene.name.clone(),
                available: scene.start_poses.len(),
                requested: config.robots,
            });
        }
        let starts = &scene.start_poses[..config.robots];
        let team = TeamController::on_scene(&scene, config.clone(), starts, seed)?;
        let base = starts[0].position();
        let mut host = Host::new(scene.clone(), config.sim.clone(), seed, config.oracles())
            .with_radio(RadioSpec {
                range_m: config.radio.range_m,
                drop_probability: config.radio.drop_probability,
                base: Some(base),
            });
        let robots: Vec<_> = starts
            .iter()
            .map(|&pose| (config.robot.clone(), pose))
            .collect();
        let fleet = host.add_fleet(&robots)?;
        for f in &config.failures {
            host.schedule_failure(host.fleet(fleet)[f.robot], f.at_s);
        }
        let eval = TeamEvaluation::new(&scene, &config, base);
        Ok(Self {
            config,
            host,
            fleet,
            team,
            eval,
            samples: Vec::new(),
        })
    }

    pub fn base_station(&self) -> &BaseStation {
        &self.team.base
    }

    /// The team's controller: what the robots believe and report.
    pub fn team(&self) -> &TeamController {
        &self.team
    }

    /// The team robots' ids on the host, robot k at index k.
    pub fn robot_ids(&self) -> &[usar_sim::RobotId] {
        self.host.fleet(self.fleet)
    }

    /// The world, as the evaluation sees it (true poses, the scene).
    pub fn simulation(&self) -> &Simulation {
        self.host.evaluator().simulation()
    }

    /// The coverage of the team's merged map so far (evaluation).
    pub fn coverage(&self) -> f64 {
        self.eval.coverage()
    }

    fn every(&self, period_s: f64, step: u64) -> bool {
        every(period_s, self.config.sim.dt_s, step)
    }

    /// Follows what the team did at its last step.
    fn evaluate(&mut self) {
        let truth = self.host.evaluator();
        self.eval
            .update(&mut self.team, &truth, self.host.fleet(self.fleet));
    }

    /// The semantic map the team bids with (the oracle's or its own segmentation).
    pub fn semantic_map(&self) -> &SemanticMap {
        &self.team.semantic
    }

    /// Whether coverage grew by less than [`TeamConfig::stall_growth`] over the last
    /// [`TeamConfig::stall_after_s`] (frontiers may be left, but none the robots can resolve).
    fn stalled(&self) -> bool {
        let Some(window) = self.config.stall_after_s else {
            return false;
        };
        let Some(last) = self.samples.last() else {
            return false;
        };
        self.samples
            .iter()
            .rev()
            .find(|s| s.time_s <= last.time_s - window + 1e-6)
            .is_some_and(|before| last.coverage - before.coverage < self.config.stall_growth)
    }

    /// Samples the metrics. The start sample is taken after the team's first step, with the
    /// assignments counted as none: it stands for the moment before the first allocation.
    fn sample(&mut self, at_start: bool) {
        let truth = self.host.evaluator();
        let assigned_per_label = if at_start {
            RoomLabel::ALL.into_iter().map(|l| (l, 0)).collect()
        } else {
            self.eval.assigned_per_label().clone()
        };
        self.samples.push(Sample {
            time_s: truth.time_s(),
            coverage: self.eval.coverage(),
            explored_area_m2: self.team.base.merged.known_area_m2(),
            victims_seen: self.eval.victims_seen().len(),
            distance_m: truth.robots().iter().map(|r| r.distance_m).sum(),
            relevant_area_m2: self.eval.relevant_area_m2(),
            assigned_per_label,
        });
    }

    /// Runs the mission to its end; `on_progress` gets the simulated time now and then.
    fn outcome(self, finish: Finish) -> TeamOutcome {
        let truth = self.host.evaluator();
        let scene = truth.scene();
        let g = scene.geometry();
        let eval = self.eval;
        let mut victims_seen = eval.victims_seen().to_vec();
        victims_seen.sort_by_key(|v| v.victim_id);
        let ids = self.host.fleet(self.fleet);
        let team = self.team;
        TeamOutcome {
            scene: scene.name.clone(),
            robots: team.agents.len(),
            time_s: truth.time_s(),
            finish,
            coverage: eval.coverage(),
            explored_area_m2: team.base.merged.known_area_m2(),
            reachable_area_m2: eval.reachable_cells() as f64 * g.cell_area_m2(),
            victims_total: scene.victims.len(),
            victims_seen: victims_seen.len(),
            victim_sightings: victims_seen,
            distance_m: truth.robots().iter().map(|r| r.distance_m).sum(),
            collisions: truth.robots().iter().map(|r| r.collisions).sum(),
            per_robot: team
                .agents
                .iter()
                .zip(ids)
                .enumerate()
                .map(|(k, (a, &id))| {
                    let r = truth.robot(id);
                    RobotOutcome {
                        robot: k,
                        distance_m: r.distance_m,
                        collisions: r.collisions,
                        max_pose_error_m: eval.max_pose_error_m()[k],
                        trajectory: a.trajectory.clone(),
                    }
                })
                .collect(),
            series: self.samples,
            relevant_area_m2: eval.relevant_area_m2(),
            relevant_total_m2: eval.relevant_total_m2(),
            time_to_relevant_s: eval.time_to_relevant_s(),
            relevant_target: eval.relevant_target(),
            assigned_per_label: eval.assigned_per_label().clone(),
            allocations: team.allocations,
            merged_map: team.base.merged,
        }
    }
}

/// The passable cell nearest `c` (Chebyshev rings up to `reach`), if any.
fn nearest_passable(grid: &NavGrid, c: Cell, reach: i32) -> Option<Cell> {
    (0..=reach).find_map(|r| {
        (-r..=r)
            .flat_map(|dr| (-r..=r).map(move |dc| (dc, dr)))
            .filter(|&(dc, dr)| dc.abs().max(dr.abs()) == r)
            .map(|(dc, dr)| Cell::new(c.col + dc, c.row + dr))
            .find(|&n| grid.is_passable(n))
    })
}

/// Where the robot's plan starts: its own cell when navigable, otherwise every navigable
/// cell a breadth-first search through known-free cells reaches within 1.5 m — the start
/// never lies behind a wall the robot stands next to, and a pocket the robot squeezed into
/// (navigable but cut off) is not its only way out.
fn source_cells(merged: &OccupancyGrid, grid: &NavGrid, p: Point2, all: bool) -> Vec<Cell> {
    let g = merged.geometry();
    let start = g.world_to_cell(p);
    if grid.is_passable(start) {
        return vec![start];
    }
    let reach = (1.5 / g.resolution_m).ceil() as i32;
    let mut queue = std::collections::VecDeque::from([start]);
    let mut seen = std::collections::BTreeSet::from([start]);
    let mut sources = Vec::new();
    while let Some(c) = queue.pop_front() {
        for (dc, dr) in usar_world::NEIGHBORS8 {
            let n = Cell::new(c.col + dc, c.row + dr);
            if !g.contains(n) || n.chebyshev(start) > reach || !seen.insert(n) {
                continue;
            }
            if grid.is_passable(n) {
                sources.push(n);
                if !all {
                    return sources;
                }
            }
            if merged.class(n) == usar_map::CellClass::Free {
                queue.push_back(n);
            }
        }
    }
    if sources.is_empty() {
        sources.push(start);
    }
    sources.sort();
    sources
}

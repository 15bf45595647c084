//! A team exploration mission: the team ([`TeamController`]) runs on the host — its robots
//! scan, the base station merges their maps, frontier candidates are assigned, robots drive
//! their paths, the thermal cameras report warm regions — while the mission, holding the
//! ground truth, measures coverage, relevant area and victims found and stops the run by the
//! experiment's rules. A mission is a pure function of (scene, configuration, seed).

use crate::assignment::{Candidate, assign_nearest, candidates, path_costs};
use crate::base_station::BaseStation;
use crate::bids::{Measures, TeamSizer};
use crate::config::{Localization, Semantics};
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
use usar_sim::host::{FleetId, Host, Oracles, RadioSpec};
use usar_sim::sensors::{HeatTruth, LaserScan};
use usar_sim::{PlacementError, Simulation, Velocity, derive_seed};
use usar_world::{Cell, GridGeometry, Point2, Pose2, RoomLabel, Scene, normalize_angle};

mod allocation;
mod controller;
mod driving;
mod live;

pub use self::controller::{Assignment, TeamController, VictimReport};
use self::driving::{gives_way, stuck_check};

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
    /// The configuration is invalid.
    #[error("invalid team configuration: {0}")]
    Config(String),
}

/// A live controller beside a running mission (the operator console): it may replace any
/// robot's velocity command (teleoperation) and, after every simulation step, look at the
/// mission, change it through its public methods, pace it, or end it.
pub trait MissionHook {
    /// The command robot `robot` gets this step; `planned` is the mission's own.
    fn command(&mut self, _robot: usize, planned: Velocity) -> Velocity {
        planned
    }
    /// Called after every simulation step; `false` ends the mission ([`Finish::Stopped`]).
    fn after_step(&mut self, _mission: &mut TeamMission) -> bool {
        true
    }
}

/// The hook of a mission nobody watches.
struct NoHook;

impl MissionHook for NoHook {}

/// A team mission: the host with the team's robots, the team controller, and the evaluation.
pub struct TeamMission {
    config: TeamConfig,
    host: Host,
    fleet: FleetId,
    team: TeamController,
    /// Evaluation: the part of the reachable area the team's merged map knows.
    coverage: CoverageCounter,
    /// Evaluation: the relevant area the team's merged map knows (the scene's room layer).
    relevant: SemanticMap,
    /// Merges of the team's map taken into the evaluation.
    merges_seen: u64,
    victims_seen: Vec<VictimSighting>,
    /// Per robot: the largest error of the team's pose estimate so far, metres.
    max_pose_error_m: Vec<f64>,
    /// Auction assignments per true room label of their target.
    assigned_per_label: BTreeMap<RoomLabel, u32>,
    samples: Vec<Sample>,
    relevant_target: f64,
    time_to_relevant_s: Option<f64>,
}

/// The grid of the team's maps: the scene's, or the same extent at `resolution_m`.
fn map_geometry(scene: &Scene, resolution_m: Option<f64>) -> GridGeometry {
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
        if config.robots == 0 {
            return Err(MissionError::Config("robots must be at least 1".into()));
        }
        let t = &config.timing;
        for (name, v) in [
            ("scan_period_s", t.scan_period_s),
            ("merge_period_s", t.merge_period_s),
            ("assignment_period_s", t.assignment_period_s),
            ("thermal_period_s", t.thermal_period_s),
            ("sample_period_s", t.sample_period_s),
            ("sim.dt_s", config.sim.dt_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(MissionError::Config(format!(
                    "{name} must be a positive number of seconds, found {v}"
                )));
            }
        }
        if let Some(r) = config.map_resolution_m
            && !(r.is_finite() && r >= scene.geometry().resolution_m)
        {
            return Err(MissionError::Config(format!(
                "map_resolution_m: found {r}, expected at least the scene's {} m",
                scene.geometry().resolution_m
            )));
        }
        let x = &config.exploration;
        let measures = Measures {
            s_mcdm: FuzzyMeasure::new(&x.s_mcdm)
                .map_err(|e| MissionError::Config(format!("S-MCDM measure: {e}")))?,
            d_mcdm: FuzzyMeasure::new(&x.d_mcdm)
                .map_err(|e| MissionError::Config(format!("D-MCDM measure: {e}")))?,
        };
        x.label_errors.check().map_err(MissionError::Config)?;
        if x.bid_grid_factor == 0 || x.max_robots_per_candidate == 0 {
            return Err(MissionError::Config(
                "bid_grid_factor and max_robots_per_candidate must be at least 1".into(),
            ));
        }
        if !(0.0..=1.0).contains(&config.radio.drop_probability) {
            return Err(MissionError::Config(format!(
                "radio drop probability: found {}, expected a probability in [0, 1]",
                config.radio.drop_probability
            )));
        }
        if let Some(r) = config.radio.range_m
            && !(r.is_finite() && r > 0.0)
        {
            return Err(MissionError::Config(format!(
                "radio range: found {r} m, expected a positive distance"
            )));
        }
        if let Some(f) = config.failures.iter().find(|f| f.robot >= config.robots) {
            return Err(MissionError::Config(format!(
                "failure of robot {}: the team has robots 0 to {}",
                f.robot,
                config.robots - 1
            )));
        }
        if let Some(f) = config.stop_at_relevant
            && !(0.0..=1.0).contains(&f)
        {
            return Err(MissionError::Config(format!(
                "stop_at_relevant: found {f}, expected a fraction in [0, 1]"
            )));
        }
        if scene.start_poses.len() < config.robots {
            return Err(MissionError::NotEnoughStartPoses {
                scene: scene.name.clone(),
                available: scene.start_poses.len(),
                requested: config.robots,
            });
        }
        let geometry = map_geometry(&scene, config.map_resolution_m);
        let starts = &scene.start_poses[..config.robots];
        let base = starts[0].position();
        let oracles = Oracles {
            localization: config.localization == Localization::True,
        };
        let mut host =
            Host::new(scene.clone(), config.sim.clone(), seed, oracles).with_radio(RadioSpec {
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
        let label_rng = Pcg64Mcg::seed_from_u64(derive_seed(seed, SEMANTIC_STREAM));
        let x = &config.exploration;
        let semantic = match config.semantics {
            // The named semantic oracle: the scene's room layer.
            Semantics::Oracle => {
                SemanticMap::new(&scene, &geometry, &x.hypothesis, x.label_errors, label_rng)
            }
            Semantics::Segmented => {
                SemanticMap::segmented(&geometry, &x.hypothesis, x.label_errors, label_rng)
            }
        };
        // The evaluation's copy draws no labels: its random stream is never used.
        let relevant = SemanticMap::new(
            &scene,
            &geometry,
            &config.exploration.hypothesis,
            config.exploration.label_errors,
            Pcg64Mcg::seed_from_u64(0),
        );
        let team = TeamController::new(config.clone(), starts, geometry, semantic, measures, seed);
        Ok(Self {
            relevant_target: config.stop_at_relevant.unwrap_or(DEFAULT_RELEVANT_TARGET),
            coverage: CoverageCounter::new(&scene, base, &geometry),
            config,
            host,
            fleet,
            team,
            relevant,
            merges_seen: 0,
            victims_seen: Vec::new(),
            max_pose_error_m: vec![0.0; starts.len()],
            assigned_per_label: RoomLabel::ALL.into_iter().map(|l| (l, 0)).collect(),
            samples: Vec::new(),
            time_to_relevant_s: None,
        })
    }

    pub fn base_station(&self) -> &BaseStation {
        &self.team.base
    }

    /// The world, as the evaluation sees it (true poses, the scene).
    pub fn simulation(&self) -> &Simulation {
        self.host.evaluator().simulation()
    }

    /// The coverage of the team's merged map so far (evaluation).
    pub fn coverage(&self) -> f64 {
        self.coverage.coverage()
    }

    fn every(&self, period_s: f64, step: u64) -> bool {
        let n = (period_s / self.config.sim.dt_s).round().max(1.0) as u64;
        step.is_multiple_of(n)
    }

    /// Follows what the team did at its last step: a merge of its map (coverage, relevant
    /// area) and its victim reports (which victims they were).
    fn evaluate(&mut self) {
        if self.team.merges() != self.merges_seen {
            self.merges_seen = self.team.merges();
            let base = &self.team.base;
            self.coverage.update_from(&base.merged, base.last_changes());
            self.relevant.update_from(&base.merged, base.last_changes());
            if self.time_to_relevant_s.is_none()
                && self.relevant.relevant_fraction() >= self.relevant_target
            {
                self.time_to_relevant_s = Some(self.host.time_s());
            }
        }
        let g = *self.team.base.merged.geometry();
        for a in self.team.take_assignments() {
            let room = self
                .relevant
                .room_of(g.index(a.target))
                .or_else(|| self.relevant.room_near(&g, a.candidate));
            if let Some(k) = room {
                *self
                    .assigned_per_label
                    .entry(self.relevant.rooms()[k].label)
                    .or_default() += 1;
            }
        }
        let truth = self.host.evaluator();
        for ((a, &id), worst) in self
            .team
            .agents
            .iter()
            .zip(self.host.fleet(self.fleet))
            .zip(&mut self.max_pose_error_m)
        {
            *worst = worst.max(a.pose.position().distance(truth.robot(id).pose.position()));
        }
        for report in self.team.take_reports() {
            if let Some(HeatTruth::Victim(id)) = truth.truth_of(report.reading)
                && !self.victims_seen.iter().any(|v| v.victim_id == id)
            {
                self.victims_seen.push(VictimSighting {
                    victim_id: id,
                    robot: report.robot,
                    time_s: report.time_s,
                });
            }
        }
    }

    /// The semantic oracle the team bids with.
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

    /// Samples the metrics; the start sample is taken before the team's first allocation.
    fn sample(&mut self, at_start: bool) {
        let truth = self.host.evaluator();
        let assigned_per_label = if at_start {
            RoomLabel::ALL.into_iter().map(|l| (l, 0)).collect()
        } else {
            self.assigned_per_label.clone()
        };
        self.samples.push(Sample {
            time_s: truth.time_s(),
            coverage: self.coverage.coverage(),
            explored_area_m2: self.team.base.merged.known_area_m2(),
            victims_seen: self.victims_seen.len(),
            distance_m: truth.robots().iter().map(|r| r.distance_m).sum(),
            relevant_area_m2: self.relevant.relevant_area_m2(),
            assigned_per_label,
        });
    }

    /// Runs the mission to its end; `on_progress` gets the simulated time now and then.
    pub fn run(self, on_progress: impl FnMut(f64)) -> TeamOutcome {
        self.run_live(on_progress, &mut NoHook)
    }

    /// The robots' current goals (the end of the path each follows), by robot index.
    pub fn robot_goal(&self, robot: usize) -> Option<Point2> {
        self.team.agents.get(robot).and_then(|a| a.follower.goal())
    }

    /// Whether robot `robot` is backing out of a contact (a recovery manoeuvre).
    pub fn is_recovering(&self, robot: usize) -> bool {
        self.team
            .agents
            .get(robot)
            .is_some_and(|a| a.recovery.is_active())
    }

    /// Replaces the relevance hypothesis of the auctions (paper 002 §4.1) while the mission
    /// runs; the relevant-area measure keeps the hypothesis the mission started with.
    pub fn set_hypothesis(&mut self, hypothesis: crate::criteria::Hypothesis) {
        self.team.config.exploration.hypothesis = hypothesis;
    }

    fn outcome(self, finish: Finish) -> TeamOutcome {
        let truth = self.host.evaluator();
        let scene = truth.scene();
        let g = scene.geometry();
        let mut victims_seen = self.victims_seen;
        victims_seen.sort_by_key(|v| v.victim_id);
        let ids = self.host.fleet(self.fleet);
        let team = self.team;
        TeamOutcome {
            scene: scene.name.clone(),
            robots: team.agents.len(),
            time_s: truth.time_s(),
            finish,
            coverage: self.coverage.coverage(),
            explored_area_m2: team.base.merged.known_area_m2(),
            reachable_area_m2: self.coverage.reachable_cells() as f64 * g.cell_area_m2(),
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
                        max_pose_error_m: self.max_pose_error_m[k],
                        trajectory: a.trajectory.clone(),
                    }
                })
                .collect(),
            series: self.samples,
            relevant_area_m2: self.relevant.relevant_area_m2(),
            relevant_total_m2: self.relevant.relevant_total_m2(),
            time_to_relevant_s: self.time_to_relevant_s,
            relevant_target: self.relevant_target,
            assigned_per_label: self.assigned_per_label,
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

/// Marks the cells within `radius_m` of `p` impassable, remembering the ones it changed.
fn block_disc(grid: &mut NavGrid, p: Point2, radius_m: f64, changed: &mut Vec<Cell>) {
    let g = *grid.geometry();
    let c = g.world_to_cell(p);
    let k = (radius_m / g.resolution_m).ceil() as i32;
    for dr in -k..=k {
        for dc in -k..=k {
            let n = Cell::new(c.col + dc, c.row + dr);
            if g.contains(n) && g.cell_center(n).distance(p) <= radius_m && grid.is_passable(n) {
                grid.set_passable(n, false);
                changed.push(n);
            }
        }
    }
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

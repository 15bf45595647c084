//! A team exploration mission: robots scan, the base station merges their maps, frontier
//! candidates are assigned, robots drive their paths, victims are noticed by the thermal
//! cameras, metrics are sampled. A mission is a pure function of (scene, configuration, seed).

use crate::assignment::{Candidate, assign_nearest, candidates, path_costs};
use crate::base_station::BaseStation;
use crate::bids::{Measures, TeamSizer};
use crate::config::{Strategy, TeamConfig};
use crate::driver::{PathFollower, Recovery, RecoveryStep};
use crate::mcdm::FuzzyMeasure;
use crate::outcome::{Finish, RobotOutcome, Sample, TeamOutcome, VictimSighting};
use crate::room_candidates::{CandidateGrouping, ClusterCandidate, group_by_room};
use crate::semantic_map::SemanticMap;
use crate::travel_time::TravelTimes;
use crate::tuning::Tuning;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::collections::BTreeMap;
use std::sync::Arc;
use usar_map::planning::{DistanceField, GridAStar, NavGrid};
use usar_map::{OccupancyGrid, OccupancyParams};
use usar_sim::sensors::{HeatTruth, LaserScan};
use usar_sim::{PlacementError, RobotId, Simulation, Velocity, derive_seed};
use usar_world::{Cell, GridGeometry, Point2, Pose2, RoomLabel, Scene, normalize_angle};

mod allocation;
mod live;

/// Random streams of the team (robots use streams 0, 1, … of the simulation's seed).
const SEMANTIC_STREAM: u64 = 1 << 20;
const STRATEGY_STREAM: u64 = (1 << 20) + 1;
const RADIO_STREAM: u64 = (1 << 20) + 2;
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

struct Agent {
    id: RobotId,
    map: OccupancyGrid,
    scan: LaserScan,
    follower: PathFollower,
    target: Option<Cell>,
    /// Pose and time of the last progress check.
    progress_mark: (Pose2, f64),
    /// Turning at the checks since the robot last moved [`Tuning::stuck_distance_m`], radians.
    turned_in_place_rad: f64,
    blacklist: Vec<(Cell, f64)>,
    trajectory: Vec<Point2>,
    /// Path costs from the robot, reused between assignments (nearest-frontier strategy).
    field: DistanceField,
    /// Recovery after bumps: the manoeuvre under way and the motions it may retrace.
    recovery: Recovery,
    /// Recoveries since the current target was assigned.
    recoveries: u32,
    /// Retracing its own trajectory out of a pocket the map no longer connects.
    escaping: bool,
    /// Whether it may retrace when no candidate is reachable: once after each target, so that
    /// a robot with nothing left to do goes idle instead of pacing back and forth.
    may_retrace: bool,
    /// Where it took its last scan.
    last_scan: Option<Pose2>,
    /// Whether its link to the base station worked at the last exchange.
    linked: bool,
    /// With a limited radio: the base station's copy of this robot's map as last received.
    uploaded: Option<OccupancyGrid>,
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

pub struct TeamMission {
    config: TeamConfig,
    sim: Simulation,
    agents: Vec<Agent>,
    base: BaseStation,
    victims_seen: Vec<VictimSighting>,
    samples: Vec<Sample>,
    semantic: SemanticMap,
    measures: Measures,
    sizer: TeamSizer,
    planner: GridAStar,
    /// The current bidder's distance field on the bid grid: one buffer for every bidder, so
    /// that an auction keeps one field's memory in cache rather than one per robot.
    bid_field: DistanceField,
    /// b(p, r) of the current bidder's paths, memoised along its distance field.
    travel_times: TravelTimes,
    strategy_rng: Pcg64Mcg,
    radio_rng: Pcg64Mcg,
    assigned_per_label: BTreeMap<RoomLabel, u32>,
    /// Candidates a robot reached (auctions): not offered to anyone for a while.
    visited: Vec<(Cell, f64)>,
    allocations: Vec<crate::outcome::Allocation>,
    /// Per room: the last i(p) inferred, with the perceived label and known fraction it was
    /// inferred from.
    team_sizes: Vec<Option<(Option<RoomLabel>, f64, usize)>>,
    /// Where and when robots reached their targets, waiting for a scan there to be merged.
    arrivals: Vec<(Point2, f64)>,
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
        let mut sim = Simulation::new(scene.clone(), config.sim.clone(), seed);
        let params = OccupancyParams::default();
        let geometry = map_geometry(&scene, config.map_resolution_m);
        let mut agents = Vec::new();
        for &pose in &scene.start_poses[..config.robots] {
            let id = sim.add_robot(config.robot.clone(), pose)?;
            agents.push(Agent {
                id,
                map: OccupancyGrid::new(geometry, params),
                scan: LaserScan::default(),
                follower: PathFollower::default(),
                target: None,
                progress_mark: (pose, 0.0),
                turned_in_place_rad: 0.0,
                blacklist: Vec::new(),
                trajectory: vec![pose.position()],
                field: DistanceField::new(),
                recovery: Recovery::for_robot(&config.robot),
                recoveries: 0,
                escaping: false,
                may_retrace: true,
                last_scan: None,
                linked: true,
                uploaded: (config.radio != crate::config::Radio::default())
                    .then(|| OccupancyGrid::new(geometry, params)),
            });
        }
        let start = scene.start_poses[0].position();
        // Occupied cells stand for walls whose faces are half a cell nearer than their centres.
        let half_cell = geometry.resolution_m / 2.0;
        let tight = config.robot.width_m / 2.0 + config.tuning.tight_margin_m + half_cell;
        let base = BaseStation::new(
            &scene,
            geometry,
            params,
            config.robot.circumscribed_radius_m() + half_cell,
            tight,
            config.exploration.bid_grid_factor,
            start,
        );
        let semantic = SemanticMap::new(
            &scene,
            &geometry,
            &config.exploration.hypothesis,
            config.exploration.label_errors,
            Pcg64Mcg::seed_from_u64(derive_seed(seed, SEMANTIC_STREAM)),
        );
        let team_sizes = vec![None; semantic.rooms().len()];
        Ok(Self {
            sizer: TeamSizer::new(config.exploration.max_robots_per_candidate),
            relevant_target: config.stop_at_relevant.unwrap_or(DEFAULT_RELEVANT_TARGET),
            config,
            sim,
            agents,
            base,
            victims_seen: Vec::new(),
            samples: Vec::new(),
            semantic,
            measures,
            planner: GridAStar::new(),
            bid_field: DistanceField::new(),
            travel_times: TravelTimes::new(),
            strategy_rng: Pcg64Mcg::seed_from_u64(derive_seed(seed, STRATEGY_STREAM)),
            radio_rng: Pcg64Mcg::seed_from_u64(derive_seed(seed, RADIO_STREAM)),
            assigned_per_label: RoomLabel::ALL.into_iter().map(|l| (l, 0)).collect(),
            visited: Vec::new(),
            allocations: Vec::new(),
            team_sizes,
            arrivals: Vec::new(),
            time_to_relevant_s: None,
        })
    }

    pub fn base_station(&self) -> &BaseStation {
        &self.base
    }

    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    fn every(&self, period_s: f64, step: u64) -> bool {
        let n = (period_s / self.config.sim.dt_s).round().max(1.0) as u64;
        step.is_multiple_of(n)
    }

    pub fn semantic_map(&self) -> &SemanticMap {
        &self.semantic
    }

    fn scan_all(&mut self) {
        let (min_move, min_turn) = (self.config.rescan_distance_m, self.config.rescan_turn_rad);
        for a in &mut self.agents {
            let r = self.sim.robot(a.id);
            if r.failed {
                continue;
            }
            if let Some(last) = a.last_scan
                && last.position().distance(r.pose.position()) < min_move
                && usar_world::normalize_angle(last.theta - r.pose.theta).abs() < min_turn
            {
                continue;
            }
            a.last_scan = Some(r.pose);
            self.sim.scan_laser(a.id, &mut a.scan);
            a.map.integrate_scan(&a.scan);
        }
    }

    /// Draws whether each working robot can talk to the base station now.
    fn update_links(&mut self) {
        let base = self.sim.scene().start_poses[0].position();
        let radio = &self.config.radio;
        for a in &mut self.agents {
            let r = self.sim.robot(a.id);
            let in_range = radio
                .range_m
                .is_none_or(|range| r.pose.position().distance(base) <= range);
            let delivered = radio.drop_probability <= 0.0
                || self.radio_rng.random::<f64>() >= radio.drop_probability;
            a.linked = !r.failed && in_range && delivered;
        }
    }

    fn merge(&mut self) {
        self.update_links();
        // With a limited radio the base station merges the copies it last received (a merge
        // recomputes a tile from every map given, so an unheard robot's copy stands in for it).
        let mut scratch = Vec::new();
        for a in &mut self.agents {
            if let (true, Some(copy)) = (a.linked, a.uploaded.as_mut()) {
                copy.merge_from(&mut [&mut a.map]);
                copy.drain_changed(&mut scratch);
                scratch.clear();
            }
            // Nothing reads a robot's own class-change log: emptied here, it stays small
            // instead of growing with every scan of the mission.
            a.map.drain_changed(&mut scratch);
            scratch.clear();
        }
        let mut maps: Vec<&mut OccupancyGrid> = self
            .agents
            .iter_mut()
            .map(|a| a.uploaded.as_mut().unwrap_or(&mut a.map))
            .collect();
        self.base.merge(&mut maps);
        self.semantic
            .update_from(&self.base.merged, self.base.last_changes());
        if self.time_to_relevant_s.is_none()
            && self.semantic.relevant_fraction() >= self.relevant_target
        {
            self.time_to_relevant_s = Some(self.sim.time_s());
        }
        // Arrivals whose scan on the spot is in the merged map now.
        let now = self.sim.time_s();
        let settled = now - self.config.timing.scan_period_s;
        let g = *self.base.merged.geometry();
        let radius = (self.config.tuning.unobservable_radius_m / g.resolution_m).round() as i32;
        for &(p, _) in self.arrivals.iter().filter(|&&(_, t)| t <= settled) {
            self.base.frontiers.retire_near(g.world_to_cell(p), radius);
        }
        self.arrivals.retain(|&(_, t)| t > settled);
    }

    fn read_thermal(&mut self) {
        let now = self.sim.time_s();
        for a in &self.agents {
            if self.sim.robot(a.id).failed {
                continue;
            }
            for d in self.sim.read_thermal(a.id) {
                if let (true, HeatTruth::Victim(id)) = (d.human_signature, d.truth)
                    && !self.victims_seen.iter().any(|v| v.victim_id == id)
                {
                    self.victims_seen.push(VictimSighting {
                        victim_id: id,
                        robot: a.id.0,
                        time_s: now,
                    });
                }
            }
        }
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

    fn sample(&mut self) {
        self.samples.push(Sample {
            time_s: self.sim.time_s(),
            coverage: self.base.coverage.coverage(),
            explored_area_m2: self.base.merged.known_area_m2(),
            victims_seen: self.victims_seen.len(),
            distance_m: self.sim.robots().iter().map(|r| r.distance_m).sum(),
            relevant_area_m2: self.semantic.relevant_area_m2(),
            assigned_per_label: self.assigned_per_label.clone(),
        });
    }

    /// Runs the mission to its end; `on_progress` gets the simulated time now and then.
    pub fn run(self, on_progress: impl FnMut(f64)) -> TeamOutcome {
        self.run_live(on_progress, &mut NoHook)
    }

    /// The robots' current goals (the end of the path each follows), by robot index.
    pub fn robot_goal(&self, robot: usize) -> Option<Point2> {
        self.agents.get(robot).and_then(|a| a.follower.goal())
    }

    /// Whether robot `robot` is backing out of a contact (a recovery manoeuvre).
    pub fn is_recovering(&self, robot: usize) -> bool {
        self.agents
            .get(robot)
            .is_some_and(|a| a.recovery.is_active())
    }

    /// Replaces the relevance hypothesis of the auctions (paper 002 §4.1) while the mission
    /// runs; the relevant-area measure keeps the hypothesis the mission started with.
    pub fn set_hypothesis(&mut self, hypothesis: crate::criteria::Hypothesis) {
        self.config.exploration.hypothesis = hypothesis;
    }

    fn outcome(self, finish: Finish) -> TeamOutcome {
        let scene = self.sim.scene();
        let g = scene.geometry();
        let mut victims_seen = self.victims_seen;
        victims_seen.sort_by_key(|v| v.victim_id);
        TeamOutcome {
            scene: scene.name.clone(),
            robots: self.agents.len(),
            time_s: self.sim.time_s(),
            finish,
            coverage: self.base.coverage.coverage(),
            explored_area_m2: self.base.merged.known_area_m2(),
            reachable_area_m2: self.base.coverage.reachable_cells() as f64 * g.cell_area_m2(),
            victims_total: scene.victims.len(),
            victims_seen: victims_seen.len(),
            victim_sightings: victims_seen,
            distance_m: self.sim.robots().iter().map(|r| r.distance_m).sum(),
            collisions: self.sim.robots().iter().map(|r| r.collisions).sum(),
            per_robot: self
                .agents
                .iter()
                .map(|a| {
                    let r = self.sim.robot(a.id);
                    RobotOutcome {
                        robot: a.id.0,
                        distance_m: r.distance_m,
                        collisions: r.collisions,
                        trajectory: a.trajectory.clone(),
                    }
                })
                .collect(),
            series: self.samples,
            relevant_area_m2: self.semantic.relevant_area_m2(),
            relevant_total_m2: self.semantic.relevant_total_m2(),
            time_to_relevant_s: self.time_to_relevant_s,
            relevant_target: self.relevant_target,
            assigned_per_label: self.assigned_per_label,
            allocations: self.allocations,
            merged_map: self.base.merged,
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

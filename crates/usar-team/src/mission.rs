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
    /// Turning at the checks since the robot last moved [`Tuning::stuck_distance_m`](crate::tuning::Tuning::stuck_distance_m), radians.
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

    /// Reassigns targets to the robots in `who` (all robots at a periodic auction, or those
    /// that reached their target or got stuck).
    fn assign(&mut self, who: &[usize]) {
        if self.config.exploration.strategy != Strategy::Nearest {
            self.auction(who);
            return;
        }
        let clusters = self.base.clusters(self.config.min_cluster_cells);
        let g = *self.base.merged.geometry();
        let merged = &self.base.merged;
        let navigable = |nav: &usar_map::NavigableMap, c: Cell| {
            g.checked_index(c)
                .is_some_and(|i| nav.is_navigable(merged, i))
        };
        let cands: Vec<Candidate> =
            candidates(&clusters, |c| navigable(&self.base.navigable_tight, c), &g);
        let now = self.sim.time_s();
        // Targets of robots that keep theirs are taken (one robot per candidate).
        let keep: Vec<Cell> = (0..self.agents.len())
            .filter(|i| !who.contains(i))
            .filter_map(|i| self.agents[i].target)
            .collect();
        let clearance = self.config.robot.circumscribed_radius_m() * 2.0;
        let mut costs = Vec::with_capacity(who.len());
        for &i in who {
            let pose = self.sim.robot(self.agents[i].id).pose;
            let others: Vec<Point2> = self
                .agents
                .iter()
                .enumerate()
                .filter(|&(j, a)| j != i && !self.sim.robot(a.id).failed)
                .map(|(_, a)| self.sim.robot(a.id).pose.position())
                .collect();
            self.agents[i].blacklist.retain(|&(_, until)| until > now);
            let mut row = Vec::new();
            // Plan with the full radius from the nearest navigable cell; if nothing is reachable,
            // squeeze with the tight radius; last, start from every navigable cell nearby.
            for (grid, all_sources) in [(0, false), (1, false), (1, true)] {
                let grid = &mut self.base.nav_grids[grid];
                let mut closed = Vec::new();
                for &p in &others {
                    block_disc(grid, p, clearance, &mut closed);
                }
                let sources = source_cells(&self.base.merged, grid, pose.position(), all_sources);
                let was_passable: Vec<bool> =
                    sources.iter().map(|&c| grid.is_passable(c)).collect();
                for &c in &sources {
                    grid.set_passable(c, true);
                }
                let agent = &mut self.agents[i];
                row = path_costs(&mut agent.field, grid, &sources, &cands);
                for (&c, &passable) in sources.iter().zip(&was_passable) {
                    grid.set_passable(c, passable);
                }
                for c in closed {
                    grid.set_passable(c, true);
                }
                for (k, c) in cands.iter().enumerate() {
                    if keep.contains(&c.cell)
                        || agent
                            .blacklist
                            .iter()
                            .any(|&(b, _)| b.chebyshev(c.cell) <= 3)
                    {
                        row[k] = None;
                    } else if let (Some(cost), Some(t)) = (row[k], agent.target)
                        && t.chebyshev(c.cell) <= self.config.tuning.commitment_cells
                    {
                        row[k] = Some(cost * self.config.tuning.commitment_factor);
                    }
                }
                if row.iter().any(Option::is_some) {
                    break;
                }
            }
            costs.push(row);
        }
        let chosen = assign_nearest(&costs);
        for (k, &i) in who.iter().enumerate() {
            let agent = &mut self.agents[i];
            match chosen[k] {
                Some(c) => {
                    let target = cands[c].cell;
                    if agent.target == Some(target) && !agent.follower.is_empty() {
                        continue;
                    }
                    let path = agent
                        .field
                        .path_to_source(target)
                        .map(|p| p.cells)
                        .unwrap_or_default();
                    let waypoints: Vec<Point2> =
                        path.iter().rev().map(|&c| g.cell_center(c)).collect();
                    agent.follower = PathFollower::new(waypoints);
                    agent.target = Some(target);
                    agent.recoveries = 0;
                    agent.escaping = false;
                    agent.may_retrace = true;
                }
                None => self.idle(i),
            }
            let agent = &mut self.agents[i];
            agent.progress_mark = (self.sim.robot(agent.id).pose, now);
        }
    }

    /// Robot `i` got nothing: it stops, retracing its way once if it may.
    fn idle(&mut self, i: usize) {
        let agent = &mut self.agents[i];
        agent.target = None;
        agent.follower = PathFollower::default();
        if std::mem::take(&mut agent.may_retrace) {
            agent.follower = PathFollower::new(retrace(
                &self.config.tuning,
                &agent.trajectory,
                self.sim.robot(agent.id).pose.position(),
            ));
        }
        agent.escaping = !agent.follower.is_empty();
    }

    /// A path on the map from robot `i` to `goal`: with the full radius if possible, else with
    /// the tight one. Waypoints from the robot to the goal.
    fn plan_path(&mut self, i: usize, goal: Cell) -> Option<Vec<Point2>> {
        let g = *self.base.merged.geometry();
        let here = self.sim.robot(self.agents[i].id).pose.position();
        let mut found = None;
        for radius in 0..2 {
            // The base station's grid (start and goal opened for the query, then closed again).
            let grid = &mut self.base.nav_grids[radius];
            let start = source_cells(&self.base.merged, grid, here, false)[0];
            let was = (grid.is_passable(start), grid.is_passable(goal));
            grid.set_passable(start, true);
            grid.set_passable(goal, true);
            let path =
                self.planner
                    .plan(grid, start, goal, usar_map::planning::Connectivity::Eight);
            grid.set_passable(start, was.0);
            grid.set_passable(goal, was.1);
            if let Some(p) = path {
                found = Some(p.cells.iter().map(|&c| g.cell_center(c)).collect());
                break;
            }
        }
        found
    }

    /// Paper 002's auction (§3.3) for the robots in `who`: candidates from the frontier
    /// clusters, each bidding robot's path lengths and times on the coarse bid grid, one
    /// candidate per room ([`CandidateGrouping::Room`]), bids by the strategy, allocation by the
    /// coordination method (robots not bidding keep their targets and count towards i(p)), then
    /// a path on the map to each new target.
    fn auction(&mut self, who: &[usize]) {
        let now = self.sim.time_s();
        let clusters = self.base.clusters(self.config.min_cluster_cells);
        let g = *self.base.merged.geometry();
        let mut cands: Vec<Candidate> = {
            let merged = &self.base.merged;
            let nav = &self.base.navigable_tight;
            candidates(
                &clusters,
                |c| {
                    g.checked_index(c)
                        .is_some_and(|i| nav.is_navigable(merged, i))
                },
                &g,
            )
        };
        // Robots that bid: working and linked. Unlinked robots keep what they do.
        let bidders: Vec<usize> = who
            .iter()
            .copied()
            .filter(|&i| self.agents[i].linked && !self.sim.robot(self.agents[i].id).failed)
            .collect();
        if bidders.is_empty() {
            return;
        }
        self.visited.retain(|&(_, until)| until > now);
        let visited: Vec<bool> = cands
            .iter()
            .map(|c| {
                self.visited
                    .iter()
                    .any(|&(v, _)| v.chebyshev(c.cell) <= self.config.tuning.visited_cells)
            })
            .collect();
        // What is known of each candidate: room, perceived label, i(p).
        let mut rooms: Vec<Option<usize>> = cands.iter().map(|c| self.room_near(c.cell)).collect();
        let labels: Vec<Option<RoomLabel>> = rooms
            .iter()
            .map(|r| r.map(|k| self.semantic.perceived_label(k)))
            .collect();
        let mut infos: Vec<crate::criteria::CandidateInfo> = cands
            .iter()
            .zip(&rooms)
            .zip(&labels)
            .map(|((c, r), &label)| crate::criteria::CandidateInfo {
                position: g.cell_center(c.cell),
                frontier_cells: c.frontier_cells,
                label,
                doors: r.map_or(0, |k| self.semantic.rooms()[k].doors),
            })
            .collect();
        let sr = self.config.exploration.coordination == crate::coordination::Coordination::Sr;
        // i(p) depends on the room, its perceived label and how much of it is known: inferred
        // again only when the label or the known fraction changed since the room's last one.
        let mut ideal: Vec<usize> = rooms
            .iter()
            .zip(&labels)
            .map(|(&r, &label)| {
                let Some(k) = r.filter(|_| !sr) else {
                    return 1;
                };
                let perceived = self.semantic.perceived_fraction(k);
                match self.team_sizes[k] {
                    Some((l, f, n)) if l == label && f == perceived => n,
                    _ => {
                        let n = self
                            .sizer
                            .ideal(Some(&self.semantic.rooms()[k]), label, perceived);
                        self.team_sizes[k] = Some((label, perceived, n));
                        n
                    }
                }
            })
            .collect();
        // Path lengths and times from each bidder, on the coarse grid.
        let grid = &self.base.bid_grid;
        let cg = *grid.geometry();
        let needs_time = matches!(
            self.config.exploration.strategy,
            Strategy::DMcdm | Strategy::SMcdm
        );
        let spec = self.config.robot.clone();
        let mut travel = Vec::with_capacity(bidders.len());
        let mut positions = Vec::with_capacity(bidders.len());
        // The bid grid cells of the candidates: a bidder's search stops once those it prices
        // are settled.
        let goals: Vec<Cell> = cands
            .iter()
            .map(|c| cg.world_to_cell(g.cell_center(c.cell)))
            .collect();
        let mut live = vec![false; cands.len()];
        let mut targets = Vec::with_capacity(cands.len());
        for &i in &bidders {
            let pose = self.sim.robot(self.agents[i].id).pose;
            positions.push(pose.position());
            let agent = &mut self.agents[i];
            agent.blacklist.retain(|&(_, until)| until > now);
            // Candidates this bidder prices: not visited, not near its blacklisted targets.
            targets.clear();
            for (k, (c, &visited)) in cands.iter().zip(&visited).enumerate() {
                live[k] = !visited
                    && !agent
                        .blacklist
                        .iter()
                        .any(|&(b, _)| b.chebyshev(c.cell) <= 3);
                if live[k] {
                    targets.push(goals[k]);
                }
            }
            let source = nearest_passable(grid, cg.world_to_cell(pose.position()), 4);
            let field = &mut self.bid_field;
            field.compute_until_settled(
                grid,
                &source.into_iter().collect::<Vec<_>>(),
                usar_map::planning::Connectivity::Eight,
                &targets,
            );
            let travel_times = &mut self.travel_times;
            travel_times.reset(field, pose.theta);
            let row: Vec<Option<crate::bids::Travel>> = (0..cands.len())
                .map(|k| {
                    if !live[k] {
                        return None;
                    }
                    let goal = goals[k];
                    let cells = field.distance_cells(goal)?;
                    let length_m = cells * cg.resolution_m;
                    let time_s = if needs_time {
                        travel_times.time_s(field, goal, length_m, &spec)?
                    } else {
                        length_m / spec.max_linear_mps
                    };
                    Some(crate::bids::Travel { length_m, time_s })
                })
                .collect();
            travel.push(row);
        }
        // One candidate per room (`room_candidates`): from here on, each group's representative
        // stands for its room's whole frontier. A robot's target still belongs to the group of
        // the cluster candidate it was (`candidate_of`), wherever the group's representative is.
        let ungrouped = cands.clone();
        let mut group_of: Vec<usize> = (0..cands.len()).collect();
        if self.config.exploration.candidates == CandidateGrouping::Room {
            let members: Vec<ClusterCandidate> = (0..cands.len())
                .map(|c| ClusterCandidate {
                    position: infos[c].position,
                    frontier_cells: cands[c].frontier_cells,
                    room: rooms[c]
                        .filter(|&k| self.semantic.rooms()[k].label != RoomLabel::Corridor),
                    reachable_by: travel.iter().filter(|row| row[c].is_some()).count(),
                })
                .collect();
            let groups = group_by_room(&members);
            for (k, g) in groups.iter().enumerate() {
                for &m in &g.members {
                    group_of[m] = k;
                }
            }
            let keep: Vec<usize> = groups.iter().map(|g| g.representative).collect();
            cands = pick(&cands, &keep);
            infos = pick(&infos, &keep);
            for ((c, info), g) in cands.iter_mut().zip(&mut infos).zip(&groups) {
                c.frontier_cells = g.frontier_cells;
                info.frontier_cells = g.frontier_cells;
            }
            rooms = pick(&rooms, &keep);
            ideal = pick(&ideal, &keep);
            for row in &mut travel {
                *row = pick(row, &keep);
            }
        }
        let tuning = self.config.tuning;
        let candidate_of =
            |t: Cell| nearest_candidate(&tuning, &ungrouped, t).map(|(k, _)| group_of[k]);
        let mut bids = crate::bids::bids(
            self.config.exploration.strategy,
            &self.measures,
            &self.config.exploration.hypothesis,
            &positions,
            &infos,
            &travel,
            &mut self.strategy_rng,
        );
        let bonus = self.config.exploration.commitment_bonus;
        for (row, &i) in bids.iter_mut().zip(&bidders) {
            if let Some(t) = self.agents[i].target
                && let Some(k) = candidate_of(t)
                && let Some(u) = row[k].as_mut()
            {
                *u += bonus;
            }
        }
        // Robots keeping their targets occupy the candidate nearest to each target.
        let mut already = vec![0usize; cands.len()];
        for (j, a) in self.agents.iter().enumerate() {
            if who.contains(&j) || self.sim.robot(a.id).failed {
                continue;
            }
            if let Some(t) = a.target
                && let Some(k) = candidate_of(t)
            {
                already[k] += 1;
            }
        }
        let x = &self.config.exploration;
        let chosen = crate::coordination::allocate_among(
            &bids,
            &ideal,
            &already,
            x.coordination,
            x.discount,
        );
        for (k, &i) in bidders.iter().enumerate() {
            match chosen[k] {
                Some(c) => {
                    let target = cands[c].cell;
                    let agent = &self.agents[i];
                    // Allocated what it is heading for (the same spot, or its target's room):
                    // it keeps its path.
                    if agent.target.is_some_and(|t| {
                        t.chebyshev(target) <= self.config.tuning.kept_target_cells
                            || candidate_of(t) == Some(c)
                    }) && !agent.follower.is_empty()
                    {
                        continue;
                    }
                    match self.plan_path(i, target) {
                        Some(waypoints) => {
                            let info = &infos[c];
                            self.allocations.push(crate::outcome::Allocation {
                                time_s: now,
                                robot: i,
                                x_m: info.position.x,
                                y_m: info.position.y,
                                label: info.label,
                                relevance: self.config.exploration.hypothesis.relevance(info.label),
                                frontier_cells: info.frontier_cells,
                                path_m: travel[k][c].map_or(f64::NAN, |t| t.length_m),
                                utility: bids[k][c].unwrap_or(f64::NAN),
                                ideal_robots: ideal[c],
                                room_known: rooms[c].map(|k| self.semantic.perceived_fraction(k)),
                            });
                            let label = self.semantic.room_of(g.index(target)).or(rooms[c]);
                            if let Some(k) = label {
                                *self
                                    .assigned_per_label
                                    .entry(self.semantic.rooms()[k].label)
                                    .or_default() += 1;
                            }
                            let agent = &mut self.agents[i];
                            agent.follower = PathFollower::new(waypoints);
                            agent.target = Some(target);
                            agent.recoveries = 0;
                            agent.escaping = false;
                            agent.may_retrace = true;
                        }
                        None => {
                            self.agents[i]
                                .blacklist
                                .push((target, now + self.config.tuning.blacklist_s));
                            self.idle(i);
                        }
                    }
                }
                None => self.idle(i),
            }
            let agent = &mut self.agents[i];
            agent.progress_mark = (self.sim.robot(agent.id).pose, now);
        }
    }

    /// The room of a map cell, or of the nearest cell within two cells that has one (a
    /// candidate may stand in a doorway's wall gap).
    fn room_near(&self, cell: Cell) -> Option<usize> {
        let g = self.base.merged.geometry();
        (0..=2).find_map(|r: i32| {
            (-r..=r)
                .flat_map(|dr| (-r..=r).map(move |dc| (dc, dr)))
                .filter(|&(dc, dr)| dc.abs().max(dr.abs()) == r)
                .find_map(|(dc, dr)| {
                    let i = g.checked_index(Cell::new(cell.col + dc, cell.row + dr))?;
                    self.semantic.room_of(i)
                })
        })
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

    /// [`TeamMission::run`] with a live controller beside it (see [`MissionHook`]).
    pub fn run_live(
        mut self,
        mut on_progress: impl FnMut(f64),
        hook: &mut dyn MissionHook,
    ) -> TeamOutcome {
        let dt = self.config.sim.dt_s;
        let steps = (self.config.duration_s / dt).round() as u64;
        self.scan_all();
        self.merge();
        self.read_thermal();
        self.sample();
        let everyone: Vec<usize> = (0..self.agents.len()).collect();
        // Nothing assigned yet ends the mission only by the idle rule below: the robots' first
        // targets may have no path on the map (the coarser bid grid joins more), and the next
        // auction offers them others.
        self.assign(&everyone);
        let mut finish = Finish::TimeLimit;
        let mut step = 0u64;
        let mut idle_since: Option<f64> = None;
        while finish == Finish::TimeLimit && step < steps {
            step += 1;
            let now = self.sim.time_s();
            for f in &self.config.failures {
                let id = self.agents[f.robot].id;
                if f.at_s <= now && !self.sim.robot(id).failed {
                    self.sim.fail_robot(id);
                    let a = &mut self.agents[f.robot];
                    a.target = None;
                    a.follower = PathFollower::default();
                    a.escaping = false;
                    a.recovery.stop();
                }
            }
            let mut replan = Vec::new();
            let commands: Vec<Velocity> = self
                .agents
                .iter_mut()
                .enumerate()
                .map(|(i, a)| {
                    let r = self.sim.robot(a.id);
                    match a.recovery.step(now, r.in_contact()) {
                        RecoveryStep::Escape(v) => v,
                        RecoveryStep::Ended => {
                            a.recoveries += 1;
                            if a.recoveries >= self.config.tuning.max_recoveries
                                && let Some(t) = a.target.take()
                            {
                                a.blacklist.push((t, now + self.config.tuning.blacklist_s));
                                a.follower = PathFollower::default();
                            }
                            replan.push(i);
                            Velocity::default()
                        }
                        RecoveryStep::Free => {
                            let mut cmd = a.follower.command(r.pose, &r.spec);
                            if cmd.linear_mps > 0.0
                                && self.sim.robots()[..i].iter().any(|o| {
                                    gives_way(&self.config.tuning, r.pose, o.pose.position())
                                })
                            {
                                cmd.linear_mps = 0.0;
                            }
                            cmd
                        }
                    }
                })
                .enumerate()
                .map(|(i, planned)| hook.command(i, planned))
                .collect();
            self.sim.step(&commands);
            let dt_s = self.sim.config().dt_s;
            for a in &mut self.agents {
                a.recovery.record(self.sim.robot(a.id).last_motion(), dt_s);
            }
            if !hook.after_step(&mut self) {
                finish = Finish::Stopped;
                break;
            }
            let now = self.sim.time_s();
            if self.every(self.config.timing.scan_period_s, step) {
                self.scan_all();
            }
            if self.every(self.config.timing.thermal_period_s, step) {
                self.read_thermal();
            }
            let merged_now = self.every(self.config.timing.merge_period_s, step);
            if merged_now {
                self.merge();
            }
            if self.every(1.0, step) {
                for a in &mut self.agents {
                    a.trajectory.push(self.sim.robot(a.id).pose.position());
                }
            }
            // Who needs a new target: reached it, has none, made no progress, or recovered.
            let mut who = replan;
            let auctioned = self.config.exploration.strategy != Strategy::Nearest;
            for (i, a) in self.agents.iter_mut().enumerate() {
                let r = self.sim.robot(a.id);
                if r.failed || a.recovery.is_active() || who.contains(&i) {
                    continue;
                }
                let done = a.follower.is_done(r.pose);
                if a.target.is_some()
                    && !done
                    && now - a.progress_mark.1 >= self.config.tuning.stuck_window_s
                {
                    let (mark, _) = a.progress_mark;
                    let (stuck, turned) =
                        stuck_check(&self.config.tuning, mark, r.pose, a.turned_in_place_rad);
                    a.turned_in_place_rad = turned;
                    if stuck {
                        a.blacklist.push((
                            a.target.expect("has target"),
                            now + self.config.tuning.blacklist_s,
                        ));
                        a.follower = PathFollower::default();
                        a.target = None;
                        who.push(i);
                        continue;
                    }
                    a.progress_mark = (r.pose, now);
                }
                if a.escaping {
                    if done {
                        a.escaping = false;
                        who.push(i);
                    }
                    continue;
                }
                if done && let Some(reached) = a.target {
                    // A frontier that did not resolve on arrival (it lies behind something the
                    // laser cannot see past) is left alone for a while.
                    a.blacklist
                        .push((reached, now + self.config.tuning.reached_blacklist_s));
                    if auctioned {
                        self.visited
                            .push((reached, now + self.config.tuning.visited_blacklist_s));
                        self.arrivals.push((r.pose.position(), now));
                    }
                    a.target = None;
                    who.push(i);
                } else if done && merged_now {
                    who.push(i);
                }
            }
            if self.every(self.config.timing.assignment_period_s, step) {
                who = everyone.clone();
            }
            if !who.is_empty() {
                self.assign(&who);
            }
            if self
                .agents
                .iter()
                .all(|a| a.target.is_none() && !a.escaping)
            {
                let since = *idle_since.get_or_insert(now);
                if now - since >= self.config.tuning.explored_after_s {
                    finish = Finish::Explored;
                }
            } else {
                idle_since = None;
            }
            if self.every(self.config.timing.sample_period_s, step) {
                self.sample();
                on_progress(now);
                if self.stalled() {
                    finish = Finish::Stalled;
                }
            }
            if let Some(target) = self.config.stop_at_coverage
                && merged_now
                && self.base.coverage.coverage() >= target
            {
                finish = Finish::CoverageTarget;
            }
            if self.config.stop_at_relevant.is_some()
                && merged_now
                && self.time_to_relevant_s.is_some()
            {
                finish = Finish::RelevantTarget;
            }
        }
        self.merge();
        if self
            .samples
            .last()
            .is_none_or(|s| s.time_s < self.sim.time_s())
        {
            self.sample();
        }
        on_progress(self.sim.time_s());
        self.outcome(finish)
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

/// The progress check of a robot with a target, [`Tuning::stuck_window_s`](crate::tuning::Tuning::stuck_window_s) after its `mark`: whether it
/// is stuck, and its turning in place since it last moved (`turned_before` until this check).
/// Moving [`Tuning::stuck_distance_m`](crate::tuning::Tuning::stuck_distance_m) is progress; so is turning [`Tuning::stuck_turn_rad`](crate::tuning::Tuning::stuck_turn_rad), up to
/// [`Tuning::max_turn_in_place_rad`](crate::tuning::Tuning::max_turn_in_place_rad) in all while the robot stays put.
fn stuck_check(tuning: &Tuning, mark: Pose2, now: Pose2, turned_before: f64) -> (bool, f64) {
    if now.position().distance(mark.position()) >= tuning.stuck_distance_m {
        return (false, 0.0);
    }
    let turned = normalize_angle(now.theta - mark.theta).abs();
    let total = turned_before + turned;
    if turned < tuning.stuck_turn_rad || total > tuning.max_turn_in_place_rad {
        (true, 0.0)
    } else {
        (false, total)
    }
}

/// The elements of `v` at `keep`, in that order.
fn pick<T: Clone>(v: &[T], keep: &[usize]) -> Vec<T> {
    keep.iter().map(|&k| v[k].clone()).collect()
}

/// The candidate nearest a robot's target, within [`Tuning::kept_target_cells`](crate::tuning::Tuning::kept_target_cells): (index, distance).
fn nearest_candidate(tuning: &Tuning, cands: &[Candidate], target: Cell) -> Option<(usize, i32)> {
    cands
        .iter()
        .enumerate()
        .map(|(k, c)| (k, c.cell.chebyshev(target)))
        .filter(|&(_, d)| d <= tuning.kept_target_cells)
        .min_by_key(|&(k, d)| (d, k))
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

/// The way back along a trajectory: its points from the latest backwards, until [`Tuning::retrace_m`](crate::tuning::Tuning::retrace_m)
/// away from `here` along the way (empty when there is no way back).
fn retrace(tuning: &Tuning, trajectory: &[Point2], here: Point2) -> Vec<Point2> {
    let mut out = Vec::new();
    let mut length = 0.0;
    let mut last = here;
    for &p in trajectory.iter().rev() {
        if p.distance(here) < 0.2 && out.is_empty() {
            continue;
        }
        length += last.distance(p);
        out.push(p);
        last = p;
        if length >= tuning.retrace_m {
            break;
        }
    }
    if last.distance(here) < 1.0 {
        out.clear();
    }
    out
}

/// Whether a robot at `pose` must give way to a robot at `other` (close, ahead of it).
fn gives_way(tuning: &Tuning, pose: usar_world::Pose2, other: Point2) -> bool {
    let here = pose.position();
    here.distance(other) < tuning.yield_distance_m
        && usar_world::normalize_angle(here.bearing_to(other) - pose.theta).abs()
            < tuning.yield_half_angle_rad
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turning_round_in_place_is_progress_and_spinning_on_the_spot_is_not() {
        let at = |x: f64, theta: f64| Pose2::new(x, 0.0, theta);
        // Standing still: stuck.
        assert_eq!(
            stuck_check(&Tuning::default(), at(0.0, 0.0), at(0.05, 0.1), 0.0),
            (true, 0.0)
        );
        // Driving: progress, and the turning count starts again.
        assert_eq!(
            stuck_check(&Tuning::default(), at(0.0, 0.0), at(0.5, 0.0), 3.0),
            (false, 0.0)
        );
        // Turning round at 0.36 rad/s, 1.44 rad a window: progress for the ~9 s it takes.
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 0.0), at(0.0, 1.44), 0.0);
        assert!(!stuck);
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 1.44), at(0.0, 2.88), turned);
        assert!(!stuck && (turned - 2.88).abs() < 1e-9);
        // Spinning on: stuck once the turning passes a full turn.
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 2.88), at(0.0, 4.32), turned);
        assert!(!stuck);
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 4.32), at(0.0, 5.76), turned);
        assert!(!stuck && turned < std::f64::consts::TAU);
        assert_eq!(
            stuck_check(&Tuning::default(), at(0.0, 5.76), at(0.0, 7.2), turned),
            (true, 0.0)
        );
    }
}

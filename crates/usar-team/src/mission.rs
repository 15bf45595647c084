//! A team exploration mission: robots scan, the base station merges their maps, frontier
//! candidates are assigned, robots drive their paths, victims are noticed by the thermal
//! cameras, metrics are sampled. A mission is a pure function of (scene, configuration, seed).

use crate::assignment::{Candidate, assign_nearest, candidates, path_costs};
use crate::base_station::BaseStation;
use crate::config::TeamConfig;
use crate::driver::PathFollower;
use crate::outcome::{Finish, RobotOutcome, Sample, TeamOutcome, VictimSighting};
use std::sync::Arc;
use usar_map::planning::{DistanceField, NavGrid};
use usar_map::{OccupancyGrid, OccupancyParams};
use usar_sim::sensors::{HeatTruth, LaserScan};
use usar_sim::{PlacementError, RobotId, Simulation, Velocity};
use usar_world::{Cell, Point2, Scene};

/// A robot is stuck when it moved less than this in [`STUCK_WINDOW_S`] while it had a target.
const STUCK_DISTANCE_M: f64 = 0.2;
const STUCK_WINDOW_S: f64 = 4.0;
/// A candidate a robot got stuck on is not given to it again for this long.
const BLACKLIST_S: f64 = 30.0;
/// A candidate a robot reached is not given to it again for this long.
const REACHED_BLACKLIST_S: f64 = 20.0;
/// Commitment: at a periodic reassignment, a candidate within this distance (cells) of the
/// robot's current target costs it [`COMMITMENT_FACTOR`] × its path cost, so that two frontiers
/// at similar distances do not make the robot turn back and forth every few seconds.
const COMMITMENT_CELLS: i32 = 10;
const COMMITMENT_FACTOR: f64 = 0.5;
/// Margin added to half the robot's width for squeezing through narrow places, metres.
const TIGHT_MARGIN_M: f64 = 0.05;
/// The mission counts as explored once no robot has had a reachable candidate for this long
/// (a doorway closed for a moment by a noisy return must not end it).
const EXPLORED_AFTER_S: f64 = 10.0;
/// Recovery after a collision (what a bumper-equipped base does): it tries these manoeuvres in
/// turn, each for [`RECOVERY_S`], moving on to the next as soon as one bumps too; then it plans
/// again. Backing up comes first; turning either way and creeping forward free a robot wedged
/// with a corner behind it.
const RECOVERY_S: f64 = 1.0;
const ESCAPES: [Velocity; 6] = [
    Velocity {
        linear_mps: -0.15,
        angular_radps: 0.0,
    },
    Velocity {
        linear_mps: 0.0,
        angular_radps: 0.8,
    },
    Velocity {
        linear_mps: 0.0,
        angular_radps: -0.8,
    },
    Velocity {
        linear_mps: -0.1,
        angular_radps: 0.6,
    },
    Velocity {
        linear_mps: -0.1,
        angular_radps: -0.6,
    },
    Velocity {
        linear_mps: 0.1,
        angular_radps: 0.0,
    },
];
/// A target that needed this many recoveries is given up (blacklisted) like a stuck one.
const MAX_RECOVERIES: u32 = 3;
/// When no candidate is reachable from where a robot stands (the map, refined since it drove
/// in, no longer connects its pocket), it retraces this much of its own trajectory and plans
/// again: it was there, so the way back is passable.
const RETRACE_M: f64 = 3.0;
/// Right of way: a robot stops (it may still turn) while a robot with a lower id is closer than
/// this, centre to centre, within ±60° of its heading.
const YIELD_DISTANCE_M: f64 = 1.2;
const YIELD_HALF_ANGLE_RAD: f64 = std::f64::consts::FRAC_PI_3;

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
    /// Position and time of the last progress check.
    progress_mark: (Point2, f64),
    blacklist: Vec<(Cell, f64)>,
    trajectory: Vec<Point2>,
    /// Path costs from the robot, reused between assignments.
    field: DistanceField,
    /// A recovery in progress: the index into [`ESCAPES`] being tried and when it ends.
    recovery: Option<(usize, f64)>,
    /// Recoveries since the current target was assigned.
    recoveries: u32,
    /// Retracing its own trajectory out of a pocket the map no longer connects.
    escaping: bool,
    /// Whether it may retrace when no candidate is reachable: once after each target, so that
    /// a robot with nothing left to do goes idle instead of pacing back and forth.
    may_retrace: bool,
}

pub struct TeamMission {
    config: TeamConfig,
    sim: Simulation,
    agents: Vec<Agent>,
    base: BaseStation,
    victims_seen: Vec<VictimSighting>,
    samples: Vec<Sample>,
    /// Planning grids from the merged map (full radius, tight radius), built on first use after
    /// each merge.
    nav_grids: Option<[NavGrid; 2]>,
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
        if scene.start_poses.len() < config.robots {
            return Err(MissionError::NotEnoughStartPoses {
                scene: scene.name.clone(),
                available: scene.start_poses.len(),
                requested: config.robots,
            });
        }
        let mut sim = Simulation::new(scene.clone(), config.sim.clone(), seed);
        let params = OccupancyParams::default();
        let mut agents = Vec::new();
        for &pose in &scene.start_poses[..config.robots] {
            let id = sim.add_robot(config.robot.clone(), pose)?;
            agents.push(Agent {
                id,
                map: OccupancyGrid::new(*scene.geometry(), params),
                scan: LaserScan::default(),
                follower: PathFollower::default(),
                target: None,
                progress_mark: (pose.position(), 0.0),
                blacklist: Vec::new(),
                trajectory: vec![pose.position()],
                field: DistanceField::new(),
                recovery: None,
                recoveries: 0,
                escaping: false,
                may_retrace: true,
            });
        }
        let start = scene.start_poses[0].position();
        // Occupied cells stand for walls whose faces are half a cell nearer than their centres.
        let half_cell = scene.geometry().resolution_m / 2.0;
        let tight = config.robot.width_m / 2.0 + TIGHT_MARGIN_M + half_cell;
        let base = BaseStation::new(
            &scene,
            params,
            config.robot.circumscribed_radius_m() + half_cell,
            tight,
            start,
        );
        Ok(Self {
            config,
            sim,
            agents,
            base,
            victims_seen: Vec::new(),
            samples: Vec::new(),
            nav_grids: None,
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

    fn scan_all(&mut self) {
        for a in &mut self.agents {
            if self.sim.robot(a.id).failed {
                continue;
            }
            self.sim.scan_laser(a.id, &mut a.scan);
            a.map.integrate_scan(&a.scan);
        }
    }

    fn merge(&mut self) {
        let mut maps: Vec<&mut OccupancyGrid> =
            self.agents.iter_mut().map(|a| &mut a.map).collect();
        self.base.merge(&mut maps);
        self.nav_grids = None;
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

    /// Where the robot's plan starts: its own cell when navigable, otherwise every navigable
    /// cell a breadth-first search through known-free cells reaches within 1.5 m — the start
    /// never lies behind a wall the robot stands next to, and a pocket the robot squeezed into
    /// (navigable but cut off) is not its only way out.
    fn source_cells(&self, grid: &NavGrid, p: Point2, all: bool) -> Vec<Cell> {
        let merged = &self.base.merged;
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

    /// Reassigns targets to the robots in `who` (all robots at a periodic auction, or those
    /// that reached their target or got stuck).
    fn assign(&mut self, who: &[usize]) -> bool {
        let clusters = self.base.clusters(self.config.min_cluster_cells);
        let g = *self.base.merged.geometry();
        let merged = &self.base.merged;
        let navigable = |nav: &usar_map::NavigableMap, c: Cell| {
            g.checked_index(c)
                .is_some_and(|i| nav.is_navigable(merged, i))
        };
        let cands: Vec<Candidate> =
            candidates(&clusters, |c| navigable(&self.base.navigable_tight, c), &g);
        let mut grids = self.nav_grids.take().unwrap_or_else(|| {
            [&self.base.navigable, &self.base.navigable_tight]
                .map(|nav| NavGrid::from_fn(g, |c| !nav.is_navigable(merged, g.index(c))))
        });
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
                let grid = &mut grids[grid];
                let mut closed = Vec::new();
                for &p in &others {
                    block_disc(grid, p, clearance, &mut closed);
                }
                let sources = self.source_cells(grid, pose.position(), all_sources);
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
                        && t.chebyshev(c.cell) <= COMMITMENT_CELLS
                    {
                        row[k] = Some(cost * COMMITMENT_FACTOR);
                    }
                }
                if row.iter().any(Option::is_some) {
                    break;
                }
            }
            costs.push(row);
        }
        self.nav_grids = Some(grids);
        let chosen = assign_nearest(&costs);
        let mut any = false;
        for (k, &i) in who.iter().enumerate() {
            let agent = &mut self.agents[i];
            match chosen[k] {
                Some(c) => {
                    let target = cands[c].cell;
                    any = true;
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
                None => {
                    agent.target = None;
                    agent.follower = PathFollower::default();
                    if std::mem::take(&mut agent.may_retrace) {
                        agent.follower = PathFollower::new(retrace(
                            &agent.trajectory,
                            self.sim.robot(agent.id).pose.position(),
                        ));
                    }
                    agent.escaping = !agent.follower.is_empty();
                }
            }
            agent.progress_mark = (self.sim.robot(agent.id).pose.position(), now);
        }
        any
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
        });
    }

    /// Runs the mission to its end; `on_progress` gets the simulated time now and then.
    pub fn run(mut self, mut on_progress: impl FnMut(f64)) -> TeamOutcome {
        let dt = self.config.sim.dt_s;
        let steps = (self.config.duration_s / dt).round() as u64;
        self.scan_all();
        self.merge();
        self.read_thermal();
        self.sample();
        let everyone: Vec<usize> = (0..self.agents.len()).collect();
        let mut finish = Finish::TimeLimit;
        if !self.assign(&everyone) {
            finish = Finish::Explored;
        }
        let mut step = 0u64;
        let mut idle_since: Option<f64> = None;
        while finish == Finish::TimeLimit && step < steps {
            step += 1;
            let now = self.sim.time_s();
            let mut replan = Vec::new();
            let commands: Vec<Velocity> = self
                .agents
                .iter_mut()
                .enumerate()
                .map(|(i, a)| {
                    let r = self.sim.robot(a.id);
                    match a.recovery {
                        Some((escape, until)) if now < until => {
                            if r.in_contact() {
                                // This manoeuvre bumps too: try the next one.
                                let next = (escape + 1) % ESCAPES.len();
                                a.recovery = Some((next, now + RECOVERY_S));
                                return ESCAPES[next];
                            }
                            ESCAPES[escape]
                        }
                        Some(_) => {
                            a.recovery = None;
                            a.recoveries += 1;
                            if a.recoveries >= MAX_RECOVERIES
                                && let Some(t) = a.target.take()
                            {
                                a.blacklist.push((t, now + BLACKLIST_S));
                                a.follower = PathFollower::default();
                            }
                            replan.push(i);
                            Velocity::default()
                        }
                        None if r.in_contact() => {
                            a.recovery = Some((0, now + RECOVERY_S));
                            ESCAPES[0]
                        }
                        None => {
                            let mut cmd = a.follower.command(r.pose, &r.spec);
                            if cmd.linear_mps > 0.0
                                && self.sim.robots()[..i]
                                    .iter()
                                    .any(|o| gives_way(r.pose, o.pose.position()))
                            {
                                cmd.linear_mps = 0.0;
                            }
                            cmd
                        }
                    }
                })
                .collect();
            self.sim.step(&commands);
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
            for (i, a) in self.agents.iter_mut().enumerate() {
                let r = self.sim.robot(a.id);
                if r.failed || a.recovery.is_some() || who.contains(&i) {
                    continue;
                }
                let done = a.follower.is_done(r.pose);
                if a.target.is_some() && !done && now - a.progress_mark.1 >= STUCK_WINDOW_S {
                    if r.pose.position().distance(a.progress_mark.0) < STUCK_DISTANCE_M {
                        a.blacklist
                            .push((a.target.expect("has target"), now + BLACKLIST_S));
                        a.follower = PathFollower::default();
                        a.target = None;
                        who.push(i);
                        continue;
                    }
                    a.progress_mark = (r.pose.position(), now);
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
                    a.blacklist.push((reached, now + REACHED_BLACKLIST_S));
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
                if now - since >= EXPLORED_AFTER_S {
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
            merged_map: self.base.merged,
        }
    }
}

/// The way back along a trajectory: its points from the latest backwards, until [`RETRACE_M`]
/// away from `here` along the way (empty when there is no way back).
fn retrace(trajectory: &[Point2], here: Point2) -> Vec<Point2> {
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
        if length >= RETRACE_M {
            break;
        }
    }
    if last.distance(here) < 1.0 {
        out.clear();
    }
    out
}

/// Whether a robot at `pose` must give way to a robot at `other` (close, ahead of it).
fn gives_way(pose: usar_world::Pose2, other: Point2) -> bool {
    let here = pose.position();
    here.distance(other) < YIELD_DISTANCE_M
        && usar_world::normalize_angle(here.bearing_to(other) - pose.theta).abs()
            < YIELD_HALF_ANGLE_RAD
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

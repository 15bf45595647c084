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

/// Why a mission could not start.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// The scene has fewer start poses than robots.
    #[error("scene {scene} has {available} start poses, {requested} robots were asked for")]
    NotEnoughStartPoses { scene: String, available: usize, requested: usize },
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
}

pub struct TeamMission {
    config: TeamConfig,
    sim: Simulation,
    agents: Vec<Agent>,
    base: BaseStation,
    victims_seen: Vec<VictimSighting>,
    samples: Vec<Sample>,
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
                return Err(MissionError::Config(format!("{name} must be a positive number of seconds, found {v}")));
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
            });
        }
        let start = scene.start_poses[0].position();
        let base = BaseStation::new(&scene, params, config.robot.circumscribed_radius_m(), start);
        Ok(Self { config, sim, agents, base, victims_seen: Vec::new(), samples: Vec::new() })
    }

    pub fn base_station(&self) -> &BaseStation {
        &self.base
    }

    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    fn every(&self, period_s: f64, step: u64) -> bool {
        let n = (period_s / self.config.sim.dt_s).round().max(1.0) as u64;
        step % n == 0
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
        let mut maps: Vec<&mut OccupancyGrid> = self.agents.iter_mut().map(|a| &mut a.map).collect();
        self.base.merge(&mut maps);
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
                    self.victims_seen.push(VictimSighting { victim_id: id, robot: a.id.0, time_s: now });
                }
            }
        }
    }

    /// The navigable cell nearest to a robot (itself when navigable), searched within 1 m.
    fn source_cell(&self, grid: &NavGrid, p: Point2) -> Cell {
        let g = self.base.merged.geometry();
        let c = g.world_to_cell(p);
        let reach = (1.0 / g.resolution_m).ceil() as i32;
        for ring in 0..=reach {
            let mut best: Option<(f64, Cell)> = None;
            for dr in -ring..=ring {
                for dc in -ring..=ring {
                    if dr.abs().max(dc.abs()) != ring {
                        continue;
                    }
                    let n = Cell::new(c.col + dc, c.row + dr);
                    if g.contains(n) && grid.is_passable(n) {
                        let d = g.cell_center(n).distance_squared(p);
                        if best.is_none_or(|(bd, bc)| d < bd || (d == bd && n < bc)) {
                            best = Some((d, n));
                        }
                    }
                }
            }
            if let Some((_, n)) = best {
                return n;
            }
        }
        c
    }

    /// Reassigns targets to the robots in `who` (all robots at a periodic auction, or those
    /// that reached their target or got stuck).
    fn assign(&mut self, who: &[usize]) -> bool {
        let clusters = self.base.clusters(self.config.min_cluster_cells);
        let g = *self.base.merged.geometry();
        let nav = &self.base.navigable;
        let merged = &self.base.merged;
        let cands: Vec<Candidate> = candidates(&clusters, |c| g.checked_index(c).is_some_and(|i| nav.is_navigable(merged, i)), &g);
        let mut grid = NavGrid::from_fn(g, |c| !nav.is_navigable(merged, g.index(c)));
        let now = self.sim.time_s();
        // Targets of robots that keep theirs are taken (one robot per candidate).
        let keep: Vec<Cell> = (0..self.agents.len()).filter(|i| !who.contains(i)).filter_map(|i| self.agents[i].target).collect();
        let mut costs = Vec::with_capacity(who.len());
        for &i in who {
            let pose = self.sim.robot(self.agents[i].id).pose;
            // Other robots are obstacles for this robot's plan.
            let mut closed = Vec::new();
            let clearance = self.config.robot.circumscribed_radius_m() * 2.0;
            for (j, other) in self.agents.iter().enumerate() {
                if j == i || self.sim.robot(other.id).failed {
                    continue;
                }
                let p = self.sim.robot(other.id).pose.position();
                block_disc(&mut grid, p, clearance, &mut closed);
            }
            let source = self.source_cell(&grid, pose.position());
            let was_passable = grid.is_passable(source);
            grid.set_passable(source, true);
            let agent = &mut self.agents[i];
            agent.blacklist.retain(|&(_, until)| until > now);
            let mut row = path_costs(&mut agent.field, &grid, source, &cands);
            for (k, c) in cands.iter().enumerate() {
                if keep.contains(&c.cell) || agent.blacklist.iter().any(|&(b, _)| b.chebyshev(c.cell) <= 3) {
                    row[k] = None;
                }
            }
            costs.push(row);
            grid.set_passable(source, was_passable);
            for c in closed {
                grid.set_passable(c, true);
            }
        }
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
                    let path = agent.field.path_to_source(target).map(|p| p.cells).unwrap_or_default();
                    let waypoints: Vec<Point2> = path.iter().rev().map(|&c| g.cell_center(c)).collect();
                    agent.follower = PathFollower::new(waypoints);
                    agent.target = Some(target);
                }
                None => {
                    agent.follower = PathFollower::default();
                    agent.target = None;
                }
            }
            agent.progress_mark = (self.sim.robot(agent.id).pose.position(), now);
        }
        any
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
        while finish == Finish::TimeLimit && step < steps {
            step += 1;
            let commands: Vec<Velocity> = self
                .agents
                .iter_mut()
                .map(|a| {
                    let r = self.sim.robot(a.id);
                    a.follower.command(r.pose, &r.spec)
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
            // Who needs a new target: reached it, has none, or made no progress.
            let mut who = Vec::new();
            for (i, a) in self.agents.iter_mut().enumerate() {
                let r = self.sim.robot(a.id);
                if r.failed {
                    continue;
                }
                let done = a.follower.is_done(r.pose);
                if a.target.is_some() && !done && now - a.progress_mark.1 >= STUCK_WINDOW_S {
                    if r.pose.position().distance(a.progress_mark.0) < STUCK_DISTANCE_M {
                        a.blacklist.push((a.target.expect("has target"), now + BLACKLIST_S));
                        a.follower = PathFollower::default();
                        a.target = None;
                        who.push(i);
                        continue;
                    }
                    a.progress_mark = (r.pose.position(), now);
                }
                if done && (a.target.is_some() || merged_now) {
                    who.push(i);
                }
            }
            if self.every(self.config.timing.assignment_period_s, step) {
                who = everyone.clone();
            }
            if !who.is_empty() {
                let any = self.assign(&who);
                let all_idle = self.agents.iter().all(|a| a.target.is_none());
                if !any && all_idle && merged_now {
                    finish = Finish::Explored;
                }
            }
            if self.every(self.config.timing.sample_period_s, step) {
                self.sample();
                on_progress(now);
            }
            if let Some(target) = self.config.stop_at_coverage
                && merged_now
                && self.base.coverage.coverage() >= target
            {
                finish = Finish::CoverageTarget;
            }
        }
        self.merge();
        if self.samples.last().is_none_or(|s| s.time_s < self.sim.time_s()) {
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
                    RobotOutcome { robot: a.id.0, distance_m: r.distance_m, collisions: r.collisions, trajectory: a.trajectory.clone() }
                })
                .collect(),
            series: self.samples,
            merged_map: self.base.merged,
        }
    }
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

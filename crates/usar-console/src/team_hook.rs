//! The team's simulation thread: [`ConsoleHook`] sits beside [`usar_team::TeamMission`]
//! ([`usar_team::MissionHook`]): after every simulation step it carries out the operators'
//! commands, paces the step to the chosen speed, moves the mission clock and publishes frames
//! (every [`FRAME_PERIOD`]) and maps (when they changed, at most every [`MAP_PERIOD`]).

use crate::mission::{Command, OperatorAnswer, Shared};
use crate::protocol::{ClientMessage, DriveCommand};
use crate::scene_setup::label_code;
use crate::snapshot::{Frame, HandOffKind, MapView, RobotView, VictimView};
use base64::Engine;
use std::sync::Arc;
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};
use usar_map::CellClass;
use usar_map::planning::{Connectivity, GridAStar};
use usar_sim::{CellAction, Velocity};
use usar_team::driver::{PathFollower, Recovery, RecoveryStep};
use usar_team::{MissionHook, Strategy, TeamMission};
use usar_world::{GridGeometry, Scene};

/// How often viewers get a frame (20 per second).
pub const FRAME_PERIOD: Duration = Duration::from_millis(50);
/// How often, at most, viewers get the maps.
pub const MAP_PERIOD: Duration = Duration::from_millis(500);
/// A teleoperation command lapses after this long without a repeat.
const TELEOP_LAPSE: Duration = Duration::from_millis(500);
/// A `drive` pulse for a team robot lasts this long.
const PULSE: Duration = Duration::from_millis(400);

/// The paper-002 strategy by name (the baseline `nearest` has no semantic criterion).
pub fn strategy(name: &str) -> Option<Strategy> {
    Strategy::from_name(name).filter(|s| *s != Strategy::Nearest)
}

/// A team robot under operator control.
enum Override {
    Teleop {
        velocity: Velocity,
        until: Instant,
    },
    /// Sent to a point: the path, and the recovery manoeuvre under way after a bump, as the
    /// team's own robots.
    Path {
        follower: PathFollower,
        recovery: Recovery,
        /// The velocity computed at the last step.
        command: Velocity,
    },
}

/// Pace: simulated time runs at `speed` × wall-clock time, measured over the last second.
struct Pacer {
    speed: f64,
    paused: bool,
    anchor_wall: Instant,
    anchor_sim_s: f64,
    window: std::collections::VecDeque<(Instant, f64)>,
}

impl Pacer {
    fn reanchor(&mut self, sim_s: f64) {
        self.anchor_wall = Instant::now();
        self.anchor_sim_s = sim_s;
    }

    fn due(&self, sim_s: f64) -> Instant {
        self.anchor_wall
            + Duration::from_secs_f64(((sim_s - self.anchor_sim_s) / self.speed).max(0.0))
    }

    fn measured(&mut self, sim_s: f64) -> f64 {
        let now = Instant::now();
        self.window.push_back((now, sim_s));
        while self
            .window
            .front()
            .is_some_and(|(t, _)| now.duration_since(*t) > Duration::from_secs(1))
        {
            self.window.pop_front();
        }
        match (self.window.front(), self.window.back()) {
            (Some((t0, s0)), Some((t1, s1))) if t1 > t0 => {
                (s1 - s0) / t1.duration_since(*t0).as_secs_f64()
            }
            _ => 0.0,
        }
    }
}

/// The team's merged grid, encoded for map messages (see [`MapView`]).
struct TeamGrid {
    geometry: GridGeometry,
    cells: String,
    labels: String,
}

/// See the [module documentation](self).
pub struct ConsoleHook {
    shared: Arc<Shared>,
    commands: Receiver<Command>,
    pacer: Pacer,
    overrides: Vec<Option<Override>>,
    planner: GridAStar,
    last_frame: Instant,
    last_map: Instant,
    seq: u64,
    map_seq: u64,
    map_state: (usize, u64, usize),
    /// Room label code per merged-map cell.
    labels: Vec<u8>,
    explored: Vec<[f64; 2]>,
    team: Vec<RobotView>,
    /// The team's merged grid as last encoded for a map message.
    team_grid: Option<TeamGrid>,
    /// Known area and coverage of the team's map, as last observed.
    explored_m2: f64,
    coverage: f64,
    hypothesis: String,
    finish: Option<String>,
    sim_s: f64,
}

impl ConsoleHook {
    pub(crate) fn new(
        shared: Arc<Shared>,
        commands: Receiver<Command>,
        speed: f64,
        hypothesis: &str,
        robots: usize,
    ) -> Self {
        let long_ago = Instant::now() - Duration::from_secs(10);
        Self {
            shared,
            commands,
            pacer: Pacer {
                speed,
                paused: false,
                anchor_wall: Instant::now(),
                anchor_sim_s: 0.0,
                window: Default::default(),
            },
            overrides: (0..robots).map(|_| None).collect(),
            planner: GridAStar::new(),
            last_frame: long_ago,
            last_map: long_ago,
            seq: 0,
            map_seq: 0,
            map_state: (usize::MAX, u64::MAX, usize::MAX),
            labels: Vec::new(),
            explored: Vec::new(),
            team: Vec::new(),
            team_grid: None,
            explored_m2: 0.0,
            coverage: 0.0,
            hypothesis: hypothesis.into(),
            finish: None,
            sim_s: 0.0,
        }
    }

    /// Carries out one command; the error is replied to the sender.
    fn apply(
        &mut self,
        message: ClientMessage,
        mission: Option<&mut TeamMission>,
    ) -> Result<(), String> {
        let team_robot = |robot: usize, n: usize| -> Result<usize, String> {
            if (1..=n).contains(&robot) {
                Ok(robot - 1)
            } else {
                Err(format!("robot {robot}: the team robots are 1 to {n}"))
            }
        };
        let n = self.overrides.len();
        match message {
            ClientMessage::Auth { .. } => Ok(()),
            ClientMessage::Pause {} => {
                self.pacer.paused = true;
                Ok(())
            }
            ClientMessage::Resume {} => {
                self.pacer.paused = false;
                self.pacer.reanchor(self.sim_s);
                Ok(())
            }
            ClientMessage::Speed { factor } => {
                self.pacer.speed = factor;
                self.pacer.reanchor(self.sim_s);
                Ok(())
            }
            ClientMessage::AnswerVictim { handoff, tag } => {
                let waiting = self
                    .shared
                    .lock_rescue()
                    .handoff
                    .as_ref()
                    .is_some_and(|h| h.kind == HandOffKind::Victim && h.id == handoff);
                if !waiting {
                    return Err(format!("no victim hand-off {handoff} is waiting"));
                }
                self.shared.answer(OperatorAnswer::Victim { handoff, tag })
            }
            ClientMessage::Drive { robot: 0, command } => {
                let stuck = self
                    .shared
                    .lock_rescue()
                    .handoff
                    .as_ref()
                    .is_some_and(|h| h.kind == HandOffKind::Stuck);
                if !stuck {
                    return Err(
                        "robot 0 (MAXQ) is autonomous: it hands navigation over when it is stuck"
                            .into(),
                    );
                }
                let action = match command {
                    DriveCommand::Forward => CellAction::Forward,
                    DriveCommand::Backward => CellAction::Backward,
                    DriveCommand::Left => CellAction::RotateLeft,
                    DriveCommand::Right => CellAction::RotateRight,
                };
                self.shared.answer(OperatorAnswer::Drive(action))
            }
            ClientMessage::Drive { robot, command } => {
                let k = team_robot(robot, n)?;
                let (linear, angular) = match command {
                    DriveCommand::Forward => (1.0, 0.0),
                    DriveCommand::Backward => (-0.5, 0.0),
                    DriveCommand::Left => (0.0, 1.0),
                    DriveCommand::Right => (0.0, -1.0),
                };
                self.teleop(k, linear, angular, PULSE, mission)
            }
            ClientMessage::Teleop {
                robot,
                linear,
                angular,
            } => {
                let k = team_robot(robot, n)?;
                self.teleop(k, linear, angular, TELEOP_LAPSE, mission)
            }
            ClientMessage::Release { robot } => {
                let k = team_robot(robot, n)?;
                self.overrides[k] = None;
                Ok(())
            }
            ClientMessage::SendTo { robot, x, y } => {
                if robot == 0 {
                    return Err("robot 0 (MAXQ) follows its policy; send a team robot (1…)".into());
                }
                let k = team_robot(robot, n)?;
                let mission = mission.ok_or("the team's mission has ended")?;
                let path = self.plan(mission, k, usar_world::Point2::new(x, y))?;
                let spec = &mission.simulation().robots()[k].spec;
                self.overrides[k] = Some(Override::Path {
                    follower: path,
                    recovery: Recovery::for_robot(spec),
                    command: Velocity::default(),
                });
                Ok(())
            }
            ClientMessage::Weights { w_l, w_p, w_q } => {
                let mut r = self.shared.lock_rescue();
                r.weights = [w_l, w_p, w_q];
                r.weights_changed = Some([w_l, w_p, w_q]);
                Ok(())
            }
            ClientMessage::Hypothesis { name } => {
                let h = usar_team::criteria::Hypothesis::named(&name)
                    .ok_or_else(|| format!("hypothesis {name:?}: expected big or small"))?;
                let mission = mission.ok_or("the team's mission has ended")?;
                mission.set_hypothesis(h);
                self.hypothesis = name;
                Ok(())
            }
        }
    }

    fn teleop(
        &mut self,
        k: usize,
        linear: f64,
        angular: f64,
        lasting: Duration,
        mission: Option<&mut TeamMission>,
    ) -> Result<(), String> {
        let mission = mission.ok_or("the team's mission has ended")?;
        let spec = &mission.simulation().robots()[k].spec;
        let velocity = Velocity {
            linear_mps: linear.clamp(-1.0, 1.0) * spec.max_linear_mps,
            angular_radps: angular.clamp(-1.0, 1.0) * spec.max_angular_radps,
        };
        self.overrides[k] = Some(Override::Teleop {
            velocity,
            until: Instant::now() + lasting,
        });
        Ok(())
    }

    /// A path for team robot `k` to `goal` on the merged map's navigable cells.
    fn plan(
        &mut self,
        mission: &TeamMission,
        k: usize,
        goal: usar_world::Point2,
    ) -> Result<PathFollower, String> {
        let base = mission.base_station();
        let g = *base.merged.geometry();
        let from = g.world_to_cell(mission.simulation().robots()[k].pose.position());
        let to = g.world_to_cell(goal);
        if !g.contains(to) {
            return Err(format!("({:.2}, {:.2}) is outside the map", goal.x, goal.y));
        }
        // The base station's grid of the tight radius, with the robot's own cell open.
        let mut grid = base.nav_grids[1].clone();
        grid.set_passable(from, true);
        let path = self
            .planner
            .plan(&grid, from, to, Connectivity::Eight)
            .ok_or_else(|| {
                format!(
                    "no path on the known free space to ({:.2}, {:.2})",
                    goal.x, goal.y
                )
            })?;
        Ok(PathFollower::new(
            path.cells
                .iter()
                .skip(1)
                .map(|&c| g.cell_center(c))
                .collect(),
        ))
    }

    fn drain_commands(&mut self, mut mission: Option<&mut TeamMission>) {
        while let Ok((message, reply)) = self.commands.try_recv() {
            let result = self.apply(message, mission.as_deref_mut());
            let _ = reply.send(result);
        }
    }

    /// Team robots and explored area from the mission.
    fn observe(&mut self, mission: &TeamMission) {
        let sim = mission.simulation();
        self.team = sim
            .robots()
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let (mode, task) = match &self.overrides[k] {
                    Some(Override::Teleop { .. }) => ("operator", "teleoperated"),
                    Some(Override::Path { .. }) => ("operator", "sent to a point"),
                    None if r.failed => ("autonomous", "failed"),
                    None if mission.is_recovering(k) => ("autonomous", "recovering"),
                    None if mission.robot_goal(k).is_some() => ("autonomous", "exploring"),
                    None => ("autonomous", "idle"),
                };
                let goal = match &self.overrides[k] {
                    Some(Override::Path { follower, .. }) => follower.goal(),
                    _ => mission.robot_goal(k),
                };
                RobotView {
                    id: k + 1,
                    name: format!("team {}", k + 1),
                    kind: "team".into(),
                    x: r.pose.x,
                    y: r.pose.y,
                    theta: r.pose.theta,
                    mode: mode.into(),
                    task: task.into(),
                    goal: goal.map(|p| [p.x, p.y]),
                }
            })
            .collect();
        let base = mission.base_station();
        self.explored_m2 = base.merged.known_area_m2();
        self.coverage = mission.coverage();
        if self
            .explored
            .last()
            .is_none_or(|s| self.sim_s - s[0] >= 1.0)
        {
            self.explored.push([self.sim_s, self.explored_m2]);
        }
    }

    /// Encodes the team's merged grid and its room labels for the next map message.
    fn encode_team_grid(&mut self, mission: &TeamMission) {
        let sim = mission.simulation();
        let merged = &mission.base_station().merged;
        let g = *merged.geometry();
        if self.labels.len() != g.len() {
            let scene: &Scene = sim.scene();
            self.labels = (0..g.len())
                .map(|i| {
                    let p = g.cell_center(g.cell_of_index(i));
                    let c = scene.geometry().world_to_cell(p);
                    label_code(scene.label_at(c))
                })
                .collect();
        }
        let mut cells = Vec::with_capacity(g.len());
        let mut labels = Vec::with_capacity(g.len());
        for i in 0..g.len() {
            let class = merged.class_at_index(i);
            cells.push(match class {
                CellClass::Unknown => 0u8,
                CellClass::Free => 1,
                CellClass::Occupied => 2,
            });
            labels.push(if class == CellClass::Unknown {
                0
            } else {
                self.labels[i]
            });
        }
        let b64 = base64::engine::general_purpose::STANDARD;
        self.team_grid = Some(TeamGrid {
            geometry: g,
            cells: b64.encode(&cells),
            labels: b64.encode(&labels),
        });
    }

    /// What the maps depend on: explored-area samples, the MAXQ robot's cell map, the BTM.
    fn map_state(&self) -> (usize, u64, usize) {
        let cell_map_version = self.shared.lock_rescue().cell_map_version;
        let btm = self.shared.lock_btm();
        (
            self.explored.len(),
            cell_map_version,
            btm.nodes.len() + btm.links.len(),
        )
    }

    /// Publishes a frame now, and the maps when `map_state` is given (they changed).
    fn publish(&mut self, measured_speed: f64, map_state: Option<(usize, u64, usize)>) {
        self.seq += 1;
        let rescue = self.shared.lock_rescue();
        let btm = self.shared.lock_btm();
        let mut maps = None;
        if let Some(state) = map_state
            && let Some(grid) = &self.team_grid
        {
            self.map_state = state;
            self.last_map = Instant::now();
            self.map_seq += 1;
            let b64 = base64::engine::general_purpose::STANDARD;
            let g = grid.geometry;
            maps = Some(MapView {
                kind: "map".into(),
                seq: self.map_seq,
                width: g.width,
                height: g.height,
                resolution_m: g.resolution_m,
                origin: [g.origin.x, g.origin.y],
                cells: grid.cells.clone(),
                labels: grid.labels.clone(),
                cell_cols: rescue.cell_cols,
                cell_rows: rescue.cell_rows,
                cell_size_m: rescue.cell_size_m,
                cell_origin: rescue.cell_origin,
                cell_map: b64.encode(&rescue.cell_map),
                btm_nodes: btm.nodes.clone(),
                btm_links: btm.links.clone(),
                explored: self.explored.clone(),
            });
        }
        let mut robots = Vec::with_capacity(self.team.len() + 2);
        robots.push(RobotView {
            id: 0,
            name: "MAXQ".into(),
            kind: "maxq".into(),
            x: rescue.pose[0],
            y: rescue.pose[1],
            theta: rescue.pose[2],
            mode: rescue.mode.into(),
            task: rescue.task.clone(),
            goal: None,
        });
        robots.extend(self.team.iter().cloned());
        if let Some([x, y, theta]) = btm.crawler {
            let building = btm.status == "building";
            robots.push(RobotView {
                id: self.team.len() + 1,
                name: "BTM crawler".into(),
                kind: "btm".into(),
                x,
                y,
                theta,
                mode: "autonomous".into(),
                task: if building {
                    format!("building the BTM (paper 004): {} nodes", btm.nodes.len())
                } else {
                    format!("BTM {}", btm.status)
                },
                goal: None,
            });
        }
        let victims = rescue
            .victims
            .iter()
            .enumerate()
            .map(|(id, (&(c, r), &(mark, probability)))| {
                let x = rescue.cell_origin[0] + (f64::from(c) + 0.5) * rescue.cell_size_m;
                let y = rescue.cell_origin[1] + (f64::from(r) + 0.5) * rescue.cell_size_m;
                VictimView {
                    id,
                    x,
                    y,
                    status: match mark {
                        usar_rescue::VictimMark::Pending => "pending",
                        usar_rescue::VictimMark::Tagged => "tagged",
                        usar_rescue::VictimMark::Dismissed => "dismissed",
                    }
                    .into(),
                    probability,
                }
            })
            .collect();
        let frame = Frame {
            kind: "frame".into(),
            seq: self.seq,
            time_s: self.sim_s,
            paused: self.pacer.paused,
            speed: self.pacer.speed,
            measured_speed,
            robots,
            victims,
            handoffs: rescue.handoff.iter().cloned().collect(),
            explored_m2: self.explored_m2,
            coverage: self.coverage,
            weights: rescue.weights,
            hypothesis: self.hypothesis.clone(),
            btm_nodes: btm.nodes.len(),
            btm_links: btm.links.len(),
            team_finish: self.finish.clone(),
            maxq_episodes: rescue.episodes,
            maxq_tags: rescue.tags,
            map_seq: self.map_seq,
        };
        drop(rescue);
        drop(btm);
        if let Some(m) = maps
            && let Ok(text) = serde_json::to_string(&m)
        {
            self.shared.map_tx.send_replace(Arc::from(text));
        }
        if let Ok(text) = serde_json::to_string(&frame) {
            self.shared.frame_tx.send_replace(Arc::from(text));
        }
        self.last_frame = Instant::now();
    }

    /// Waits until simulated time `sim_s` is due, carrying out commands and publishing frames
    /// meanwhile; `false` when the mission is stopping.
    fn pace(&mut self, mut mission: Option<&mut TeamMission>) -> bool {
        loop {
            self.drain_commands(mission.as_deref_mut());
            if self.shared.clock.is_stopping() {
                return false;
            }
            if self.last_frame.elapsed() >= FRAME_PERIOD {
                if let Some(m) = mission.as_deref() {
                    self.observe(m);
                }
                // The team's grid is encoded only when a map message goes out.
                let state = self.map_state();
                let map_due = state != self.map_state && self.last_map.elapsed() >= MAP_PERIOD;
                if map_due && let Some(m) = mission.as_deref() {
                    self.encode_team_grid(m);
                }
                let measured = self.pacer.measured(self.sim_s);
                self.publish(measured, map_due.then_some(state));
            }
            if self.pacer.paused {
                std::thread::sleep(Duration::from_millis(10));
                continue;
            }
            let due = self.pacer.due(self.sim_s);
            let now = Instant::now();
            if now >= due {
                // More than two seconds behind: the machine cannot keep up; do not race.
                if now.duration_since(due) > Duration::from_secs(2) {
                    self.pacer.reanchor(self.sim_s);
                }
                return true;
            }
            std::thread::sleep((due - now).min(Duration::from_millis(10)));
        }
    }

    /// After the team's mission ended: the clock goes on for the other robots.
    pub(crate) fn after_mission(&mut self, finish: &str) {
        self.finish = Some(finish.into());
        for o in &mut self.overrides {
            *o = None;
        }
        let tick = 0.1;
        loop {
            self.sim_s += tick;
            self.shared.clock.advance_to(self.sim_s);
            if !self.pace(None) {
                return;
            }
        }
    }
}

impl MissionHook for ConsoleHook {
    fn command(&mut self, robot: usize, planned: Velocity) -> Velocity {
        match &self.overrides[robot] {
            Some(Override::Teleop { velocity, until }) if Instant::now() < *until => *velocity,
            Some(Override::Teleop { .. }) => {
                self.overrides[robot] = None;
                planned
            }
            Some(Override::Path { command, .. }) => *command,
            None => planned,
        }
    }

    fn after_step(&mut self, mission: &mut TeamMission) -> bool {
        self.sim_s = mission.simulation().time_s();
        for k in 0..self.overrides.len() {
            if let Some(Override::Path {
                follower,
                recovery,
                command,
            }) = &mut self.overrides[k]
            {
                let r = &mission.simulation().robots()[k];
                if follower.is_done(r.pose) {
                    self.overrides[k] = None;
                    continue;
                }
                // After a bump the team's own recovery, then the path again.
                recovery.record(r.last_motion(), mission.simulation().config().dt_s);
                *command = match recovery.step(self.sim_s, r.in_contact()) {
                    RecoveryStep::Escape(v) => v,
                    RecoveryStep::Ended | RecoveryStep::Free => follower.command(r.pose, &r.spec),
                };
            }
        }
        self.shared.clock.advance_to(self.sim_s);
        self.shared
            .steps
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.pace(Some(mission))
    }
}

//! The console beside the running mission: [`ConsoleHook`] is the mission's
//! [`usar_mission::MissionHook`]. At every simulation step, after the controllers decided and
//! before the world moves, it carries out the browsers' commands (answers at the desk,
//! teleoperation, a point to go to, the hypothesis, the weights), drives the team robots under
//! operator control, paces the step to the chosen speed, moves the mission clock and publishes
//! frames (every [`FRAME_PERIOD`]) and maps (when they changed, at most every [`MAP_PERIOD`]).

use crate::mission::{Command, Shared};
use crate::protocol::{ClientMessage, DriveCommand};
use crate::view::{Observed, console_ids};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, SyncSender};
use std::time::{Duration, Instant};
use usar_map::planning::{Connectivity, GridAStar};
use usar_mission::{LiveMission, MissionError, MissionHook};
use usar_rescue::controller::{Answer, Question};
use usar_rescue::exploration::ExplorationWeights;
use usar_rescue::operator::VictimDecision;
use usar_sim::{CellAction, Velocity};
use usar_team::driver::{PathFollower, Recovery, RecoveryStep};
use usar_world::Point2;

/// How often viewers get a frame (20 per second).
pub const FRAME_PERIOD: Duration = Duration::from_millis(50);
/// How often, at most, viewers get the maps.
pub const MAP_PERIOD: Duration = Duration::from_millis(500);
/// A teleoperation command lapses after this long without a repeat.
const TELEOP_LAPSE: Duration = Duration::from_millis(500);
/// A `drive` pulse for a team robot lasts this long.
const PULSE: Duration = Duration::from_millis(400);

/// A team robot under operator control.
pub(crate) enum Override {
    Teleop {
        velocity: Velocity,
        until: Instant,
    },
    /// Sent to a point: the path, and the recovery manoeuvre under way after a bump, as the
    /// team's own robots.
    Path {
        follower: PathFollower,
        recovery: Recovery,
    },
}

/// Pace: simulated time runs at `speed` × wall-clock time, measured over the last second.
pub(crate) struct Pacer {
    pub speed: f64,
    pub paused: bool,
    anchor_wall: Instant,
    anchor_sim_s: f64,
    window: std::collections::VecDeque<(Instant, f64)>,
}

impl Pacer {
    fn new(speed: f64) -> Self {
        Self {
            speed,
            paused: false,
            anchor_wall: Instant::now(),
            anchor_sim_s: 0.0,
            window: Default::default(),
        }
    }

    fn reanchor(&mut self, sim_s: f64) {
        self.anchor_wall = Instant::now();
        self.anchor_sim_s = sim_s;
    }

    fn due(&self, sim_s: f64) -> Instant {
        self.anchor_wall
            + Duration::from_secs_f64(((sim_s - self.anchor_sim_s) / self.speed).max(0.0))
    }

    /// Simulated seconds per wall second over the last second.
    pub(crate) fn measured(&mut self, sim_s: f64) -> f64 {
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

/// See the [module documentation](self).
pub struct ConsoleHook {
    shared: Arc<Shared>,
    commands: Receiver<Command>,
    /// Told once, at the first step, that the mission is set up (or why it is not).
    ready: Option<SyncSender<Result<(), MissionError>>>,
    pub(crate) pacer: Pacer,
    /// Per team robot.
    pub(crate) overrides: Vec<Option<Override>>,
    planner: GridAStar,
    pub(crate) observed: Observed,
    pub(crate) sim_s: f64,
}

/// Team robot `robot` (1…n on the console) as the team's index.
fn team_index(robot: usize, n: usize) -> Result<usize, String> {
    if (1..=n).contains(&robot) {
        Ok(robot - 1)
    } else if robot == n + 1 {
        Err(format!(
            "robot {robot} (the BTM crawler) follows paper 004's behaviours on its own"
        ))
    } else {
        Err(format!("robot {robot}: the team robots are 1 to {n}"))
    }
}

impl ConsoleHook {
    pub(crate) fn new(
        shared: Arc<Shared>,
        commands: Receiver<Command>,
        ready: SyncSender<Result<(), MissionError>>,
        speed: f64,
        hypothesis: &str,
        weights: [f64; 3],
    ) -> Self {
        Self {
            shared,
            commands,
            ready: Some(ready),
            pacer: Pacer::new(speed),
            overrides: Vec::new(),
            planner: GridAStar::new(),
            observed: Observed::new(hypothesis, weights),
            sim_s: 0.0,
        }
    }

    /// Tells the launcher why the mission could not start, if it has not started.
    pub(crate) fn failed(&mut self, error: MissionError) -> Option<MissionError> {
        match self.ready.take() {
            Some(ready) => {
                let _ = ready.send(Err(error));
                None
            }
            None => Some(error),
        }
    }

    /// Carries out a message about the clock (or the token), which needs no mission.
    fn clock_command(&mut self, message: &ClientMessage) -> Option<Result<(), String>> {
        match *message {
            ClientMessage::Auth { .. } => {}
            ClientMessage::Pause {} => self.pacer.paused = true,
            ClientMessage::Resume {} => {
                self.pacer.paused = false;
                self.pacer.reanchor(self.sim_s);
            }
            ClientMessage::Speed { factor } => {
                self.pacer.speed = factor;
                self.pacer.reanchor(self.sim_s);
            }
            _ => return None,
        }
        Some(Ok(()))
    }

    /// Carries out one command; the error is replied to the sender.
    fn apply(
        &mut self,
        message: ClientMessage,
        live: &mut LiveMission<'_, '_>,
    ) -> Result<(), String> {
        if let Some(result) = self.clock_command(&message) {
            return result;
        }
        let n = live.team_len();
        match message {
            ClientMessage::Auth { .. }
            | ClientMessage::Pause {}
            | ClientMessage::Resume {}
            | ClientMessage::Speed { .. } => Ok(()),
            ClientMessage::AnswerVictim { handoff, tag } => {
                let decision = if tag {
                    VictimDecision::Tag
                } else {
                    VictimDecision::Reject
                };
                live.respond(handoff, Answer::Victim(decision))
                    .map_err(|e| e.to_string())
            }
            ClientMessage::Drive { robot: 0, command } => {
                let rescuer = live
                    .rescuer_robot()
                    .ok_or("this mission has no MAXQ robot")?;
                let asking = live.desk().attending().filter(|q| {
                    q.robot == rescuer.0 && matches!(q.question, Question::Drive { .. })
                });
                let Some(question) = asking else {
                    return Err(
                        "robot 0 (MAXQ) is autonomous: it hands navigation over when it is stuck"
                            .into(),
                    );
                };
                let action = match command {
                    DriveCommand::Forward => CellAction::Forward,
                    DriveCommand::Backward => CellAction::Backward,
                    DriveCommand::Left => CellAction::RotateLeft,
                    DriveCommand::Right => CellAction::RotateRight,
                };
                live.respond(question.id, Answer::Drive(action))
                    .map_err(|e| e.to_string())
            }
            ClientMessage::Drive { robot, command } => {
                let k = team_index(robot, n)?;
                let (linear, angular) = match command {
                    DriveCommand::Forward => (1.0, 0.0),
                    DriveCommand::Backward => (-0.5, 0.0),
                    DriveCommand::Left => (0.0, 1.0),
                    DriveCommand::Right => (0.0, -1.0),
                };
                self.teleop(live, k, linear, angular, PULSE);
                Ok(())
            }
            ClientMessage::Teleop {
                robot,
                linear,
                angular,
            } => {
                let k = team_index(robot, n)?;
                self.teleop(live, k, linear, angular, TELEOP_LAPSE);
                Ok(())
            }
            ClientMessage::Release { robot } => {
                let k = team_index(robot, n)?;
                self.overrides[k] = None;
                Ok(())
            }
            ClientMessage::SendTo { robot, x, y } => {
                if robot == 0 {
                    return Err("robot 0 (MAXQ) follows its policy; send a team robot (1…)".into());
                }
                let k = team_index(robot, n)?;
                let follower = self.plan(live, k, Point2::new(x, y))?;
                let id = live.team_robot(k).ok_or("no such team robot")?;
                let spec = &live.evaluator().robot(id).spec;
                self.overrides[k] = Some(Override::Path {
                    follower,
                    recovery: Recovery::for_robot(spec),
                });
                Ok(())
            }
            ClientMessage::Weights { w_l, w_p, w_q } => {
                let rescuer = live.rescuer_mut().ok_or("this mission has no MAXQ robot")?;
                rescuer.set_exploration_weights(ExplorationWeights::weighted(
                    "console", w_l, w_p, w_q,
                ));
                self.observed.weights = [w_l, w_p, w_q];
                Ok(())
            }
            ClientMessage::Hypothesis { name } => {
                let h = usar_team::criteria::Hypothesis::named(&name)
                    .ok_or_else(|| format!("hypothesis {name:?}: expected big or small"))?;
                live.team_mut().set_hypothesis(h);
                self.observed.hypothesis = name;
                Ok(())
            }
        }
    }

    fn teleop(
        &mut self,
        live: &LiveMission<'_, '_>,
        k: usize,
        linear: f64,
        angular: f64,
        lasting: Duration,
    ) {
        let Some(id) = live.team_robot(k) else {
            return;
        };
        let spec = &live.evaluator().robot(id).spec;
        let velocity = Velocity {
            linear_mps: linear.clamp(-1.0, 1.0) * spec.max_linear_mps,
            angular_radps: angular.clamp(-1.0, 1.0) * spec.max_angular_radps,
        };
        self.overrides[k] = Some(Override::Teleop {
            velocity,
            until: Instant::now() + lasting,
        });
    }

    /// A path for team robot `k` from where it believes it is to `goal`, on the base
    /// station's navigable cells.
    fn plan(
        &mut self,
        live: &LiveMission<'_, '_>,
        k: usize,
        goal: Point2,
    ) -> Result<PathFollower, String> {
        let team = live.team();
        let base = team.base_station();
        let g = *base.merged.geometry();
        let pose = team.pose(k).ok_or("no such team robot")?;
        let from = g.world_to_cell(pose.position());
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

    /// Replaces the team's commands of the robots under operator control: a teleoperation
    /// command until it lapses; a path followed from the robot's own pose estimate, with the
    /// team's recovery after a bump.
    fn drive_overrides(&mut self, live: &mut LiveMission<'_, '_>) {
        let dt_s = live.evaluator().simulation().config().dt_s;
        for k in 0..self.overrides.len() {
            let Some(id) = live.team_robot(k) else {
                continue;
            };
            let command = match &mut self.overrides[k] {
                None => continue,
                Some(Override::Teleop { velocity, until }) => {
                    if Instant::now() >= *until {
                        self.overrides[k] = None;
                        continue;
                    }
                    *velocity
                }
                Some(Override::Path { follower, recovery }) => {
                    let truth = live.evaluator();
                    let body = truth.robot(id);
                    let Some(pose) = live.team().pose(k) else {
                        continue;
                    };
                    if follower.is_done(pose) {
                        self.overrides[k] = None;
                        continue;
                    }
                    recovery.record(body.last_motion(), dt_s);
                    match recovery.step(self.sim_s, body.in_contact()) {
                        RecoveryStep::Escape(v) => v,
                        RecoveryStep::Ended | RecoveryStep::Free => {
                            follower.command(pose, &body.spec)
                        }
                    }
                }
            };
            live.override_team(k, command);
        }
    }

    fn drain_commands(&mut self, live: &mut LiveMission<'_, '_>) {
        while let Ok((message, reply)) = self.commands.try_recv() {
            let result = self.apply(message, live);
            let _ = reply.send(result);
        }
    }

    /// Waits until simulated time `sim_s` is due, carrying out commands and publishing frames
    /// meanwhile; `false` when the console is stopping.
    fn pace(&mut self, live: &mut LiveMission<'_, '_>) -> bool {
        loop {
            self.drain_commands(live);
            if self.shared.clock.is_stopping() {
                return false;
            }
            if self.observed.frame_due() {
                self.observed.observe(live, &self.overrides, &self.shared);
                let measured = self.pacer.measured(self.sim_s);
                self.observed
                    .publish(&self.shared, self.sim_s, &self.pacer, measured);
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

    /// After the mission ended (`finish`): the last frame stays on show, commands other than
    /// the clock's are refused, until the console stops.
    pub(crate) fn after_mission(&mut self, finish: &str) {
        self.observed.finish = Some(finish.into());
        for o in &mut self.overrides {
            *o = None;
        }
        while !self.shared.clock.is_stopping() {
            while let Ok((message, reply)) = self.commands.try_recv() {
                let result = self
                    .clock_command(&message)
                    .unwrap_or_else(|| Err(format!("the mission has ended ({finish})")));
                let _ = reply.send(result);
            }
            if self.observed.frame_due() {
                let measured = self.pacer.measured(self.sim_s);
                self.observed
                    .publish(&self.shared, self.sim_s, &self.pacer, measured);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl MissionHook for ConsoleHook {
    fn after_decide(&mut self, live: &mut LiveMission<'_, '_>) -> bool {
        self.sim_s = live.time_s();
        if let Some(ready) = self.ready.take() {
            self.overrides = (0..live.team_len()).map(|_| None).collect();
            self.observed.ids = console_ids(live);
            // The first frame is out before the console serves anyone.
            self.observed.observe(live, &self.overrides, &self.shared);
            self.observed
                .publish(&self.shared, self.sim_s, &self.pacer, 0.0);
            let _ = ready.send(Ok(()));
        }
        self.shared.clock.advance_to(self.sim_s);
        self.shared
            .steps
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let go_on = self.pace(live);
        self.drive_overrides(live);
        go_on
    }
}

//! Paper 000's robot as a controller on the shared simulator ([`usar_sim::host`]): the learned
//! MAXQ policy chooses each primitive ([`GreedyStepper`]), the robot drives it on the
//! continuous simulator over as many steps as it takes, and its [`RescueAgent`] is fed by its
//! own sensors — the depth array D_xy (classified by [`RubbleClassifier`]), the infrared ring,
//! the thermal camera and the attitude — through the host's [`FleetIo`]. It never sees the
//! scene.
//!
//! The robot searches a **zone**: a grid of cells (paper 000's 0.914 m) it is given, as an
//! operator would mark a part of a floor. It keeps inside it.
//!
//! Hand-offs go to whoever answers [`RescueController::take_question`]: an uncertain victim
//! (HC₂: tag or reject) or a stuck robot (HC₃: one driving command per question, until it is
//! free). Until the answer arrives the robot waits, stopped; an operator busy elsewhere costs
//! it time.
//!
//! A primitive on the continuous robot: F and B drive to the centre of the next cell along the
//! heading (B in reverse); a contact (the bumper) makes it a collision, no arrival within
//! [`MOVE_TIMEOUT_FACTOR`] times the nominal time a slip; after either the robot drives back to
//! the centre of its cell; either way it then turns to its cell heading again. A rotation turns
//! in place to the next quarter heading; one that does not get there in time did not take
//! effect (a slip, as paper 000 calls commands that do not: two in a row and the robot is
//! stuck), and the robot turns back. Driving into
//! a cell the robot's map holds a possible victim in, or out of the zone, is refused like a
//! collision (the robot stops itself).

use crate::agent::{Begun, CellReading, HeatReading, Move, RescueAgent};
use crate::domain::{DomainConfig, VictimMark};
use crate::exploration::{Direction, ExplorationWeights};
use crate::hierarchy::{self, RescueHierarchy};
use crate::operator::{NavigationRequest, VictimDecision};
use crate::perception::{INFRARED_NEIGHBOURS, RubbleClassifier};
use crate::state::RescueState;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::Arc;
use usar_maxq::{Delegation, GreedyStepper, MaxqQ, Next};
use usar_sim::host::{Controller, FleetIo};
use usar_sim::sensors::DetectionId;
use usar_sim::{CellAction, CellOutcome, Velocity};
use usar_world::cellview::{CellClass, CellViewParams};
use usar_world::{Cell, GridGeometry, Point2, Pose2, Rect};

/// A move that has not arrived after this many times its nominal time slipped.
pub const MOVE_TIMEOUT_FACTOR: f64 = 3.0;
/// A position this close to its goal has arrived, metres.
const ARRIVED_M: f64 = 0.08;
/// A heading this close to its goal has arrived, radians (2°).
const ALIGNED_RAD: f64 = 0.035;
/// Points this close to a cell's border are left out of its plane fit, metres: half the
/// 5 cm grid of the generated scenes (the cell-physics runs use half the scene's own grid).
const DEPTH_MARGIN_M: f64 = 0.025;

/// A question for the operator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Question {
    /// HC₂: is this a victim? The reading's number lets whoever looks at the camera image
    /// (the simulated operator: the evaluator) know what it shows.
    Victim {
        /// The thermal reading that made it a possible victim.
        source: DetectionId,
        /// p = f(h, s) and s, as the robot measured them.
        probability: f64,
        size_m2: f64,
        /// Where the warm region is, in the world.
        at: Point2,
    },
    /// HC₃: drive me one command. `request.camera` is what the robot's cameras show of its
    /// four neighbours, which only the one looking can fill in; `neighbours_at` are their
    /// centres in the world.
    Drive {
        request: NavigationRequest,
        neighbours_at: [Point2; 4],
    },
}

/// The operator's answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Answer {
    Victim(VictimDecision),
    Drive(CellAction),
}

/// Where a hand-off stands.
#[derive(Clone, Copy, Debug, PartialEq)]
enum HandOff {
    None,
    /// Asked, not yet collected by the operator's side.
    Posted(Question),
    /// Collected; the answer is awaited.
    Waiting,
    Answered(Answer),
}

/// A primitive being driven.
#[derive(Clone, Copy, Debug)]
struct Motion {
    m: Move,
    /// The cell's centre the robot started from, and where it goes.
    from: Point2,
    goal: Point2,
    goal_theta: f64,
    /// The cell heading it started with.
    from_theta: f64,
    /// When the phase started.
    started_s: f64,
    phase: Phase,
}

/// The phases of a primitive on the continuous robot.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Toward the goal (a cell's centre, or a heading).
    Going,
    /// Back to the cell's centre it started from, after this outcome.
    Returning(CellOutcome),
    /// Turning to the cell's heading again, with this outcome.
    Aligning(CellOutcome),
    Done(CellOutcome),
}

/// A possible victim tagged.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Tag {
    pub source: DetectionId,
    pub time_s: f64,
    pub by_operator: bool,
}

/// What the rescue robot did, as it knows it.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct RescueLog {
    /// Primitives the policy chose (navigation, Tag, Reject, Exit).
    pub primitives: u64,
    /// Table I's rewards the robot can score itself (all but those of its tags).
    pub reward: f64,
    /// Hand-offs asked: uncertain victims and stuck.
    pub handoffs_victim: u32,
    pub handoffs_stuck: u32,
    /// Questions answered by the operator.
    pub answers: u32,
    /// Seconds spent stopped, waiting for an answer.
    pub waiting_s: f64,
    pub collisions: u32,
    /// Whether the policy ended the search (Exit, or its root subtask over).
    pub finished: bool,
}

/// See the [module documentation](self). It drives one robot: the first of its fleet.
pub struct RescueController {
    zone: GridGeometry,
    weights: ExplorationWeights,
    config: DomainConfig,
    policy: Arc<MaxqQ>,
    hierarchy: RescueHierarchy,
    stepper: GreedyStepper<RescueState>,
    params: CellViewParams,
    /// Set up at the first step, from the first readings.
    mind: Option<(RescueAgent<DetectionId>, RubbleClassifier)>,
    motion: Option<Motion>,
    handoff: HandOff,
    /// What it tagged: the reading that made it a possible victim, when, and whether the
    /// operator decided (HC₂) rather than the robot (p above the tag threshold).
    pub tags: Vec<Tag>,
    pub log: RescueLog,
}

impl RescueController {
    /// A robot searching `zone` (cells of paper 000's size or any) with `policy`, at most
    /// `max_primitives` of them.
    pub fn new(
        zone: GridGeometry,
        policy: Arc<MaxqQ>,
        weights: ExplorationWeights,
        config: DomainConfig,
        max_primitives: u64,
    ) -> Self {
        Self {
            zone,
            weights,
            config,
            policy,
            hierarchy: RescueHierarchy::new(),
            stepper: GreedyStepper::new(max_primitives),
            params: CellViewParams::default(),
            mind: None,
            motion: None,
            handoff: HandOff::None,
            tags: Vec::new(),
            log: RescueLog::default(),
        }
    }

    /// The robot's mind, once it has started.
    pub fn agent(&self) -> Option<&RescueAgent<DetectionId>> {
        self.mind.as_ref().map(|(a, _)| a)
    }

    /// The possible victims it met: the reading that made each one, and what became of it.
    pub fn sightings(&self) -> Vec<(DetectionId, VictimMark)> {
        self.agent()
            .map_or_else(Vec::new, |a| a.victim_sources().collect())
    }

    /// The zone's cells.
    pub fn zone(&self) -> &GridGeometry {
        &self.zone
    }

    /// A question for the operator, if one is waiting to be collected.
    pub fn take_question(&mut self) -> Option<Question> {
        match self.handoff {
            HandOff::Posted(q) => {
                self.handoff = HandOff::Waiting;
                Some(q)
            }
            _ => None,
        }
    }

    /// The operator's answer to the question collected last.
    pub fn answer(&mut self, answer: Answer) {
        if self.handoff == HandOff::Waiting {
            self.handoff = HandOff::Answered(answer);
            self.log.answers += 1;
        }
    }

    /// The pose the robot believes: the localization oracle's, else its odometry.
    fn pose(io: &FleetIo<'_>) -> Pose2 {
        io.true_pose(0).unwrap_or_else(|| io.odometry(0).estimate)
    }

    fn start(&mut self, io: &mut FleetIo<'_>) -> bool {
        let pose = Self::pose(io);
        let cell = self.zone.world_to_cell(pose.position());
        if !self.zone.contains(cell) {
            return false;
        }
        let quarter = (pose.theta / FRAC_PI_2).round() as i64;
        let image = io.depth(0);
        let floor_m = image.sensor_z_m - io.spec(0).depth.mount_height_m;
        let classifier = RubbleClassifier {
            params: self.params,
            reference_floor_m: floor_m,
            margin_m: DEPTH_MARGIN_M,
            max_range_m: io.spec(0).depth.max_range_m,
        };
        let mut agent = RescueAgent::new(
            self.zone.width as i32,
            self.zone.height as i32,
            (cell, quarter.rem_euclid(4) as u8),
            self.weights.clone(),
            self.config.clone(),
            CellClass::Open,
        );
        let heat = self.heat(io);
        let front = self.front(&agent, &classifier, io);
        agent.start(CellReading {
            front,
            infrared: self.infrared(io),
            heat: &heat,
        });
        agent.take_handoffs_asked();
        self.mind = Some((agent, classifier));
        true
    }

    /// The class D_xy gives the cell ahead (`None`: it lies outside the zone).
    fn front(
        &self,
        agent: &RescueAgent<DetectionId>,
        classifier: &RubbleClassifier,
        io: &mut FleetIo<'_>,
    ) -> Option<CellClass> {
        let (dc, dr) = Direction::from_index(usize::from(agent.robot.heading)).step();
        let ahead = Cell::new(agent.robot.cell.col + dc, agent.robot.cell.row + dr);
        if !self.zone.contains(ahead) {
            return None;
        }
        let image = io.depth(0);
        let floor_m = image.sensor_z_m - io.spec(0).depth.mount_height_m;
        let centre = self.zone.cell_center(ahead);
        let half = 0.5 * self.zone.resolution_m;
        let rect = Rect::new(
            centre.x - half,
            centre.y - half,
            centre.x + half,
            centre.y + half,
        );
        Some(classifier.classify(&image, image.pose, floor_m, rect, centre))
    }

    /// Infrared hits closer than a cell, as a mask over [`INFRARED_NEIGHBOURS`].
    fn infrared(&self, io: &mut FleetIo<'_>) -> u8 {
        let reading = io.infrared(0);
        let mut mask = 0u8;
        for (k, range) in reading
            .ranges_m
            .iter()
            .enumerate()
            .take(INFRARED_NEIGHBOURS.len())
        {
            if range.is_some_and(|d| d < self.zone.resolution_m) {
                mask |= 1 << k;
            }
        }
        mask
    }

    /// The thermal camera's warm regions inside the zone.
    fn heat(&self, io: &mut FleetIo<'_>) -> Vec<HeatReading<DetectionId>> {
        let pose = Self::pose(io);
        io.thermal(0)
            .into_iter()
            .filter_map(|t| {
                let at = pose
                    .position()
                    .offset(pose.theta + t.bearing_rad, t.range_m);
                let c = self.zone.world_to_cell(at);
                self.zone.contains(c).then_some(HeatReading {
                    cell: (c.col, c.row),
                    human_signature: t.human_signature,
                    size_m2: t.size_m2,
                    source: t.id,
                })
            })
            .collect()
    }

    /// Begins a navigation primitive: a motion, or a refusal (into a possible victim or out of
    /// the zone) finished at once.
    fn begin_motion(&mut self, m: Move, io: &mut FleetIo<'_>) {
        let Some((agent, _)) = &self.mind else { return };
        let robot = agent.robot;
        let from = self.zone.cell_center(robot.cell);
        let theta = f64::from(robot.heading) * FRAC_PI_2;
        let (goal, goal_theta) = match m.action {
            CellAction::RotateLeft => (from, theta + FRAC_PI_2),
            CellAction::RotateRight => (from, theta - FRAC_PI_2),
            _ => {
                let target = robot.move_target(m.action).unwrap_or(robot.cell);
                let refused = !self.zone.contains(target)
                    || agent.map.get(target.col, target.row) == crate::cell_map::MapCell::Victim;
                if refused {
                    self.finish_motion(m, CellOutcome::Collided, io);
                    return;
                }
                (self.zone.cell_center(target), theta)
            }
        };
        self.motion = Some(Motion {
            m,
            from,
            goal,
            goal_theta,
            from_theta: theta,
            started_s: io.time_s(),
            phase: Phase::Going,
        });
    }

    /// The robot's own outcome, then what its sensors read where it ended.
    fn finish_motion(&mut self, m: Move, outcome: CellOutcome, io: &mut FleetIo<'_>) {
        let heat = self.heat(io);
        let Some((mut agent, classifier)) = self.mind.take() else {
            return;
        };
        match (outcome, m.action) {
            (CellOutcome::Moved, a) => {
                if let Some(t) = agent.robot.move_target(a) {
                    agent.robot.cell = t;
                }
            }
            (CellOutcome::Rotated, CellAction::RotateLeft) => {
                agent.robot.heading = (agent.robot.heading + 1) % 4;
            }
            (CellOutcome::Rotated, _) => agent.robot.heading = (agent.robot.heading + 3) % 4,
            (CellOutcome::Collided, _) => self.log.collisions += 1,
            _ => {}
        }
        let felt = if io.attitude(0).inclination_rad() > self.params.open_max_slope_rad {
            CellClass::Climbable
        } else {
            CellClass::Open
        };
        let front = self.front(&agent, &classifier, io);
        let reading = CellReading {
            front,
            infrared: self.infrared(io),
            heat: &heat,
        };
        self.log.reward += agent.finish(m, outcome, felt, reading);
        self.mind = Some((agent, classifier));
        self.sync_log();
    }

    /// The log's counts from the robot's mind.
    fn sync_log(&mut self) {
        if let Some((agent, _)) = &mut self.mind {
            // The operator's time is the host's clock here, not a charge.
            agent.take_handoffs_asked();
            self.log.handoffs_victim = agent.stats.handoffs_victim;
            self.log.handoffs_stuck = agent.stats.handoffs_stuck;
            self.log.finished |= agent.is_done();
        }
    }

    /// One control step of the primitive being driven: its command, or its end.
    fn drive(&mut self, io: &mut FleetIo<'_>) {
        let Some(mut motion) = self.motion else {
            return;
        };
        let pose = Self::pose(io);
        let spec = io.spec(0);
        let (v_max, w_max) = (spec.max_linear_mps, spec.max_angular_radps);
        let elapsed = io.time_s() - motion.started_s;
        let nominal = self.zone.resolution_m / v_max.max(1e-3) + FRAC_PI_2 / w_max.max(1e-3);
        let timed_out = elapsed > MOVE_TIMEOUT_FACTOR * nominal;
        let heading_err = wrap(motion.goal_theta - pose.theta);
        let rotation = matches!(
            motion.m.action,
            CellAction::RotateLeft | CellAction::RotateRight
        );
        // The phase's end, if it ended: the next phase, or the primitive's outcome.
        let next = match motion.phase {
            Phase::Going if rotation => {
                if heading_err.abs() < ALIGNED_RAD {
                    Some(Phase::Done(CellOutcome::Rotated))
                } else if timed_out {
                    // A turn its body cannot make did not take effect, like a slip: back to
                    // where it faced before.
                    motion.goal_theta = motion.from_theta;
                    Some(Phase::Aligning(CellOutcome::Slipped))
                } else {
                    None
                }
            }
            Phase::Going if pose.position().distance(motion.goal) < ARRIVED_M => {
                Some(Phase::Aligning(CellOutcome::Moved))
            }
            Phase::Going if io.contact(0) => Some(Phase::Returning(CellOutcome::Collided)),
            Phase::Going if timed_out => Some(Phase::Returning(CellOutcome::Slipped)),
            Phase::Returning(outcome)
                if timed_out || pose.position().distance(motion.from) < ARRIVED_M =>
            {
                Some(Phase::Aligning(outcome))
            }
            Phase::Aligning(outcome) if heading_err.abs() < ALIGNED_RAD || timed_out => {
                Some(Phase::Done(outcome))
            }
            _ => None,
        };
        if let Some(phase) = next {
            io.command(0, Velocity::default());
            if let Phase::Done(outcome) = phase {
                self.motion = None;
                self.finish_motion(motion.m, outcome, io);
            } else {
                motion.phase = phase;
                motion.started_s = io.time_s();
                self.motion = Some(motion);
            }
            return;
        }
        let reverse = motion.m.action == CellAction::Backward;
        let command = match motion.phase {
            Phase::Going if rotation => velocity(0.0, (2.0 * heading_err).clamp(-w_max, w_max)),
            Phase::Going => toward(pose, motion.goal, reverse, v_max, w_max),
            Phase::Returning(_) => toward(pose, motion.from, !reverse, v_max, w_max),
            _ => velocity(0.0, (2.0 * heading_err).clamp(-w_max, w_max)),
        };
        io.command(0, command);
    }

    /// The operator's answer at hand-off node `node`, a question, or the learner's choice.
    fn delegate(
        agent: &mut RescueAgent<DetectionId>,
        handoff: &mut HandOff,
        zone: &GridGeometry,
        node: usize,
    ) -> Delegation {
        let question = match node {
            hierarchy::HC_SHARE => match agent.uncertain_victim() {
                Some(victim) => Question::Victim {
                    source: victim.source,
                    probability: victim.probability,
                    size_m2: victim.size_m2,
                    at: zone.cell_center(Cell::new(victim.cell.0, victim.cell.1)),
                },
                None => return Delegation::Learner,
            },
            hierarchy::HC_NAV => {
                let c = agent.robot.cell;
                let neighbours_at = Direction::ALL.map(|d| {
                    let (dc, dr) = d.step();
                    zone.cell_center(Cell::new(c.col + dc, c.row + dr))
                });
                Question::Drive {
                    request: agent.navigation_request([(CellClass::NonClimbable, false); 4]),
                    neighbours_at,
                }
            }
            _ => return Delegation::Learner,
        };
        match *handoff {
            HandOff::Answered(answer) => {
                *handoff = HandOff::None;
                agent.operator_takes_turn();
                Delegation::Child(match answer {
                    Answer::Victim(VictimDecision::Tag) => 0,
                    Answer::Victim(VictimDecision::Reject) => 1,
                    Answer::Drive(CellAction::Forward) => 0,
                    Answer::Drive(CellAction::Backward) => 1,
                    Answer::Drive(CellAction::RotateLeft) => 2,
                    Answer::Drive(CellAction::RotateRight) => 3,
                })
            }
            HandOff::None => {
                *handoff = HandOff::Posted(question);
                Delegation::Pending
            }
            HandOff::Posted(_) | HandOff::Waiting => Delegation::Pending,
        }
    }
}

impl Controller for RescueController {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        if io.is_empty() || !io.alive(0) || self.log.finished {
            return;
        }
        if self.mind.is_none() && !self.start(io) {
            // Not in its zone: nothing it may search.
            self.log.finished = true;
            return;
        }
        if self.motion.is_some() {
            self.drive(io);
            return;
        }
        let Some((agent, _)) = &mut self.mind else {
            return;
        };
        let s = agent.state();
        let (handoff, zone) = (&mut self.handoff, &self.zone);
        let mut answered = false;
        let next = self
            .stepper
            .next(&self.policy, &self.hierarchy, &s, s.done(), |node, _| {
                let d = Self::delegate(agent, handoff, zone, node);
                answered |= matches!(d, Delegation::Child(_));
                d
            });
        match next {
            Next::Act(a) => {
                self.log.primitives += 1;
                match agent.begin(a) {
                    Begun::Move(m) => self.begin_motion(m, io),
                    Begun::Done(r) => self.log.reward += r,
                    Begun::Tagged(source) => self.tags.extend(source.map(|source| Tag {
                        source,
                        time_s: io.time_s(),
                        by_operator: answered,
                    })),
                }
                self.sync_log();
            }
            Next::Wait => self.log.waiting_s += io.dt_s(),
            Next::Finished => self.log.finished = true,
        }
    }
}

/// A unicycle command toward `goal`, nose first or (`reverse`) tail first.
fn toward(pose: Pose2, goal: Point2, reverse: bool, v_max: f64, w_max: f64) -> Velocity {
    let (dx, dy) = (goal.x - pose.x, goal.y - pose.y);
    let distance = dx.hypot(dy);
    let facing = if reverse { pose.theta + PI } else { pose.theta };
    let err = wrap(dy.atan2(dx) - facing);
    let speed = (v_max * err.cos()).max(0.0).min(2.0 * distance);
    let v = if reverse { -speed } else { speed };
    velocity(v, (2.0 * err).clamp(-w_max, w_max))
}

fn velocity(linear_mps: f64, angular_radps: f64) -> Velocity {
    Velocity {
        linear_mps,
        angular_radps,
    }
}

/// An angle in (−π, π].
fn wrap(a: f64) -> f64 {
    let mut a = a % (2.0 * PI);
    if a <= -PI {
        a += 2.0 * PI;
    } else if a > PI {
        a -= 2.0 * PI;
    }
    a
}

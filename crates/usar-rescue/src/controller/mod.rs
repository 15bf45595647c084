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

mod motion;
mod senses;

use self::motion::Motion;
use self::senses::DEPTH_MARGIN_M;
use crate::agent::{Begun, CellReading, RescueAgent};
use crate::domain::DomainConfig;
use crate::exploration::{Direction, ExplorationWeights};
use crate::hierarchy::{self, RescueHierarchy};
use crate::operator::{NavigationRequest, VictimDecision};
use crate::perception::RubbleClassifier;
use crate::state::RescueState;
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;
use usar_maxq::{Delegation, GreedyStepper, MaxqQ, Next};
use usar_sim::CellAction;
use usar_sim::host::{Controller, FleetIo};
use usar_sim::sensors::DetectionId;
use usar_world::cellview::{CellClass, CellViewParams};
use usar_world::{Cell, GridGeometry, Point2};

/// A move that has not arrived after this many times its nominal time slipped.
pub const MOVE_TIMEOUT_FACTOR: f64 = 3.0;
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

    /// Replaces its exploration weights (paper 000 §V's w_l, w_p, w_q) while it runs: a person
    /// tuning it live at the console.
    pub fn set_exploration_weights(&mut self, weights: ExplorationWeights) {
        if let Some((agent, _)) = &mut self.mind {
            agent.set_exploration_weights(weights.clone());
        }
        self.weights = weights;
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
        self.mind = Some((agent, classifier));
        true
    }

    /// Notes an Exit in the log. (The hand-offs the mind counts for a charge of the operator's
    /// time are not drained: here the operator's time is the host's clock.)
    fn note_exit(&mut self) {
        self.log.finished |= self.agent().is_some_and(RescueAgent::is_done);
    }

    /// Hand-offs it asked for: uncertain victims (HC₂) and stuck (HC₃).
    pub fn handoffs(&self) -> (u32, u32) {
        self.agent().map_or((0, 0), |a| {
            (a.stats.handoffs_victim, a.stats.handoffs_stuck)
        })
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
                self.note_exit();
            }
            Next::Wait => self.log.waiting_s += io.dt_s(),
            Next::Finished => self.log.finished = true,
        }
    }
}

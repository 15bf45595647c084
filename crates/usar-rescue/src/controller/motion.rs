//! A primitive on the continuous robot, in phases: going (to the next cell's centre, or to the
//! next quarter heading), returning (to its cell's centre after a bump or a slip) and aligning
//! (to its cell heading), then done with the outcome the robot felt.

use super::{MOVE_TIMEOUT_FACTOR, RescueController};
use crate::agent::{CellReading, Move};
use std::f64::consts::{FRAC_PI_2, PI};
use usar_sim::host::FleetIo;
use usar_sim::{CellAction, CellOutcome, Velocity};
use usar_world::cellview::CellClass;
use usar_world::{Point2, Pose2};

/// A position this close to its goal has arrived, metres.
const ARRIVED_M: f64 = 0.08;
/// A heading this close to its goal has arrived, radians (2°).
const ALIGNED_RAD: f64 = 0.035;
/// A primitive being driven.
#[derive(Clone, Copy, Debug)]
pub(super) struct Motion {
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

impl RescueController {
    /// Begins a navigation primitive: a motion, or a refusal (into a possible victim or out of
    /// the zone) finished at once.
    pub(super) fn begin_motion(&mut self, m: Move, io: &mut FleetIo<'_>) {
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
    pub(super) fn finish_motion(&mut self, m: Move, outcome: CellOutcome, io: &mut FleetIo<'_>) {
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
        self.note_exit();
    }

    /// One control step of the primitive being driven: its command, or its end.
    pub(super) fn drive(&mut self, io: &mut FleetIo<'_>) {
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

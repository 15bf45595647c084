//! Following a planned path with a unicycle robot: pure pursuit towards a look-ahead point,
//! turning in place when the heading error is large.

use usar_sim::{RobotSpec, Velocity};
use usar_world::{Point2, Pose2, normalize_angle};

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

/// A recovery manoeuvre under way: the index into [`ESCAPES`] being tried and when it ends,
/// simulated seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Recovery {
    escape: usize,
    until_s: f64,
}

/// What recovery asks of a robot this step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RecoveryStep {
    /// Drive this escape manoeuvre.
    Escape(Velocity),
    /// The manoeuvre just ended: the robot is free to plan and drive again.
    Ended,
    /// No recovery: drive as planned.
    Free,
}

impl Recovery {
    /// Advances `state` at time `now_s` given whether the robot's last motion bumped: a bump
    /// starts the first escape, a bump during an escape moves on to the next one, and an escape
    /// ends after [`RECOVERY_S`].
    pub fn step(state: &mut Option<Recovery>, now_s: f64, in_contact: bool) -> RecoveryStep {
        let start = |escape: usize| Recovery {
            escape,
            until_s: now_s + RECOVERY_S,
        };
        match *state {
            Some(r) if now_s < r.until_s => {
                if in_contact {
                    // This manoeuvre bumps too: try the next one.
                    *state = Some(start((r.escape + 1) % ESCAPES.len()));
                }
                RecoveryStep::Escape(ESCAPES[state.map_or(r.escape, |r| r.escape)])
            }
            Some(_) => {
                *state = None;
                RecoveryStep::Ended
            }
            None if in_contact => {
                *state = Some(start(0));
                RecoveryStep::Escape(ESCAPES[0])
            }
            None => RecoveryStep::Free,
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct PathFollower {
    waypoints: Vec<Point2>,
    next: usize,
}

/// Distance ahead on the path that the robot steers towards, metres.
pub const LOOKAHEAD_M: f64 = 0.35;
/// The goal counts as reached within this distance, metres.
pub const GOAL_TOLERANCE_M: f64 = 0.25;
/// Heading error above which the robot turns in place, radians.
const TURN_IN_PLACE_RAD: f64 = 0.6;

impl PathFollower {
    pub fn new(waypoints: Vec<Point2>) -> Self {
        Self { waypoints, next: 0 }
    }

    pub fn is_empty(&self) -> bool {
        self.waypoints.is_empty()
    }

    pub fn goal(&self) -> Option<Point2> {
        self.waypoints.last().copied()
    }

    pub fn waypoints(&self) -> &[Point2] {
        &self.waypoints
    }

    /// Whether the robot at `pose` has reached the end of the path.
    pub fn is_done(&self, pose: Pose2) -> bool {
        self.goal()
            .is_none_or(|g| g.distance(pose.position()) <= GOAL_TOLERANCE_M)
    }

    /// The velocity command that follows the path from `pose`.
    pub fn command(&mut self, pose: Pose2, spec: &RobotSpec) -> Velocity {
        if self.is_done(pose) {
            return Velocity::default();
        }
        let here = pose.position();
        while self.next + 1 < self.waypoints.len()
            && self.waypoints[self.next].distance(here) < LOOKAHEAD_M
        {
            self.next += 1;
        }
        let target = self.waypoints[self.next];
        let error = normalize_angle(here.bearing_to(target) - pose.theta);
        let angular = (2.0 * error).clamp(-spec.max_angular_radps, spec.max_angular_radps);
        if error.abs() > TURN_IN_PLACE_RAD {
            return Velocity {
                linear_mps: 0.0,
                angular_radps: angular,
            };
        }
        let remaining = self.waypoints.last().map_or(0.0, |g| g.distance(here));
        let linear = (spec.max_linear_mps * error.cos().powi(2)).min(remaining.max(0.1));
        Velocity {
            linear_mps: linear,
            angular_radps: angular,
        }
    }
}

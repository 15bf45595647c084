//! Following a planned path with a unicycle robot: pure pursuit towards a look-ahead point,
//! turning in place when the heading error is large.

use usar_sim::{RobotSpec, Velocity};
use usar_world::{Point2, Pose2, normalize_angle};

/// Recovery after a collision (what a bumper-equipped base does): it tries these manoeuvres in
/// turn, each for [`RECOVERY_S`], moving on to the next as soon as one bumps too; then it plans
/// again. Backing up comes first; turning either way and creeping forward free a robot wedged
/// with a corner behind it.
pub const RECOVERY_S: f64 = 1.0;
pub const ESCAPES: [Velocity; 6] = [
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

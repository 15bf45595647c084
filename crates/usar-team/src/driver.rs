//! Following a planned path with a unicycle robot: pure pursuit towards a look-ahead point,
//! turning in place when the heading error is large.

use std::collections::VecDeque;
use usar_sim::{RobotSpec, Velocity};
use usar_world::{Point2, Pose2, normalize_angle};

/// How long a recovery retraces the robot's own latest motion, simulated seconds, at least.
const RETRACE_S: f64 = 1.0;
/// How far a recovery retraces, metres: a robot slower than 0.5 m/s retraces for longer.
const RETRACE_M: f64 = 0.5;
/// How many of its latest motions a robot remembers for retracing (30 s at the 0.1 s step).
const TRAIL_STEPS: usize = 300;
/// Repeated retraces double in length at most this many times (32 × the first: beyond the
/// remembered trail for any robot).
const MAX_DOUBLINGS: u32 = 5;
/// How long each of the [`ESCAPES`] is tried, simulated seconds, by a robot whose speeds do
/// not clip it; a slower robot keeps at each for longer (see [`Recovery::for_robot`]).
const ESCAPE_S: f64 = 1.0;
/// The manoeuvres tried in turn when retracing is impossible or bumps too (something moved in
/// behind the robot), each for [`ESCAPE_S`], moving on to the next as soon as one bumps: backing
/// up comes first; turning either way and creeping forward free a robot wedged with a corner
/// behind it.
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

/// Recovery after a collision (what a bumper-equipped base does). The robot first retraces its
/// own latest motion for up to [`RETRACE_S`], driving each remembered step backwards, newest
/// first: it came that way, so that way is free — even out of a gap between furniture too
/// narrow to turn in, where backing straight and turning on the spot both bump. Then it plans
/// again. Retracing continues, at the next bump, from where the last one stopped.
///
/// A bump before the robot drove [`RETRACE_M`] since the last recovery ended means that
/// recovery did not free it: the next retrace lasts twice as long, and so on up to the whole
/// remembered trail. Otherwise a slow robot wedged in a bend undoes, at each retrace, little
/// more than the turn on the spot that bumped it, and turns and bumps there for ever.
#[derive(Clone, Debug)]
pub struct Recovery {
    /// How long to retrace and to try each escape, seconds (from the robot's speeds).
    retrace_s: f64,
    escape_s: f64,
    /// Distance driven since the last manoeuvre ended, metres, and how many retraces in a row
    /// did not free the robot.
    driven_m: f64,
    repeats: u32,
    manoeuvre: Option<Manoeuvre>,
    /// The motions the robot made (`SimRobot::last_motion`), oldest first, without the
    /// retracing ones and without standstills.
    trail: VecDeque<Velocity>,
}

/// A recovery manoeuvre under way and when it ends, simulated seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Manoeuvre {
    Retrace { until_s: f64 },
    Escape { escape: usize, until_s: f64 },
}

/// What recovery asks of a robot this step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RecoveryStep {
    /// Drive this manoeuvre.
    Escape(Velocity),
    /// The manoeuvre just ended: the robot is free to plan and drive again.
    Ended,
    /// No recovery: drive as planned.
    Free,
}

impl Default for Recovery {
    /// Recovery for a robot that drives at least 0.5 m/s and turns at least 0.8 rad/s.
    fn default() -> Self {
        Self {
            retrace_s: RETRACE_S,
            escape_s: ESCAPE_S,
            driven_m: f64::INFINITY,
            repeats: 0,
            manoeuvre: None,
            trail: VecDeque::new(),
        }
    }
}

impl Recovery {
    /// Recovery for a robot with `spec`'s speeds: it retraces [`RETRACE_M`] at least, and
    /// tries each escape long enough to turn and move as far as [`ESCAPES`] do in
    /// [`ESCAPE_S`], however much its speed limits clip them. A slow robot retracing and
    /// escaping for the same time as a fast one undid too little of its motion and stayed
    /// wedged against the furniture it had bumped.
    pub fn for_robot(spec: &RobotSpec) -> Self {
        // How many times slower than commanded the robot drives the most clipped escape.
        let clip = ESCAPES
            .iter()
            .map(|e| {
                (e.linear_mps.abs() / spec.max_linear_mps)
                    .max(e.angular_radps.abs() / spec.max_angular_radps)
            })
            .fold(1.0, f64::max);
        Self {
            retrace_s: RETRACE_S.max(RETRACE_M / spec.max_linear_mps),
            escape_s: ESCAPE_S * clip,
            ..Self::default()
        }
    }

    /// Whether a manoeuvre is under way.
    pub fn is_active(&self) -> bool {
        self.manoeuvre.is_some()
    }

    /// Ends any manoeuvre (a failed robot, a robot an operator takes over).
    pub fn stop(&mut self) {
        self.manoeuvre = None;
    }

    /// Remembers the motion the robot made this step of `dt_s` seconds
    /// (`SimRobot::last_motion`); call it after every simulation step.
    pub fn record(&mut self, motion: Velocity, dt_s: f64) {
        let retracing = matches!(self.manoeuvre, Some(Manoeuvre::Retrace { .. }));
        if retracing || motion == Velocity::default() {
            return;
        }
        if self.manoeuvre.is_none() {
            self.driven_m += motion.linear_mps.abs() * dt_s;
        }
        if self.trail.len() == TRAIL_STEPS {
            self.trail.pop_front();
        }
        self.trail.push_back(motion);
    }

    /// Advances the recovery at time `now_s` given whether the robot's last motion bumped: a bump
    /// starts retracing (or the first escape when there is nothing to retrace), a bump while
    /// retracing starts the escapes, a bump during an escape moves on to the next one.
    pub fn step(&mut self, now_s: f64, in_contact: bool) -> RecoveryStep {
        let escape_s = self.escape_s;
        let escape = |escape: usize| {
            let until_s = now_s + escape_s;
            (Manoeuvre::Escape { escape, until_s }, ESCAPES[escape])
        };
        let (next, step) = match self.manoeuvre {
            None if !in_contact => return RecoveryStep::Free,
            None => match self.trail.pop_back() {
                Some(m) => {
                    self.repeats = if self.driven_m < RETRACE_M {
                        (self.repeats + 1).min(MAX_DOUBLINGS)
                    } else {
                        0
                    };
                    let retrace_s = self.retrace_s * f64::from(1u32 << self.repeats);
                    (
                        Manoeuvre::Retrace {
                            until_s: now_s + retrace_s,
                        },
                        -m,
                    )
                }
                None => escape(0),
            },
            Some(Manoeuvre::Retrace { until_s }) => {
                if in_contact {
                    escape(0)
                } else if now_s < until_s
                    && let Some(m) = self.trail.pop_back()
                {
                    (Manoeuvre::Retrace { until_s }, -m)
                } else {
                    return self.end();
                }
            }
            Some(Manoeuvre::Escape { escape: k, until_s }) if now_s < until_s => {
                if in_contact {
                    // This manoeuvre bumps too: try the next one.
                    escape((k + 1) % ESCAPES.len())
                } else {
                    (Manoeuvre::Escape { escape: k, until_s }, ESCAPES[k])
                }
            }
            Some(Manoeuvre::Escape { .. }) => return self.end(),
        };
        self.manoeuvre = Some(next);
        RecoveryStep::Escape(step)
    }

    fn end(&mut self) -> RecoveryStep {
        self.manoeuvre = None;
        self.driven_m = 0.0;
        RecoveryStep::Ended
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

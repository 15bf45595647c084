//! The stall watchdog: a robot that has not moved for a while is wedged (a doorway met at an
//! angle, clutter on a real floor). Turning on the spot is not progress: a robot wedged
//! between chairs turns back and forth for ever. It first tries escape manoeuvres; when
//! it stalls again on the same target it gives that target up, so that exploration always
//! ends. Paper 004 leaves such places to the operator (Table I's "operator intervention"
//! note); a robot on its own marks them [`crate::build::BLOCKED_FOR`] itself.

use std::f64::consts::PI;
use usar_sim::Velocity;
use usar_world::{Point2, Pose2};

/// A robot that moved less than this …
const STALL_DISTANCE_M: f64 = 0.2;
/// … for this long is stalled.
const STALL_AFTER_S: f64 = 20.0;
/// Escapes tried on one target before it is given up.
const ESCAPES_PER_TARGET: u32 = 2;
/// An escape: back up, then turn on the spot (alternating direction).
const ESCAPE_BACK: Velocity = Velocity {
    linear_mps: -0.15,
    angular_radps: 0.0,
};
const ESCAPE_BACK_S: f64 = 1.5;
const ESCAPE_TURN_RADPS: f64 = 0.6;
const ESCAPE_TURN_RAD: f64 = PI / 3.0;

/// What the explorer is trying to reach, for counting stalls per target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// Exploring this un-searched link.
    Link(u32),
    /// Driving back to this node.
    Node(u32),
    /// Backing away from where a branch ended.
    Backoff,
}

/// What to do about a stall.
#[derive(Clone, Debug, PartialEq)]
pub enum Remedy {
    /// Play these commands (one per simulation step), then carry on.
    Escape(Vec<Velocity>),
    /// Give the target up.
    GiveUp(Target),
}

#[derive(Clone, Debug)]
pub struct StallWatch {
    /// The control step, seconds (escapes are played one command per step).
    dt_s: f64,
    anchor: Point2,
    since_s: f64,
    target: Option<Target>,
    escapes: u32,
}

impl StallWatch {
    pub fn new(pose: Pose2, time_s: f64, dt_s: f64) -> Self {
        Self {
            dt_s,
            anchor: pose.position(),
            since_s: time_s,
            target: None,
            escapes: 0,
        }
    }

    /// Called once per control step with the robot's estimated pose; `None` while it makes
    /// progress (or has nothing to do).
    pub fn check(&mut self, pose: Pose2, time_s: f64, target: Option<Target>) -> Option<Remedy> {
        if target != self.target {
            self.target = target;
            self.escapes = 0;
            self.reset(pose, time_s);
        }
        if pose.position().distance(self.anchor) > STALL_DISTANCE_M {
            self.reset(pose, time_s);
            return None;
        }
        let target = target?;
        if time_s - self.since_s < STALL_AFTER_S {
            return None;
        }
        self.reset(pose, time_s);
        if self.escapes >= ESCAPES_PER_TARGET {
            self.escapes = 0;
            return Some(Remedy::GiveUp(target));
        }
        self.escapes += 1;
        let steps = |s: f64| (s / self.dt_s).round().max(1.0) as usize;
        let turn = Velocity {
            linear_mps: 0.0,
            angular_radps: if self.escapes % 2 == 1 {
                ESCAPE_TURN_RADPS
            } else {
                -ESCAPE_TURN_RADPS
            },
        };
        let mut commands = vec![ESCAPE_BACK; steps(ESCAPE_BACK_S)];
        commands.extend(std::iter::repeat_n(
            turn,
            steps(ESCAPE_TURN_RAD / ESCAPE_TURN_RADPS),
        ));
        Some(Remedy::Escape(commands))
    }

    fn reset(&mut self, pose: Pose2, time_s: f64) {
        self.anchor = pose.position();
        self.since_s = time_s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_robot_standing_still_escapes_twice_then_gives_up() {
        let p = Pose2::new(1.0, 2.0, 0.3);
        let mut w = StallWatch::new(p, 0.0, 0.1);
        let t = Some(Target::Link(7));
        let mut remedies = Vec::new();
        let mut time = 0.0;
        while remedies.len() < 3 {
            time += 0.1;
            if let Some(r) = w.check(p, time, t) {
                remedies.push((time, r));
            }
        }
        assert!(matches!(remedies[0].1, Remedy::Escape(_)));
        assert!(matches!(remedies[1].1, Remedy::Escape(_)));
        assert_eq!(remedies[2].1, Remedy::GiveUp(Target::Link(7)));
        assert!((remedies[0].0 - STALL_AFTER_S).abs() < 0.2);
    }

    #[test]
    fn progress_or_a_new_target_resets_the_watch() {
        let mut w = StallWatch::new(Pose2::new(0.0, 0.0, 0.0), 0.0, 0.1);
        let mut time = 0.0;
        for i in 0..1000 {
            time += 0.1;
            // Creeping forward 1 cm per step: never stalled.
            let p = Pose2::new(0.01 * f64::from(i), 0.0, 0.0);
            assert_eq!(w.check(p, time, Some(Target::Node(3))), None);
        }
        // Without a target nothing is ever done.
        for _ in 0..1000 {
            time += 0.1;
            assert_eq!(w.check(Pose2::new(0.0, 0.0, 0.0), time, None), None);
        }
    }
}

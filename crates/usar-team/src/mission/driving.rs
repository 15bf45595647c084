//! Driving: every robot's command for the coming step, and the rules the papers leave open —
//! when a robot with a target is stuck, the way back along its trajectory, and when it gives
//! way to a team mate.

use super::*;
use usar_sim::host::FleetIo;

impl TeamController {
    /// Who needs a new target after the last step: robots whose recovery ended, that reached
    /// their target (or, with none, stand where a merge may have opened something), made no
    /// progress towards it (it is blacklisted), or finished retracing.
    pub(super) fn needing_targets(&mut self, merged_now: bool) -> Vec<usize> {
        let now = self.now;
        let mut who = std::mem::take(&mut self.replan);
        let auctioned = self.config.exploration.strategy != Strategy::Nearest;
        let tuning = self.config.tuning;
        for (i, a) in self.agents.iter_mut().enumerate() {
            if !a.alive || a.recovery.is_active() || who.contains(&i) {
                continue;
            }
            let done = a.follower.is_done(a.pose);
            if a.target.is_some() && !done && now - a.progress_mark.1 >= tuning.stuck_window_s {
                let (mark, _) = a.progress_mark;
                let (stuck, turned) = stuck_check(&tuning, mark, a.pose, a.turned_in_place_rad);
                a.turned_in_place_rad = turned;
                if stuck {
                    a.blacklist
                        .push((a.target.expect("has target"), now + tuning.blacklist_s));
                    a.follower = PathFollower::default();
                    a.target = None;
                    who.push(i);
                    continue;
                }
                a.progress_mark = (a.pose, now);
            }
            if a.escaping {
                if done {
                    a.escaping = false;
                    who.push(i);
                }
                continue;
            }
            if done && let Some(reached) = a.target {
                // A frontier that did not resolve on arrival (it lies behind something the
                // laser cannot see past) is left alone for a while.
                a.blacklist
                    .push((reached, now + tuning.reached_blacklist_s));
                if auctioned {
                    self.visited
                        .push((reached, now + tuning.visited_blacklist_s));
                    self.arrivals.push((a.pose.position(), now));
                }
                a.target = None;
                who.push(i);
            } else if done && merged_now {
                who.push(i);
            }
        }
        who
    }

    /// The team believes the floor explored once nobody has had anything to do for
    /// [`Tuning::explored_after_s`].
    pub(super) fn check_explored(&mut self) {
        let now = self.now;
        let tuning = self.config.tuning;
        if self
            .agents
            .iter()
            .all(|a| a.target.is_none() && !a.escaping)
        {
            let since = *self.idle_since.get_or_insert(now);
            if now - since >= tuning.explored_after_s {
                self.explored = true;
            }
        } else {
            self.idle_since = None;
        }
    }

    /// Every robot's velocity for the coming step: a recovery manoeuvre, or its path, giving
    /// way to a team mate close ahead.
    pub(super) fn drive(&mut self, io: &mut FleetIo<'_>) {
        let now = self.now;
        let tuning = self.config.tuning;
        let poses: Vec<Pose2> = self.agents.iter().map(|a| a.pose).collect();
        for (k, a) in self.agents.iter_mut().enumerate() {
            let command = match a.recovery.step(now, io.contact(k)) {
                RecoveryStep::Escape(v) => v,
                RecoveryStep::Ended => {
                    a.recoveries += 1;
                    if a.recoveries >= tuning.max_recoveries
                        && let Some(t) = a.target.take()
                    {
                        a.blacklist.push((t, now + tuning.blacklist_s));
                        a.follower = PathFollower::default();
                    }
                    self.replan.push(k);
                    Velocity::default()
                }
                RecoveryStep::Free => {
                    let mut cmd = a.follower.command(a.pose, io.spec(k));
                    if cmd.linear_mps > 0.0
                        && poses[..k]
                            .iter()
                            .any(|o| gives_way(&tuning, a.pose, o.position()))
                    {
                        cmd.linear_mps = 0.0;
                    }
                    cmd
                }
            };
            io.command(k, command);
        }
    }
}

/// The progress check of a robot with a target, [`Tuning::stuck_window_s`] after its `mark`: whether it
/// is stuck, and its turning in place since it last moved (`turned_before` until this check).
/// Moving [`Tuning::stuck_distance_m`] is progress; so is turning [`Tuning::stuck_turn_rad`], up to
/// [`Tuning::max_turn_in_place_rad`] in all while the robot stays put.
pub(super) fn stuck_check(
    tuning: &Tuning,
    mark: Pose2,
    now: Pose2,
    turned_before: f64,
) -> (bool, f64) {
    if now.position().distance(mark.position()) >= tuning.stuck_distance_m {
        return (false, 0.0);
    }
    let turned = normalize_angle(now.theta - mark.theta).abs();
    let total = turned_before + turned;
    if turned < tuning.stuck_turn_rad || total > tuning.max_turn_in_place_rad {
        (true, 0.0)
    } else {
        (false, total)
    }
}

/// The way back along a trajectory: its points from the latest backwards, until [`Tuning::retrace_m`]
/// away from `here` along the way (empty when there is no way back).
pub(super) fn retrace(tuning: &Tuning, trajectory: &[Point2], here: Point2) -> Vec<Point2> {
    let mut out = Vec::new();
    let mut length = 0.0;
    let mut last = here;
    for &p in trajectory.iter().rev() {
        if p.distance(here) < 0.2 && out.is_empty() {
            continue;
        }
        length += last.distance(p);
        out.push(p);
        last = p;
        if length >= tuning.retrace_m {
            break;
        }
    }
    if last.distance(here) < 1.0 {
        out.clear();
    }
    out
}

/// Whether a robot at `pose` must give way to a robot at `other` (close, ahead of it).
pub(super) fn gives_way(tuning: &Tuning, pose: usar_world::Pose2, other: Point2) -> bool {
    let here = pose.position();
    here.distance(other) < tuning.yield_distance_m
        && usar_world::normalize_angle(here.bearing_to(other) - pose.theta).abs()
            < tuning.yield_half_angle_rad
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turning_round_in_place_is_progress_and_spinning_on_the_spot_is_not() {
        let at = |x: f64, theta: f64| Pose2::new(x, 0.0, theta);
        // Standing still: stuck.
        assert_eq!(
            stuck_check(&Tuning::default(), at(0.0, 0.0), at(0.05, 0.1), 0.0),
            (true, 0.0)
        );
        // Driving: progress, and the turning count starts again.
        assert_eq!(
            stuck_check(&Tuning::default(), at(0.0, 0.0), at(0.5, 0.0), 3.0),
            (false, 0.0)
        );
        // Turning round at 0.36 rad/s, 1.44 rad a window: progress for the ~9 s it takes.
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 0.0), at(0.0, 1.44), 0.0);
        assert!(!stuck);
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 1.44), at(0.0, 2.88), turned);
        assert!(!stuck && (turned - 2.88).abs() < 1e-9);
        // Spinning on: stuck once the turning passes a full turn.
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 2.88), at(0.0, 4.32), turned);
        assert!(!stuck);
        let (stuck, turned) = stuck_check(&Tuning::default(), at(0.0, 4.32), at(0.0, 5.76), turned);
        assert!(!stuck && turned < std::f64::consts::TAU);
        assert_eq!(
            stuck_check(&Tuning::default(), at(0.0, 5.76), at(0.0, 7.2), turned),
            (true, 0.0)
        );
    }
}

//! The mission loop: robots scan, the base station merges, allocation runs on its period and on
//! arrival, robots drive their paths, get unstuck, give way to each other, and a live hook may
//! steer them.

use super::*;

impl TeamMission {
    /// [`TeamMission::run`] with a live controller beside it (see [`MissionHook`]).
    pub fn run_live(
        mut self,
        mut on_progress: impl FnMut(f64),
        hook: &mut dyn MissionHook,
    ) -> TeamOutcome {
        let dt = self.config.sim.dt_s;
        let steps = (self.config.duration_s / dt).round() as u64;
        self.scan_all();
        self.merge();
        self.read_thermal();
        self.sample();
        let everyone: Vec<usize> = (0..self.agents.len()).collect();
        // Nothing assigned yet ends the mission only by the idle rule below: the robots' first
        // targets may have no path on the map (the coarser bid grid joins more), and the next
        // auction offers them others.
        self.assign(&everyone);
        let mut finish = Finish::TimeLimit;
        let mut step = 0u64;
        let mut idle_since: Option<f64> = None;
        while finish == Finish::TimeLimit && step < steps {
            step += 1;
            let now = self.sim.time_s();
            for f in &self.config.failures {
                let id = self.agents[f.robot].id;
                if f.at_s <= now && !self.sim.robot(id).failed {
                    self.sim.fail_robot(id);
                    let a = &mut self.agents[f.robot];
                    a.target = None;
                    a.follower = PathFollower::default();
                    a.escaping = false;
                    a.recovery.stop();
                }
            }
            let mut replan = Vec::new();
            let commands: Vec<Velocity> = self
                .agents
                .iter_mut()
                .enumerate()
                .map(|(i, a)| {
                    let r = self.sim.robot(a.id);
                    match a.recovery.step(now, r.in_contact()) {
                        RecoveryStep::Escape(v) => v,
                        RecoveryStep::Ended => {
                            a.recoveries += 1;
                            if a.recoveries >= self.config.tuning.max_recoveries
                                && let Some(t) = a.target.take()
                            {
                                a.blacklist.push((t, now + self.config.tuning.blacklist_s));
                                a.follower = PathFollower::default();
                            }
                            replan.push(i);
                            Velocity::default()
                        }
                        RecoveryStep::Free => {
                            let mut cmd = a.follower.command(r.pose, &r.spec);
                            if cmd.linear_mps > 0.0
                                && self.sim.robots()[..i].iter().any(|o| {
                                    gives_way(&self.config.tuning, r.pose, o.pose.position())
                                })
                            {
                                cmd.linear_mps = 0.0;
                            }
                            cmd
                        }
                    }
                })
                .enumerate()
                .map(|(i, planned)| hook.command(i, planned))
                .collect();
            self.sim.step(&commands);
            let dt_s = self.sim.config().dt_s;
            for a in &mut self.agents {
                a.recovery.record(self.sim.robot(a.id).last_motion(), dt_s);
            }
            if !hook.after_step(&mut self) {
                finish = Finish::Stopped;
                break;
            }
            let now = self.sim.time_s();
            if self.every(self.config.timing.scan_period_s, step) {
                self.scan_all();
            }
            if self.every(self.config.timing.thermal_period_s, step) {
                self.read_thermal();
            }
            let merged_now = self.every(self.config.timing.merge_period_s, step);
            if merged_now {
                self.merge();
            }
            if self.every(1.0, step) {
                for a in &mut self.agents {
                    a.trajectory.push(self.sim.robot(a.id).pose.position());
                }
            }
            // Who needs a new target: reached it, has none, made no progress, or recovered.
            let mut who = replan;
            let auctioned = self.config.exploration.strategy != Strategy::Nearest;
            for (i, a) in self.agents.iter_mut().enumerate() {
                let r = self.sim.robot(a.id);
                if r.failed || a.recovery.is_active() || who.contains(&i) {
                    continue;
                }
                let done = a.follower.is_done(r.pose);
                if a.target.is_some()
                    && !done
                    && now - a.progress_mark.1 >= self.config.tuning.stuck_window_s
                {
                    let (mark, _) = a.progress_mark;
                    let (stuck, turned) =
                        stuck_check(&self.config.tuning, mark, r.pose, a.turned_in_place_rad);
                    a.turned_in_place_rad = turned;
                    if stuck {
                        a.blacklist.push((
                            a.target.expect("has target"),
                            now + self.config.tuning.blacklist_s,
                        ));
                        a.follower = PathFollower::default();
                        a.target = None;
                        who.push(i);
                        continue;
                    }
                    a.progress_mark = (r.pose, now);
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
                        .push((reached, now + self.config.tuning.reached_blacklist_s));
                    if auctioned {
                        self.visited
                            .push((reached, now + self.config.tuning.visited_blacklist_s));
                        self.arrivals.push((r.pose.position(), now));
                    }
                    a.target = None;
                    who.push(i);
                } else if done && merged_now {
                    who.push(i);
                }
            }
            if self.every(self.config.timing.assignment_period_s, step) {
                who = everyone.clone();
            }
            if !who.is_empty() {
                self.assign(&who);
            }
            if self
                .agents
                .iter()
                .all(|a| a.target.is_none() && !a.escaping)
            {
                let since = *idle_since.get_or_insert(now);
                if now - since >= self.config.tuning.explored_after_s {
                    finish = Finish::Explored;
                }
            } else {
                idle_since = None;
            }
            if self.every(self.config.timing.sample_period_s, step) {
                self.sample();
                on_progress(now);
                if self.stalled() {
                    finish = Finish::Stalled;
                }
            }
            if let Some(target) = self.config.stop_at_coverage
                && merged_now
                && self.base.coverage.coverage() >= target
            {
                finish = Finish::CoverageTarget;
            }
            if self.config.stop_at_relevant.is_some()
                && merged_now
                && self.time_to_relevant_s.is_some()
            {
                finish = Finish::RelevantTarget;
            }
        }
        self.merge();
        if self
            .samples
            .last()
            .is_none_or(|s| s.time_s < self.sim.time_s())
        {
            self.sample();
        }
        on_progress(self.sim.time_s());
        self.outcome(finish)
    }
}

/// The progress check of a robot with a target, [`Tuning::stuck_window_s`] after its `mark`: whether it
/// is stuck, and its turning in place since it last moved (`turned_before` until this check).
/// Moving [`Tuning::stuck_distance_m`] is progress; so is turning [`Tuning::stuck_turn_rad`], up to
/// [`Tuning::max_turn_in_place_rad`] in all while the robot stays put.
fn stuck_check(tuning: &Tuning, mark: Pose2, now: Pose2, turned_before: f64) -> (bool, f64) {
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
fn gives_way(tuning: &Tuning, pose: usar_world::Pose2, other: Point2) -> bool {
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

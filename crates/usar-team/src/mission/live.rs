//! The mission loop: the team decides, the world moves; after every step the evaluator
//! follows the team's merged map and victim reports, samples the metrics and stops the run
//! when a stop rule of the experiment says so.

use super::controller::Finishing;
use super::*;

impl TeamMission {
    /// Runs the mission to its end; `on_progress` gets the simulated time now and then.
    pub fn run(self, on_progress: impl FnMut(f64)) -> TeamOutcome {
        self.run_observed(on_progress, |_| {})
    }

    /// [`TeamMission::run`], showing the mission to `observe` after every step's decisions
    /// (a recorder, a viewer): it sees, it does not steer.
    pub fn run_observed(
        mut self,
        mut on_progress: impl FnMut(f64),
        mut observe: impl FnMut(&TeamMission),
    ) -> TeamOutcome {
        let dt = self.config.sim.dt_s;
        let steps = (self.config.duration_s / dt).round() as u64;
        let mut finish = Finish::TimeLimit;
        let mut step = 0u64;
        loop {
            self.host.decide(self.fleet, &mut self.team);
            self.evaluate();
            observe(&self);
            let now = self.host.time_s();
            if step > 0 && self.team.explored() {
                finish = Finish::Explored;
            }
            if step == 0 || self.every(self.config.timing.sample_period_s, step) {
                self.sample(step == 0);
                if step > 0 {
                    on_progress(now);
                    if self.stalled() {
                        finish = Finish::Stalled;
                    }
                }
            }
            if step > 0 {
                let merged_now = self.every(self.config.timing.merge_period_s, step);
                if let Some(target) = self.config.stop_at_coverage
                    && merged_now
                    && self.eval.coverage() >= target
                {
                    finish = Finish::CoverageTarget;
                }
                if self.config.stop_at_relevant.is_some()
                    && merged_now
                    && self.eval.time_to_relevant_s().is_some()
                {
                    finish = Finish::RelevantTarget;
                }
            }
            if finish != Finish::TimeLimit || step >= steps {
                break;
            }
            self.host.advance();
            step += 1;
        }
        self.host.decide(self.fleet, &mut Finishing(&mut self.team));
        self.evaluate();
        if self
            .samples
            .last()
            .is_none_or(|s| s.time_s < self.host.time_s())
        {
            self.sample(false);
        }
        on_progress(self.host.time_s());
        self.outcome(finish)
    }
}

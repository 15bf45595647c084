//! Paper 002 runs as the `team run` command and the `team` campaign runner describe them: the
//! names of strategies, coordination methods, hypotheses and error models, turned into a
//! mission configuration.

use crate::coordination::Coordination;
use crate::criteria::Hypothesis;
use crate::room_candidates::CandidateGrouping;
use crate::semantic_map::LabelErrors;
use crate::{Exploration, Localization, Radio, RobotFailure, Semantics, Strategy, TeamConfig};

/// The robot of a team run when none is named: the wheeled robot at paper 002's pace
/// ([`usar_sim::RobotSpec::wheeled_paper_pace`]).
pub const DEFAULT_ROBOT: &str = "wheeled-paper-pace";

/// One paper-002 run, by name.
#[derive(Clone, Debug)]
pub struct TeamSetup<'a> {
    pub robots: usize,
    pub robot: &'a str,
    pub strategy: &'a str,
    pub coordination: &'a str,
    pub hypothesis: &'a str,
    pub minutes: f64,
    pub label_errors: &'a str,
    pub candidates: &'a str,
    /// `oracle` or `segmented` ([`Semantics`]).
    pub semantics: &'a str,
    /// `true` or `estimated` ([`Localization`]).
    pub localization: &'a str,
    pub stop_at_relevant: Option<f64>,
    pub merge_period_s: f64,
    pub radio: Radio,
    pub failures: Vec<RobotFailure>,
}

impl TeamSetup<'_> {
    /// The mission configuration; errors name the argument and what was expected.
    pub fn config(&self) -> Result<TeamConfig, String> {
        let strategy = Strategy::from_name(self.strategy).ok_or_else(|| {
            format!(
                "strategy: found {:?}, expected random, distance, d-mcdm, s-mcdm or nearest",
                self.strategy
            )
        })?;
        let coordination = Coordination::from_name(self.coordination).ok_or_else(|| {
            format!(
                "coordination: found {:?}, expected sr, mrv1 or mrv2",
                self.coordination
            )
        })?;
        let hypothesis = Hypothesis::named(self.hypothesis).ok_or_else(|| {
            format!(
                "hypothesis: found {:?}, expected big or small",
                self.hypothesis
            )
        })?;
        let candidates = CandidateGrouping::from_name(self.candidates).ok_or_else(|| {
            format!(
                "candidates: found {:?}, expected room or cluster",
                self.candidates
            )
        })?;
        let semantics = Semantics::parse(self.semantics).ok_or_else(|| {
            format!(
                "semantics: found {:?}, expected oracle or segmented",
                self.semantics
            )
        })?;
        let localization = Localization::parse(self.localization).ok_or_else(|| {
            format!(
                "localization: found {:?}, expected true or estimated",
                self.localization
            )
        })?;
        if !(self.minutes.is_finite() && self.minutes > 0.0) {
            return Err(format!(
                "minutes: found {}, expected a positive number",
                self.minutes
            ));
        }
        if !(self.merge_period_s.is_finite() && self.merge_period_s > 0.0) {
            return Err(format!(
                "merge period: found {} s, expected a positive number of seconds",
                self.merge_period_s
            ));
        }
        let robot = usar_sim::RobotSpec::load(self.robot).map_err(|e| e.to_string())?;
        let exploration = Exploration {
            strategy,
            coordination,
            hypothesis,
            label_errors: LabelErrors::parse(self.label_errors)?,
            candidates,
            ..Exploration::default()
        };
        let mut config = TeamConfig::paper_002(self.robots, self.minutes, exploration);
        config.robot = robot;
        config.stop_at_relevant = self.stop_at_relevant;
        config.timing.merge_period_s = self.merge_period_s;
        config.radio = self.radio.clone();
        config.failures = self.failures.clone();
        config.semantics = semantics;
        config.localization = localization;
        Ok(config)
    }
}

/// Reads `ROBOT@SECONDS`.
pub fn parse_failure(text: &str) -> Result<RobotFailure, String> {
    let bad = || format!("--fail: found {text:?}, expected ROBOT@SECONDS, e.g. 2@300");
    let (robot, at) = text.split_once('@').ok_or_else(bad)?;
    let robot = robot.trim().parse().map_err(|_| bad())?;
    let at_s: f64 = at.trim().parse().map_err(|_| bad())?;
    if !(at_s.is_finite() && at_s >= 0.0) {
        return Err(bad());
    }
    Ok(RobotFailure { robot, at_s })
}

//! Paper 002 runs as the `team run` command and the `team` campaign runner describe them: the
//! names of strategies, coordination methods, hypotheses and error models, turned into a
//! mission configuration.

use crate::coordination::Coordination;
use crate::criteria::Hypothesis;
use crate::room_candidates::CandidateGrouping;
use crate::semantic_map::{LabelErrors, LabelErrorsError};
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

/// Why a named setting of a team run was refused.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// A name that is not one of the setting's choices.
    #[error("{setting}: found {found:?}, expected {expected}")]
    Choice {
        setting: &'static str,
        found: String,
        expected: &'static str,
    },
    /// A number outside the setting's range.
    #[error("{setting}: found {found}, expected {expected}")]
    Range {
        setting: &'static str,
        found: String,
        expected: &'static str,
    },
    #[error(transparent)]
    LabelErrors(#[from] LabelErrorsError),
    #[error(transparent)]
    Robot(#[from] usar_sim::SimError),
}

/// The choice `found` of `setting` by `parse`, or the error naming the choices.
fn choose<T>(
    setting: &'static str,
    found: &str,
    expected: &'static str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<T, SetupError> {
    parse(found).ok_or_else(|| SetupError::Choice {
        setting,
        found: found.to_string(),
        expected,
    })
}

impl TeamSetup<'_> {
    /// The mission configuration; errors name the argument and what was expected.
    pub fn config(&self) -> Result<TeamConfig, SetupError> {
        let strategy = choose(
            "strategy",
            self.strategy,
            "random, distance, d-mcdm, s-mcdm or nearest",
            Strategy::from_name,
        )?;
        let coordination = choose(
            "coordination",
            self.coordination,
            "sr, mrv1 or mrv2",
            Coordination::from_name,
        )?;
        let hypothesis = choose(
            "hypothesis",
            self.hypothesis,
            "big or small",
            Hypothesis::named,
        )?;
        let candidates = choose(
            "candidates",
            self.candidates,
            "room or cluster",
            CandidateGrouping::from_name,
        )?;
        let semantics = choose(
            "semantics",
            self.semantics,
            "oracle or segmented",
            Semantics::parse,
        )?;
        let localization = choose(
            "localization",
            self.localization,
            "true or estimated",
            Localization::parse,
        )?;
        if !(self.minutes.is_finite() && self.minutes > 0.0) {
            return Err(SetupError::Range {
                setting: "minutes",
                found: self.minutes.to_string(),
                expected: "a positive number",
            });
        }
        if !(self.merge_period_s.is_finite() && self.merge_period_s > 0.0) {
            return Err(SetupError::Range {
                setting: "merge period",
                found: format!("{} s", self.merge_period_s),
                expected: "a positive number of seconds",
            });
        }
        let robot = usar_sim::RobotSpec::load(self.robot)?;
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
pub fn parse_failure(text: &str) -> Result<RobotFailure, SetupError> {
    let bad = || SetupError::Choice {
        setting: "--fail",
        found: text.to_string(),
        expected: "ROBOT@SECONDS, e.g. 2@300",
    };
    let (robot, at) = text.split_once('@').ok_or_else(bad)?;
    let robot = robot.trim().parse().map_err(|_| bad())?;
    let at_s: f64 = at.trim().parse().map_err(|_| bad())?;
    if !(at_s.is_finite() && at_s >= 0.0) {
        return Err(bad());
    }
    Ok(RobotFailure { robot, at_s })
}

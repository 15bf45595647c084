//! What the engine runs: a [`Runner`] names the factors it understands and the metrics it
//! reports, and turns one configuration and a seed into a [`RunOutput`]. Controllers (the
//! baseline explorer, MAXQ, the paper-002 team, BTM) each provide one; the engine knows none of
//! them.

use crate::design::{Config, Level};
use serde::Serialize;
use std::collections::BTreeMap;

/// What values a factor takes.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum FactorKind {
    /// An integer in [min, max].
    Int { min: i64, max: i64 },
    /// A number in [min, max] (integers are accepted).
    Float { min: f64, max: f64 },
    /// Text; one of `choices` when it is not empty (empty: any text, e.g. a file name).
    Text { choices: Vec<String> },
}

/// A factor a runner understands, with the value it takes when a campaign does not set it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FactorSpec {
    pub name: String,
    pub kind: FactorKind,
    pub default: Level,
    pub help: String,
}

impl FactorSpec {
    /// Checks a value against the kind; the error says what was expected.
    pub fn check(&self, value: &Level) -> Result<Level, String> {
        match (&self.kind, value) {
            (FactorKind::Int { min, max }, Level::Int(v)) if (min..=max).contains(&v) => {
                Ok(value.clone())
            }
            (FactorKind::Int { min, max }, _) => Err(format!("an integer in [{min}, {max}]")),
            (FactorKind::Float { min, max }, Level::Int(v))
                if (*min..=*max).contains(&(*v as f64)) =>
            {
                Ok(Level::Float(*v as f64))
            }
            (FactorKind::Float { min, max }, Level::Float(v)) if (*min..=*max).contains(v) => {
                Ok(value.clone())
            }
            (FactorKind::Float { min, max }, _) => Err(format!("a number in [{min}, {max}]")),
            (FactorKind::Text { choices }, Level::Text(t))
                if choices.is_empty() || choices.contains(t) =>
            {
                Ok(value.clone())
            }
            (FactorKind::Text { choices }, _) if choices.is_empty() => Err("text".into()),
            (FactorKind::Text { choices }, _) => Err(format!("one of {}", choices.join(", "))),
        }
    }
}

/// A metric a runner reports at the end of every run (and maybe over time).
impl FactorSpec {
    pub fn new(name: &str, kind: FactorKind, default: Level, help: &str) -> Self {
        Self {
            name: name.into(),
            kind,
            default,
            help: help.into(),
        }
    }

    /// A text factor taking one of `choices` (any text when empty).
    pub fn text(name: &str, choices: &[&str], default: &str, help: &str) -> Self {
        let choices = choices.iter().map(|c| c.to_string()).collect();
        Self::new(
            name,
            FactorKind::Text { choices },
            Level::Text(default.into()),
            help,
        )
    }

    /// An integer factor in `min..=max`.
    pub fn int(name: &str, (min, max): (i64, i64), default: i64, help: &str) -> Self {
        Self::new(
            name,
            FactorKind::Int { min, max },
            Level::Int(default),
            help,
        )
    }

    /// A real factor in `min..=max`.
    pub fn float(name: &str, (min, max): (f64, f64), default: f64, help: &str) -> Self {
        Self::new(
            name,
            FactorKind::Float { min, max },
            Level::Float(default),
            help,
        )
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MetricSpec {
    pub name: String,
    pub help: String,
}

impl MetricSpec {
    pub fn new(name: &str, help: &str) -> Self {
        Self {
            name: name.into(),
            help: help.into(),
        }
    }
}

/// One point of a run's series: the x value (time, episode) and the metrics at it.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SeriesPoint {
    pub x: f64,
    pub values: BTreeMap<String, f64>,
}

/// The result of one run: final metrics and series over time or episodes.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RunOutput {
    pub metrics: BTreeMap<String, f64>,
    pub series: Vec<SeriesPoint>,
}

/// Why a run could not be made: the user's configuration (exit code 2 at the command line), or
/// the run itself.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The configuration is the user's to fix: a scene file that does not exist, a value a
    /// factor does not accept, a policy file that cannot be read.
    #[error("{0}")]
    Input(String),
    /// The run failed on its own.
    #[error("{0}")]
    Failed(String),
}

impl RunError {
    /// Whether the user's configuration is at fault.
    pub fn is_input(&self) -> bool {
        matches!(self, RunError::Input(_))
    }
}

/// A controller the engine can run. A run must be a pure function of (configuration, seed),
/// whatever thread runs it.
pub trait Runner: Sync {
    /// The name campaign files give in `runner = "..."`.
    fn name(&self) -> &str;
    /// The factors it understands.
    fn factors(&self) -> Vec<FactorSpec>;
    /// The final metrics every run reports.
    fn metrics(&self) -> Vec<MetricSpec>;
    /// What the x of its series means (e.g. `time_s`, `episode`).
    fn series_x(&self) -> &str;
    /// Checks a complete configuration before anything runs (e.g. that a scene file exists).
    fn check(&self, _config: &Config) -> Result<(), RunError> {
        Ok(())
    }
    /// Runs one configuration with one seed.
    fn run(&self, config: &Config, seed: u64) -> Result<RunOutput, RunError>;
}

/// A runner that does nothing but echo its seed: for measuring the engine's own overhead and
/// for testing the engine. Factors `a` (integer) and `b` (text); metrics `seed` and `value`
/// (a deterministic function of the configuration and the seed), one series point.
pub struct NoopRunner;

impl Runner for NoopRunner {
    fn name(&self) -> &str {
        "noop"
    }

    fn factors(&self) -> Vec<FactorSpec> {
        vec![
            FactorSpec {
                name: "a".into(),
                kind: FactorKind::Int { min: 0, max: 1000 },
                default: Level::Int(0),
                help: "an integer".into(),
            },
            FactorSpec {
                name: "b".into(),
                kind: FactorKind::Text {
                    choices: vec!["x".into(), "y".into(), "z".into()],
                },
                default: Level::Text("x".into()),
                help: "a choice".into(),
            },
        ]
    }

    fn metrics(&self) -> Vec<MetricSpec> {
        vec![
            MetricSpec {
                name: "seed".into(),
                help: "the run's seed".into(),
            },
            MetricSpec {
                name: "value".into(),
                help: "a + (seed mod 7) / 10 + (b = y ? 1 : 0)".into(),
            },
        ]
    }

    fn series_x(&self) -> &str {
        "step"
    }

    fn run(&self, config: &Config, seed: u64) -> Result<RunOutput, RunError> {
        let a = config.int("a").unwrap_or(0) as f64;
        let b = f64::from(u8::from(config.text("b") == Some("y")));
        let value = a + (seed % 7) as f64 / 10.0 + b;
        Ok(RunOutput {
            metrics: BTreeMap::from([("seed".into(), seed as f64), ("value".into(), value)]),
            series: vec![SeriesPoint {
                x: 0.0,
                values: BTreeMap::from([("value".into(), value)]),
            }],
        })
    }
}

//! Campaign files and the full factorial designs they expand to.
//!
//! A campaign file (TOML, documented in `docs/campaign-format.md`) names a runner, its factors
//! with the levels to try (`[factors]`), settings held constant (`[fixed]`), the number of runs
//! per configuration and the base seed, and what the report shows (`[report]`). The design is
//! every combination of the factor levels — factors in alphabetical order, the last one varying
//! fastest — each run `runs` times with seeds `base_seed`, `base_seed + 1`, …: the same seeds in
//! every configuration, so runs that differ only in one factor can be paired.
//!
//! Run `id = config_index · runs + repetition` identifies a run in the result database; the
//! design's hash (of the runner, the configurations, `runs` and `base_seed`, not of the report
//! section or the name) tells whether a database belongs to a campaign.

use crate::error::{CampaignError, Result};
use crate::runner::Runner;
use crate::stats::Tails;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

/// One level of a factor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Level {
    Int(i64),
    Float(f64),
    Text(String),
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Level::Int(v) => write!(f, "{v}"),
            Level::Float(v) => write!(f, "{v}"),
            Level::Text(v) => write!(f, "{v}"),
        }
    }
}

impl Level {
    /// The value as a number, if it is one.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Level::Int(v) => Some(*v as f64),
            Level::Float(v) => Some(*v),
            Level::Text(_) => None,
        }
    }
}

/// A complete configuration: every factor the runner knows, with its value.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Config(pub BTreeMap<String, Level>);

impl Config {
    pub fn get(&self, name: &str) -> Option<&Level> {
        self.0.get(name)
    }

    pub fn int(&self, name: &str) -> Option<i64> {
        match self.0.get(name)? {
            Level::Int(v) => Some(*v),
            _ => None,
        }
    }

    pub fn float(&self, name: &str) -> Option<f64> {
        self.0.get(name)?.as_f64()
    }

    pub fn text(&self, name: &str) -> Option<&str> {
        match self.0.get(name)? {
            Level::Text(v) => Some(v),
            _ => None,
        }
    }

    /// `a=1, b=x` for messages.
    pub fn describe(&self, only: &[String]) -> String {
        self.0
            .iter()
            .filter(|(k, _)| only.is_empty() || only.contains(k))
            .map(|(k, v)| format!("{k}={v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Which test a comparison runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TestKind {
    /// One-way ANOVA over the factor's levels.
    Anova,
    /// Welch's t-test between two levels.
    Welch,
    /// Paired t-test between two levels; runs are paired by seed and the other factors.
    Paired,
}

/// A comparison the report computes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Comparison {
    pub metric: String,
    pub factor: String,
    pub test: TestKind,
    /// The levels compared (default: all levels of the factor; t-tests need exactly two).
    #[serde(default)]
    pub groups: Vec<Level>,
    /// The alternative of a t-test: `two-sided`, `greater` (first group greater), `less`.
    #[serde(default = "two_sided")]
    pub tails: Tails,
    /// Compare only the runs with these levels of other factors (e.g. one cell of a table).
    #[serde(default)]
    pub within: BTreeMap<String, Level>,
    /// Shown beside the result (e.g. what the paper found).
    #[serde(default)]
    pub note: String,
}

fn two_sided() -> Tails {
    Tails::TwoSided
}

/// What `usar campaign report` shows.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReportSpec {
    /// Factor whose levels are the table's rows (default: the first factor); `a+b` makes one
    /// row per combination of a's and b's levels.
    pub rows: Option<String>,
    /// Factor whose levels are the table's columns (default: none, one column); `a+b` as for
    /// rows.
    pub columns: Option<String>,
    /// Metrics tabulated (default: all of the runner's).
    #[serde(default)]
    pub metrics: Vec<String>,
    /// Series plotted over time/episodes with a mean ± sd band per row level.
    #[serde(default)]
    pub series: Vec<String>,
    #[serde(default)]
    pub compare: Vec<Comparison>,
}

/// A campaign file as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignFile {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Which runner runs it (e.g. `explore`).
    pub runner: String,
    /// Runs per configuration.
    pub runs: u32,
    #[serde(default = "one")]
    pub base_seed: u64,
    /// Factor name → the levels to try.
    #[serde(default)]
    pub factors: BTreeMap<String, Vec<Level>>,
    /// Factor name → the value held in every run.
    #[serde(default)]
    pub fixed: BTreeMap<String, Level>,
    #[serde(default)]
    pub report: ReportSpec,
}

fn one() -> u64 {
    1
}

/// One run of the design.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunSpec {
    pub id: u64,
    pub config_index: usize,
    pub repetition: u32,
    pub seed: u64,
}

/// A campaign checked against its runner and expanded.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    pub campaign: CampaignFile,
    /// Every configuration, in design order.
    pub configs: Vec<Config>,
    /// Hex FNV-1a hash identifying the design.
    pub hash: String,
}

/// The line (1-based) where `key` is first set in `text`, for messages.
fn line_of(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|l| {
            let l = l.trim_start();
            l.strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        })
        .map(|i| i + 1)
}

/// Whether a campaign name is one plain path component: ASCII letters, digits, `-`, `_` and
/// `.`, at most 100 characters, and not `.` or `..` — so `out/campaigns/NAME` stays inside
/// `out/campaigns`.
pub fn is_plain_name(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= 100
        && name != "."
        && name != ".."
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.'))
}

/// 64-bit FNV-1a.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

impl Design {
    /// Parses a campaign file's text; `source` names it in messages.
    pub fn parse(text: &str, source: &str, runner: &dyn Runner) -> Result<Self> {
        let campaign: CampaignFile =
            toml::from_str(text).map_err(|e| toml_error(text, source, &e))?;
        Self::new(campaign, source, text, runner)
    }

    /// Reads and parses a campaign file.
    pub fn read(
        path: &Path,
        runner_for: impl Fn(&str) -> Option<&'static dyn Runner>,
    ) -> Result<Self> {
        let source = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| CampaignError::Input(format!("{source}: cannot read: {e}")))?;
        let runner = runner_named(&text, &source, runner_for)?;
        Self::parse(&text, &source, runner)
    }

    /// Checks a campaign against its runner and expands it.
    pub fn new(
        campaign: CampaignFile,
        source: &str,
        text: &str,
        runner: &dyn Runner,
    ) -> Result<Self> {
        let bad = |key: &str, msg: String| {
            let at = line_of(text, key)
                .map(|l| format!(" line {l}:"))
                .unwrap_or_default();
            CampaignError::Input(format!("{source}:{at} {msg}"))
        };
        if !is_plain_name(&campaign.name) {
            return Err(bad(
                "name",
                format!(
                    "name = {:?}, expected a plain folder name (letters, digits, `-`, `_`, `.`; not `.` or `..`): results go to out/campaigns/NAME",
                    campaign.name
                ),
            ));
        }
        if campaign.runner != runner.name() {
            return Err(bad(
                "runner",
                format!("runner `{}`, expected `{}`", campaign.runner, runner.name()),
            ));
        }
        if campaign.runs == 0 {
            return Err(bad(
                "runs",
                "runs = 0, expected at least 1 run per configuration".into(),
            ));
        }
        let specs = runner.factors();
        let known = || {
            specs
                .iter()
                .map(|s| s.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let spec_of = |name: &str| {
            specs.iter().find(|s| s.name == name).ok_or_else(|| {
                bad(
                    name,
                    format!(
                        "unknown factor `{name}` for runner {}, expected one of {}",
                        runner.name(),
                        known()
                    ),
                )
            })
        };
        let mut base = BTreeMap::new();
        for spec in &specs {
            base.insert(spec.name.clone(), spec.default.clone());
        }
        for (name, value) in &campaign.fixed {
            let spec = spec_of(name)?;
            let v = spec
                .check(value)
                .map_err(|want| bad(name, format!("fixed `{name}` = {value}, expected {want}")))?;
            base.insert(name.clone(), v);
        }
        let mut levels: Vec<(String, Vec<Level>)> = Vec::new();
        for (name, values) in &campaign.factors {
            let spec = spec_of(name)?;
            if campaign.fixed.contains_key(name) {
                return Err(bad(
                    name,
                    format!("factor `{name}` is both varied and fixed"),
                ));
            }
            if values.is_empty() {
                return Err(bad(
                    name,
                    format!("factor `{name}` has no levels, expected a list of values"),
                ));
            }
            let mut checked = Vec::new();
            for v in values {
                let c = spec.check(v).map_err(|want| {
                    bad(name, format!("factor `{name}` level {v}, expected {want}"))
                })?;
                if checked.contains(&c) {
                    return Err(bad(name, format!("factor `{name}` lists level {v} twice")));
                }
                checked.push(c);
            }
            levels.push((name.clone(), checked));
        }
        // Full factorial, last factor fastest.
        let mut configs = vec![Config(base)];
        for (name, values) in &levels {
            configs = configs
                .into_iter()
                .flat_map(|c| {
                    values.iter().map(move |v| {
                        let mut c = c.clone();
                        c.0.insert(name.clone(), v.clone());
                        c
                    })
                })
                .collect();
        }
        for c in &configs {
            runner.check(c).map_err(|msg| {
                CampaignError::Input(format!(
                    "{source}: configuration {}: {msg}",
                    c.describe(&[])
                ))
            })?;
        }
        check_report(&campaign, &levels, runner, &bad)?;
        let identity = serde_json::json!({
            "runner": campaign.runner,
            "runs": campaign.runs,
            "base_seed": campaign.base_seed,
            "configs": configs,
        });
        let hash = format!("{:016x}", fnv1a(identity.to_string().as_bytes()));
        Ok(Design {
            campaign,
            configs,
            hash,
        })
    }

    /// Factors varied by the design, in design order, with their levels.
    pub fn factor_levels(&self) -> Vec<(String, Vec<Level>)> {
        self.campaign
            .factors
            .iter()
            .map(|(k, v)| {
                let levels = self.configs.iter().filter_map(|c| c.get(k).cloned()).fold(
                    Vec::<Level>::new(),
                    |mut acc, l| {
                        if !acc.contains(&l) {
                            acc.push(l);
                        }
                        acc
                    },
                );
                debug_assert_eq!(levels.len(), v.len());
                (k.clone(), levels)
            })
            .collect()
    }

    /// Number of runs in the design.
    pub fn len(&self) -> u64 {
        self.configs.len() as u64 * u64::from(self.campaign.runs)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The run with this id.
    pub fn run(&self, id: u64) -> RunSpec {
        let runs = u64::from(self.campaign.runs);
        let repetition = (id % runs) as u32;
        RunSpec {
            id,
            config_index: (id / runs) as usize,
            repetition,
            seed: self.campaign.base_seed + u64::from(repetition),
        }
    }

    /// Every run, in id order.
    pub fn runs(&self) -> impl Iterator<Item = RunSpec> + '_ {
        (0..self.len()).map(|id| self.run(id))
    }
}

/// Finds the runner a campaign text names.
pub fn runner_named(
    text: &str,
    source: &str,
    runner_for: impl Fn(&str) -> Option<&'static dyn Runner>,
) -> Result<&'static dyn Runner> {
    #[derive(Deserialize)]
    struct Head {
        runner: Option<String>,
    }
    // A file that is not TOML at all gets its syntax error here (a duplicate key used to read
    // as a missing runner); a wrong field is left to `Design::parse`, which names it.
    let table = toml::from_str::<toml::Table>(text).map_err(|e| toml_error(text, source, &e))?;
    let head: Head = table.try_into().unwrap_or(Head { runner: None });
    let name = head.runner.ok_or_else(|| {
        CampaignError::Input(format!(
            "{source}: missing `runner = \"...\"`, expected the name of a runner (e.g. explore)"
        ))
    })?;
    runner_for(&name).ok_or_else(|| {
        let at = line_of(text, "runner")
            .map(|l| format!(" line {l}:"))
            .unwrap_or_default();
        CampaignError::Input(format!("{source}:{at} unknown runner `{name}`"))
    })
}

/// A campaign text as a listing shows it (`usar campaign list`): parsed against its runner, so
/// a broken preset shows as broken. Fields are in alphabetical order, as the listing's JSON
/// has always had them.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Summary {
    /// The campaign parses: its runner, its number of runs and its description.
    Ready {
        description: String,
        name: String,
        runner: String,
        runs: u64,
    },
    /// The campaign does not parse: why.
    Broken { error: String, name: String },
}

impl Summary {
    /// The campaign's name, as the listing gives it.
    pub fn name(&self) -> &str {
        match self {
            Summary::Ready { name, .. } | Summary::Broken { name, .. } => name,
        }
    }
}

/// Summarises the campaign text `text` listed as `name`; `source` names it in messages (e.g.
/// `preset smoke`). Its runner is found with `runner_for` and the design expanded.
pub fn summarize(
    name: &str,
    source: &str,
    text: &str,
    runner_for: impl Fn(&str) -> Option<&'static dyn Runner>,
) -> Summary {
    match runner_named(text, source, runner_for).and_then(|r| Design::parse(text, source, r)) {
        Ok(d) => Summary::Ready {
            description: d.campaign.description.clone(),
            name: name.to_string(),
            runner: d.campaign.runner.clone(),
            runs: d.len(),
        },
        Err(e) => Summary::Broken {
            error: e.to_string(),
            name: name.to_string(),
        },
    }
}

/// A TOML error of a campaign file as one line: `SOURCE: line L, column C: message`.
fn toml_error(text: &str, source: &str, e: &toml::de::Error) -> CampaignError {
    CampaignError::Input(format!(
        "{source}: {}",
        usar_world::toml_error_line(text, e)
    ))
}

fn check_report(
    campaign: &CampaignFile,
    levels: &[(String, Vec<Level>)],
    runner: &dyn Runner,
    bad: &dyn Fn(&str, String) -> CampaignError,
) -> Result<()> {
    let report = &campaign.report;
    let varied = |f: &str| levels.iter().find(|(n, _)| n == f);
    let varied_names = || {
        levels
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    for (key, f) in [("rows", &report.rows), ("columns", &report.columns)] {
        if let Some(f) = f
            && f.split('+').any(|f| varied(f).is_none())
        {
            return Err(bad(
                key,
                format!(
                    "report {key} = `{f}`, expected a varied factor ({})",
                    varied_names()
                ),
            ));
        }
    }
    let metrics: Vec<String> = runner.metrics().into_iter().map(|m| m.name).collect();
    for m in report.metrics.iter().chain(&report.series) {
        if !metrics.contains(m) {
            return Err(bad(
                "metrics",
                format!(
                    "unknown metric `{m}` for runner {}, expected one of {}",
                    runner.name(),
                    metrics.join(", ")
                ),
            ));
        }
    }
    for c in &report.compare {
        if !metrics.contains(&c.metric) {
            return Err(bad(
                "metric",
                format!(
                    "comparison of unknown metric `{}`, expected one of {}",
                    c.metric,
                    metrics.join(", ")
                ),
            ));
        }
        for (f, l) in &c.within {
            let Some((_, levels)) = varied(f) else {
                return Err(bad(
                    "within",
                    format!(
                        "comparison within `{f}`, expected a varied factor ({})",
                        varied_names()
                    ),
                ));
            };
            if c.factor.split('+').any(|x| x == f)
                || !levels.iter().any(|v| v.to_string() == l.to_string())
            {
                return Err(bad(
                    "within",
                    format!(
                        "comparison within {f} = {l}: not a level of `{f}` or the compared factor itself"
                    ),
                ));
            }
        }
        if c.factor.contains('+') {
            // A composite factor (`strategy+coordination`): groups are joined levels
            // (`s-mcdm · mrv1`), checked when the report is built.
            if let Some(f) = c.factor.split('+').find(|f| varied(f).is_none()) {
                return Err(bad(
                    "factor",
                    format!(
                        "comparison over `{}`: `{f}` is not a varied factor ({})",
                        c.factor,
                        varied_names()
                    ),
                ));
            }
            if c.test != TestKind::Anova && c.groups.len() != 2 {
                return Err(bad(
                    "groups",
                    format!("a t-test over `{}` needs exactly two groups", c.factor),
                ));
            }
            continue;
        }
        let Some((_, lv)) = varied(&c.factor) else {
            return Err(bad(
                "factor",
                format!(
                    "comparison over `{}`, expected a varied factor ({})",
                    c.factor,
                    varied_names()
                ),
            ));
        };
        for g in &c.groups {
            if !lv.iter().any(|l| l.to_string() == g.to_string()) {
                return Err(bad(
                    "groups",
                    format!("comparison group {g} is not a level of `{}`", c.factor),
                ));
            }
        }
        let n = if c.groups.is_empty() {
            lv.len()
        } else {
            c.groups.len()
        };
        let ok = match c.test {
            TestKind::Anova => n >= 2,
            TestKind::Welch | TestKind::Paired => n == 2,
        };
        if !ok {
            return Err(bad(
                "test",
                format!(
                    "{:?} test over {n} groups of `{}`, expected {}",
                    c.test,
                    c.factor,
                    if c.test == TestKind::Anova {
                        "at least 2"
                    } else {
                        "exactly 2 (set `groups`)"
                    }
                ),
            ));
        }
    }
    Ok(())
}

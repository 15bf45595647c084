//! The statistics of paper 000 §VI-B over an evaluation's runs: per scene, the mean (sd) of
//! steps, coverage, collisions, victims and hand-offs, and the runs that covered everything,
//! found every victim or had no collision; across the weight cases of Table II, a one-way
//! ANOVA of the steps and one-tailed paired t-tests of the travel-weighted case against each
//! other case, paired by (scene, start, repetition).

use crate::evaluation::{EvalConfig, EvalRun};
use serde::Serialize;
use std::collections::BTreeMap;
use usar_campaign::stats::{self, StatsError, Tails, TestResult};

/// Mean and sd of one metric.
#[derive(Serialize)]
pub struct MeanSd {
    pub mean: f64,
    pub sd: Option<f64>,
}

pub fn mean_sd(xs: &[f64]) -> MeanSd {
    let s = stats::summarize(xs);
    MeanSd {
        mean: s.as_ref().map_or(f64::NAN, |s| s.mean),
        sd: s.and_then(|s| s.sd),
    }
}

/// A test's statistic, df and p, or why it could not be computed (`{"error": "..."}`).
#[derive(Serialize)]
#[serde(untagged)]
pub enum TestOutcome {
    Computed(TestResult),
    NotComputed { error: String },
}

impl From<Result<TestResult, StatsError>> for TestOutcome {
    fn from(r: Result<TestResult, StatsError>) -> Self {
        match r {
            Ok(t) => Self::Computed(t),
            Err(e) => Self::NotComputed {
                error: e.to_string(),
            },
        }
    }
}

#[derive(Serialize)]
pub struct SceneSummary {
    pub runs: usize,
    pub steps: MeanSd,
    pub coverage: MeanSd,
    pub collisions: MeanSd,
    pub operator_collisions: MeanSd,
    pub victims_found: MeanSd,
    pub victims_reachable: MeanSd,
    pub handoffs_stuck: MeanSd,
    pub handoffs_victim: MeanSd,
    /// Runs that explored every reachable cell.
    pub full_coverage_runs: usize,
    /// Runs that found every reachable victim.
    pub all_victims_runs: usize,
    /// Runs without a collision while the robot was in control.
    pub collision_free_runs: usize,
    /// Mean steps per weight case (Fig. 9).
    pub steps_by_weights: BTreeMap<String, MeanSd>,
}

pub fn summarize_runs(runs: &[&EvalRun]) -> SceneSummary {
    let col = |f: &dyn Fn(&EvalRun) -> f64| runs.iter().map(|r| f(r)).collect::<Vec<_>>();
    let mut by_weights: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for r in runs {
        by_weights
            .entry(r.weights.clone())
            .or_default()
            .push(r.steps as f64);
    }
    SceneSummary {
        runs: runs.len(),
        steps: mean_sd(&col(&|r| r.steps as f64)),
        coverage: mean_sd(&col(&|r| r.coverage)),
        collisions: mean_sd(&col(&|r| f64::from(r.collisions))),
        operator_collisions: mean_sd(&col(&|r| f64::from(r.operator_collisions))),
        victims_found: mean_sd(&col(&|r| f64::from(r.victims_found))),
        victims_reachable: mean_sd(&col(&|r| f64::from(r.victims_reachable))),
        handoffs_stuck: mean_sd(&col(&|r| f64::from(r.handoffs_stuck))),
        handoffs_victim: mean_sd(&col(&|r| f64::from(r.handoffs_victim))),
        full_coverage_runs: runs.iter().filter(|r| r.coverage >= 1.0).count(),
        all_victims_runs: runs
            .iter()
            .filter(|r| r.victims_found >= r.victims_reachable)
            .count(),
        collision_free_runs: runs.iter().filter(|r| r.collisions == 0).count(),
        steps_by_weights: by_weights
            .iter()
            .map(|(k, v)| (k.clone(), mean_sd(v)))
            .collect(),
    }
}

/// The §VI-B analysis of one evaluation.
#[derive(Serialize)]
pub struct EvalAnalysis {
    /// Per scene, by name.
    pub scenes: BTreeMap<String, SceneSummary>,
    /// One-way ANOVA of the steps across the weight cases.
    pub anova_steps_by_weights: TestOutcome,
    /// `travel_vs_CASE`: one-tailed paired t-test that the travel-weighted case needs fewer
    /// steps than CASE.
    pub paired_t_steps: BTreeMap<String, TestOutcome>,
}

/// What `usar maxq eval --json` prints: the policy evaluated, the number of runs, the §VI-B
/// [`EvalAnalysis`] (its fields inline) and, when asked for, every run.
#[derive(Serialize)]
pub struct EvalSummary<'a> {
    /// The policy file evaluated.
    pub policy: &'a std::path::Path,
    pub runs_total: usize,
    #[serde(flatten)]
    pub analysis: EvalAnalysis,
    /// Every run, when kept.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub runs: Option<&'a [EvalRun]>,
}

impl<'a> EvalSummary<'a> {
    /// Analyses `runs`, an evaluation of `policy` made with `config` ([`analyse`]); the runs
    /// themselves are kept in the summary when `keep_runs`.
    pub fn new(
        policy: &'a std::path::Path,
        runs: &'a [EvalRun],
        config: &EvalConfig,
        keep_runs: bool,
    ) -> Self {
        EvalSummary {
            policy,
            runs_total: runs.len(),
            analysis: analyse(runs, config),
            runs: keep_runs.then_some(runs),
        }
    }
}

/// Analyses the runs of an evaluation made with `config` (see the module documentation).
pub fn analyse(runs: &[EvalRun], config: &EvalConfig) -> EvalAnalysis {
    let mut scenes = BTreeMap::new();
    for name in &config.scenes {
        let of_scene: Vec<&EvalRun> = runs.iter().filter(|r| &r.scene == name).collect();
        scenes.insert(name.clone(), summarize_runs(&of_scene));
    }
    let steps_of = |w: &str| -> Vec<f64> {
        runs.iter()
            .filter(|r| r.weights == w)
            .map(|r| r.steps as f64)
            .collect()
    };
    let groups: Vec<Vec<f64>> = config.weights.iter().map(|w| steps_of(&w.name)).collect();
    let group_refs: Vec<&[f64]> = groups.iter().map(Vec::as_slice).collect();
    let travel = steps_of("travel");
    let paired_t_steps = config
        .weights
        .iter()
        .filter(|w| w.name != "travel")
        .map(|w| {
            let test = stats::paired_t_test(&travel, &steps_of(&w.name), Tails::Less);
            (format!("travel_vs_{}", w.name), test.into())
        })
        .collect();
    EvalAnalysis {
        scenes,
        anova_steps_by_weights: stats::one_way_anova(&group_refs).into(),
        paired_t_steps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run of `weights` on scene A taking `steps`, covering everything.
    fn run(weights: &str, repetition: u32, steps: u64) -> EvalRun {
        EvalRun {
            scene: "A".into(),
            start: 0,
            weights: weights.into(),
            repetition,
            steps,
            coverage: 1.0,
            reachable_cells: 100,
            collisions: 0,
            operator_collisions: 0,
            victims_found: 7,
            victims_reachable: 7,
            false_tags: 0,
            handoffs_stuck: 0,
            handoffs_victim: 1,
            time_s: 0.0,
            exited: true,
        }
    }

    #[test]
    fn a_travel_case_that_is_always_faster_is_significant_against_every_other_case() {
        let config = EvalConfig {
            scenes: vec!["A".into()],
            ..EvalConfig::default()
        };
        let mut runs = Vec::new();
        for rep in 0..8 {
            for (k, w) in config.weights.iter().enumerate() {
                let base = 800 + 13 * u64::from(rep % 3);
                let extra = if w.name == "travel" {
                    0
                } else {
                    40 + 7 * k as u64 + u64::from(rep)
                };
                runs.push(run(&w.name, rep, base + extra));
            }
        }
        let a = analyse(&runs, &config);
        let scene = &a.scenes["A"];
        assert_eq!(scene.runs, runs.len());
        assert_eq!(scene.full_coverage_runs, runs.len());
        assert_eq!(scene.steps_by_weights.len(), config.weights.len());
        assert_eq!(a.paired_t_steps.len(), config.weights.len() - 1);
        for (name, test) in &a.paired_t_steps {
            let TestOutcome::Computed(t) = test else {
                panic!("{name}: not computed");
            };
            assert!(t.p < 0.001, "{name}: p = {}", t.p);
        }
    }
}

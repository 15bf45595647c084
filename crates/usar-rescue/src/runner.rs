//! The campaign runner `maxq-eval`: one evaluation run of paper 000's semi-autonomous controller (§VI-B) —
//! a trained MAXQ policy on scene A, B or C from one of its start poses with one weight case of
//! Table II, an operator answering the hand-offs.
//!
//! The policy is a policy file (`policy`), or, when that is empty, trained once per campaign
//! with `train_trials` and `train_seed` — so a campaign is self-contained and resumable.

use crate::domain::RescueScene;
use crate::evaluation::{EvalConfig, SCENES, eval_scene, run_once};
use crate::exploration::ExplorationWeights;
use crate::policy::PolicyFile;
use crate::training::{TrainConfig, train};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, Mutex};
use usar_campaign::{Config, FactorSpec, MetricSpec, RunError, RunOutput, Runner};
use usar_maxq::MaxqQ;

/// Policies by (file, trials, seed) and scenes by (name, seed), built once per campaign.
pub struct MaxqEvalRunner {
    policies: Mutex<BTreeMap<(String, i64, i64), Arc<MaxqQ>>>,
    scenes: Mutex<BTreeMap<(String, u64), Arc<RescueScene>>>,
}

impl Default for MaxqEvalRunner {
    fn default() -> Self {
        Self::new()
    }
}

impl MaxqEvalRunner {
    /// A runner with empty policy and scene caches (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self {
            policies: Mutex::new(BTreeMap::new()),
            scenes: Mutex::new(BTreeMap::new()),
        }
    }

    /// The configured policy: read from its file, or trained, once.
    fn policy(&self, config: &Config) -> Result<Arc<MaxqQ>, String> {
        let file = config.text("policy").unwrap_or("").to_string();
        let trials = config.int("train_trials").unwrap_or(1800);
        let seed = config.int("train_seed").unwrap_or(1);
        let key = (file.clone(), trials, seed);
        // The lock is held while training so that parallel runs train only once.
        let mut cache = self.policies.lock().expect("policy cache");
        if let Some(p) = cache.get(&key) {
            return Ok(p.clone());
        }
        let learner = if file.is_empty() {
            let train_config = TrainConfig {
                seed: seed as u64,
                trials: trials as u32,
                flat: false,
                ..TrainConfig::default()
            };
            train(&train_config, |_| {}).0
        } else {
            PolicyFile::load(Path::new(&file))
                .map_err(|e| format!("{e:#}"))?
                .learner
        };
        let learner = Arc::new(learner);
        cache.insert(key, learner.clone());
        Ok(learner)
    }

    fn scene(&self, config: &Config) -> Result<Arc<RescueScene>, String> {
        let name = config.text("scene").unwrap_or("A").to_string();
        let seed = config.int("scene_seed").unwrap_or(1) as u64;
        let key = (name.clone(), seed);
        if let Some(s) = self.scenes.lock().expect("scene cache").get(&key) {
            return Ok(s.clone());
        }
        let scene = Arc::new(eval_scene(&name, seed).ok_or_else(|| format!("no scene {name}"))?);
        self.scenes
            .lock()
            .expect("scene cache")
            .insert(key, scene.clone());
        Ok(scene)
    }
}

impl Runner for MaxqEvalRunner {
    fn name(&self) -> &str {
        "maxq-eval"
    }

    fn factors(&self) -> Vec<FactorSpec> {
        let int = |name: &str, min: i64, max: i64, default: i64, help: &str| {
            FactorSpec::int(name, (min, max), default, help)
        };
        let weights = ExplorationWeights::table_ii();
        let weights: Vec<&str> = weights.iter().map(|w| w.name.as_str()).collect();
        let scenes: Vec<&str> = SCENES.iter().map(|(n, _)| *n).collect();
        vec![
            FactorSpec::text(
                "policy",
                &[],
                "",
                "a policy file from `usar maxq train`; empty: train one with train_trials and train_seed",
            ),
            int(
                "train_trials",
                1,
                1_000_000,
                1800,
                "training trials when no policy file is given",
            ),
            int(
                "train_seed",
                0,
                i64::MAX,
                1,
                "training seed when no policy file is given",
            ),
            FactorSpec::text("scene", &scenes, "A", "evaluation scene (paper 000 §VI-B)"),
            int("scene_seed", 0, i64::MAX, 1, "seed of the scene generator"),
            int("start", 0, 2, 0, "start pose of the scene (0, 1, 2)"),
            FactorSpec::text(
                "weights",
                &weights,
                "travel",
                "exploration weight case of Table II",
            ),
            int(
                "max_steps",
                1,
                1_000_000,
                6000,
                "primitive steps after which a run is cut off",
            ),
        ]
    }

    fn metrics(&self) -> Vec<MetricSpec> {
        vec![
            MetricSpec::new("steps", "navigation primitives until the robot exits"),
            MetricSpec::new("coverage", "reachable cells visited / reachable cells"),
            MetricSpec::new("collisions", "collisions while the robot was in control"),
            MetricSpec::new("operator_collisions", "collisions while the operator drove"),
            MetricSpec::new("victims_found", "victims tagged"),
            MetricSpec::new("victims_reachable", "victims in the reachable cells"),
            MetricSpec::new("false_tags", "tags of heat sources that are not victims"),
            MetricSpec::new("handoffs_stuck", "hand-offs because the robot was stuck"),
            MetricSpec::new("handoffs_victim", "hand-offs to identify a victim"),
            MetricSpec::new("time_s", "mission time, operator delays included"),
            MetricSpec::new("exited", "1 if the robot exited by itself, 0 if cut off"),
        ]
    }

    fn series_x(&self) -> &str {
        "step"
    }

    fn check(&self, config: &Config) -> Result<(), RunError> {
        match config.text("policy") {
            Some(file) if !file.is_empty() && !Path::new(file).is_file() => Err(RunError::Input(
                format!("policy file {file} does not exist"),
            )),
            _ => Ok(()),
        }
    }

    fn run(&self, config: &Config, seed: u64) -> Result<RunOutput, RunError> {
        let policy = self.policy(config).map_err(RunError::Input)?;
        let scene = self.scene(config).map_err(RunError::Input)?;
        let start = config.int("start").unwrap_or(0) as usize;
        let weights_name = config.text("weights").unwrap_or("travel");
        let weights = ExplorationWeights::named(weights_name)
            .ok_or_else(|| RunError::Input(format!("no weight case {weights_name}")))?;
        let eval = EvalConfig {
            max_steps: config.int("max_steps").unwrap_or(6000) as u64,
            ..EvalConfig::default()
        };
        let (steps, stats, coverage, _, victims_reachable, exited) =
            run_once(&policy, &scene, start, &weights, &eval, seed)
                .ok_or_else(|| RunError::Input(format!("the scene has no start pose {start}")))?;
        let metrics = BTreeMap::from([
            ("steps".to_string(), steps as f64),
            ("coverage".to_string(), coverage),
            ("collisions".to_string(), f64::from(stats.robot_collisions)),
            (
                "operator_collisions".to_string(),
                f64::from(stats.operator_collisions),
            ),
            ("victims_found".to_string(), f64::from(stats.victims_found)),
            (
                "victims_reachable".to_string(),
                f64::from(victims_reachable),
            ),
            ("false_tags".to_string(), f64::from(stats.false_tags)),
            (
                "handoffs_stuck".to_string(),
                f64::from(stats.handoffs_stuck),
            ),
            (
                "handoffs_victim".to_string(),
                f64::from(stats.handoffs_victim),
            ),
            ("time_s".to_string(), stats.time_s),
            ("exited".to_string(), f64::from(u8::from(exited))),
        ]);
        Ok(RunOutput {
            metrics,
            series: Vec::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_campaign::design::Level;

    #[test]
    fn a_run_trains_its_policy_once_and_reports_every_metric() {
        let runner = MaxqEvalRunner::new();
        let mut levels: BTreeMap<String, Level> = runner
            .factors()
            .into_iter()
            .map(|f| (f.name, f.default))
            .collect();
        levels.insert("train_trials".into(), Level::Int(3));
        levels.insert("max_steps".into(), Level::Int(300));
        let mut config = Config(levels);
        assert_eq!(runner.check(&config), Ok(()));
        let a = runner.run(&config, 7).unwrap();
        let b = runner.run(&config, 7).unwrap();
        assert_eq!(a, b, "a run is a pure function of configuration and seed");
        assert_eq!(runner.policies.lock().unwrap().len(), 1, "trained once");
        let names: Vec<String> = runner.metrics().into_iter().map(|m| m.name).collect();
        assert!(
            names.iter().all(|n| a.metrics.contains_key(n)),
            "{:?}",
            a.metrics
        );
        assert!(a.metrics["steps"] <= 300.0);
        config
            .0
            .insert("policy".into(), Level::Text("no/such/policy.json".into()));
        let err = runner.check(&config).unwrap_err();
        assert!(
            err.is_input() && err.to_string().contains("does not exist"),
            "{err}"
        );
    }
}

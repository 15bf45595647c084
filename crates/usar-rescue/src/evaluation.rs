//! Evaluation of a trained policy (paper 000 §VI-B): the built-in scenes A, B and C × their
//! three start poses × the four weight cases of Table II × repetitions, the greedy hierarchical
//! policy in control and an operator answering hand-offs. Each run is a pure function of
//! (policy, scene, start, weights, repetition, seed); runs execute in parallel.

use crate::domain::{DomainConfig, RescueDomain, RescueScene};
use crate::exploration::ExplorationWeights;
use crate::hierarchy::RescueHierarchy;
use crate::operator::{OperatorProfile, SimulatedOperator};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use usar_maxq::MaxqQ;
use usar_world::generate::{RubbleParams, RubbleStyle, generate_rubble};

/// The evaluation scenes: name and style (the generator seed is [`EvalConfig::scene_seed`]).
pub const SCENES: [(&str, RubbleStyle); 3] = [
    ("A", RubbleStyle::SceneA),
    ("B", RubbleStyle::SceneB),
    ("C", RubbleStyle::SceneC),
];

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalConfig {
    pub seed: u64,
    /// Seed of the generator for scenes A, B, C.
    pub scene_seed: u64,
    pub repetitions: u32,
    /// Which of the scenes (names of [`SCENES`]).
    pub scenes: Vec<String>,
    pub weights: Vec<ExplorationWeights>,
    pub domain: DomainConfig,
    pub operator: OperatorProfile,
    /// Primitive steps after which a run is cut off.
    pub max_steps: u64,
}

impl Default for EvalConfig {
    /// The paper's design: scenes A, B, C × 3 starts × 4 weight cases × 6 repetitions.
    fn default() -> Self {
        Self {
            seed: 1,
            scene_seed: 1,
            repetitions: 6,
            scenes: SCENES.iter().map(|(n, _)| n.to_string()).collect(),
            weights: ExplorationWeights::table_ii().to_vec(),
            domain: DomainConfig::default(),
            operator: OperatorProfile::expert(),
            max_steps: 6000,
        }
    }
}

/// One evaluation run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EvalRun {
    pub scene: String,
    pub start: usize,
    pub weights: String,
    pub repetition: u32,
    /// Navigation primitives (F, B, θ) until the robot exits.
    pub steps: u64,
    /// Reachable cells visited / reachable cells.
    pub coverage: f64,
    pub reachable_cells: usize,
    /// Collisions while the robot was in control.
    pub collisions: u32,
    /// Collisions while the operator drove.
    pub operator_collisions: u32,
    pub victims_found: u32,
    pub victims_reachable: u32,
    pub false_tags: u32,
    pub handoffs_stuck: u32,
    pub handoffs_victim: u32,
    pub time_s: f64,
    /// Whether the robot exited by itself (not cut off).
    pub exited: bool,
}

/// The seed of one run.
fn run_seed(seed: u64, scene: usize, start: usize, weights: usize, rep: u32) -> u64 {
    let mut h = seed ^ 0xE7A1_u64;
    for v in [scene as u64, start as u64, weights as u64, u64::from(rep)] {
        h = (h ^ v).wrapping_mul(0x100_0000_01B3).rotate_left(17) ^ 0x9E37_79B9_7F4A_7C15;
    }
    h
}

/// Builds scene `name` (A, B or C).
pub fn eval_scene(name: &str, scene_seed: u64) -> Option<RescueScene> {
    let (_, style) = SCENES.iter().find(|(n, _)| *n == name)?;
    Some(RescueScene::new(generate_rubble(
        scene_seed,
        &RubbleParams::with_style(*style),
    )))
}

/// Runs the policy once.
pub fn run_once(
    policy: &MaxqQ,
    scene: &RescueScene,
    start: usize,
    weights: &ExplorationWeights,
    config: &EvalConfig,
    seed: u64,
) -> Option<(u64, crate::RunStats, f64, usize, u32, bool)> {
    run_observed(policy, scene, start, weights, config, seed, |_| {})
}

/// The robot's domain in an evaluation run, as an observer sees it.
pub type EvalDomain<'a> = RescueDomain<'a, SimulatedOperator>;

/// [`run_once`], showing the domain to `observe` after every primitive step.
pub fn run_observed(
    policy: &MaxqQ,
    scene: &RescueScene,
    start: usize,
    weights: &ExplorationWeights,
    config: &EvalConfig,
    seed: u64,
    observe: impl FnMut(&EvalDomain<'_>),
) -> Option<(u64, crate::RunStats, f64, usize, u32, bool)> {
    let h = RescueHierarchy::new();
    let start_pose = scene.start(start)?;
    let operator = SimulatedOperator::new(config.operator.clone(), seed ^ 0x0DE);
    let domain = RescueDomain::new(
        scene,
        start_pose,
        weights.clone(),
        config.domain.clone(),
        operator,
        seed,
    );
    let mut learner = policy.clone();
    learner.params.max_steps_per_episode = config.max_steps;
    let s0 = domain.state();
    let mut observed = usar_maxq::Observed { domain, observe };
    let episode = learner.greedy_episode(&h, &mut observed, s0);
    let domain = observed.domain;
    let (reachable, victims) = scene.reachable(start_pose.0);
    let reachable_cells = reachable.iter().filter(|&&r| r).count();
    let visited = domain
        .visited()
        .zip(&reachable)
        .filter(|&(v, &r)| v && r)
        .count();
    let coverage = if reachable_cells == 0 {
        1.0
    } else {
        visited as f64 / reachable_cells as f64
    };
    Some((
        domain.agent.stats.steps,
        domain.agent.stats.clone(),
        coverage,
        reachable_cells,
        victims.len() as u32,
        episode.finished,
    ))
}

/// One run of the design: (scene, start, weights, repetition) indices.
pub type DesignRun = (usize, usize, usize, u32);

/// The evaluation's named scenes and its design, in design order.
pub fn design(config: &EvalConfig) -> (Vec<(String, RescueScene)>, Vec<DesignRun>) {
    let scenes: Vec<(String, RescueScene)> = config
        .scenes
        .iter()
        .filter_map(|n| eval_scene(n, config.scene_seed).map(|s| (n.clone(), s)))
        .collect();
    let mut design = Vec::new();
    for (si, (_, scene)) in scenes.iter().enumerate() {
        for start in 0..scene.scene.start_poses.len().min(3) {
            for wi in 0..config.weights.len() {
                for rep in 0..config.repetitions {
                    design.push((si, start, wi, rep));
                }
            }
        }
    }
    (scenes, design)
}

/// Run `(si, start, wi, rep)` of the design, shown to `observe` step by step.
fn design_run(
    policy: &MaxqQ,
    config: &EvalConfig,
    scenes: &[(String, RescueScene)],
    (si, start, wi, rep): DesignRun,
    observe: impl FnMut(&EvalDomain<'_>),
) -> Option<EvalRun> {
    let (name, scene) = &scenes[si];
    let weights = &config.weights[wi];
    let seed = run_seed(config.seed, si, start, wi, rep);
    let (steps, stats, coverage, reachable_cells, victims_reachable, exited) =
        run_observed(policy, scene, start, weights, config, seed, observe)?;
    Some(EvalRun {
        scene: name.clone(),
        start,
        weights: weights.name.clone(),
        repetition: rep,
        steps,
        coverage,
        reachable_cells,
        collisions: stats.robot_collisions,
        operator_collisions: stats.operator_collisions,
        victims_found: stats.victims_found,
        victims_reachable,
        false_tags: stats.false_tags,
        handoffs_stuck: stats.handoffs_stuck,
        handoffs_victim: stats.handoffs_victim,
        time_s: stats.time_s,
        exited,
    })
}

/// Every run of the design, in design order (scene, start, weights, repetition).
pub fn evaluate(policy: &MaxqQ, config: &EvalConfig, progress: impl Fn() + Sync) -> Vec<EvalRun> {
    let (scenes, design) = design(config);
    design
        .par_iter()
        .filter_map(|&run| {
            let out = design_run(policy, config, &scenes, run, |_| {});
            progress();
            out
        })
        .collect()
}

/// Run `index` of the design (in design order) again, shown to `observe` after every
/// primitive step: the same run as in [`evaluate`] (same scene, start, weights and seed).
/// `None` when there is no such run.
pub fn replay(
    policy: &MaxqQ,
    config: &EvalConfig,
    index: usize,
    observe: impl FnMut(&EvalDomain<'_>),
) -> Option<EvalRun> {
    let (scenes, design) = design(config);
    design_run(policy, config, &scenes, *design.get(index)?, observe)
}

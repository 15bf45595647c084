//! Training of the hierarchy over random rubble scenes (paper 000 §VI-A): every trial is a new
//! scene of the training style; MAXQ-Q and flat Q-learning learn on the same scenes with the
//! same rates, initial values, state variables and primitive actions. The curves are the
//! cumulative reward per trial (Fig. 7a) and the steps per trial (Fig. 7b).

use crate::domain::{DomainConfig, RescueDomain, RescueScene};
use crate::exploration::ExplorationWeights;
use crate::hierarchy::{RescueHierarchy, action};
use crate::operator::{OperatorProfile, SimulatedOperator};
use crate::perception::Perception;
use crate::state::RescueState;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use usar_maxq::{Domain, Hierarchy, LearningParams, MaxqQ, Schedule, SparseFlatQ};
use usar_world::generate::{RubbleParams, RubbleStyle, generate_rubble};

/// How training runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainConfig {
    pub seed: u64,
    /// Trials, one random scene each (paper: 1 800).
    pub trials: u32,
    pub params: LearningParams,
    /// Exploration weights used while training.
    pub weights: ExplorationWeights,
    pub domain: DomainConfig,
    /// The operator answering hand-offs while training.
    pub operator: OperatorProfile,
    /// Train the flat Q-learner too.
    pub flat: bool,
}

impl Default for TrainConfig {
    /// The paper's schedules (ε and α start at 1, −0.01 every 100 primitive steps) with floors
    /// ε ≥ 0.1, α ≥ 0.1 (the paper gives none; at 0 learning would stop after 10 000 steps);
    /// γ = 0.9; a trial is cut at 3 000 primitive steps; equal exploration weights.
    fn default() -> Self {
        Self {
            seed: 1,
            trials: 1800,
            params: LearningParams {
                gamma: 0.9,
                alpha: Schedule::paper_000(0.1),
                epsilon: Schedule::paper_000(0.1),
                max_steps_per_episode: 3000,
            },
            weights: ExplorationWeights::named("equal").expect("Table II case"),
            domain: DomainConfig::default(),
            operator: OperatorProfile::expert(),
            flat: true,
        }
    }
}

/// A training configuration that cannot run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TrainConfigError {
    #[error("trials: {}", self.problem())]
    Trials { found: u32, max: u64 },
}

impl TrainConfigError {
    /// What is wrong, without the field's name (for callers that name the field their way).
    pub fn problem(&self) -> String {
        match self {
            Self::Trials { found, max } => {
                format!("found {found}, expected 1 to {max} (raise the limit with --max-trials)")
            }
        }
    }
}

impl TrainConfig {
    /// Checks the trial count (1 ..= the trial limit).
    pub fn validate(&self) -> Result<(), TrainConfigError> {
        check_trials(self.trials)
    }
}

/// Checks a trial count against 1 ..= the trial limit in force: paper 000 trains 1 800; the
/// limit ([`usar_world::limits`], `usar --max-trials`, 1 000 000 by default) is checked before
/// anything is allocated, so a mistyped `4000000000` is refused at once instead of running for
/// years.
pub fn check_trials(trials: u32) -> Result<(), TrainConfigError> {
    let max = usar_world::limits::limits().max_trials;
    if trials >= 1 && u64::from(trials) <= max {
        Ok(())
    } else {
        Err(TrainConfigError::Trials { found: trials, max })
    }
}

/// One trial of the learning curves.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrialPoint {
    pub trial: u32,
    pub maxq_reward: f64,
    /// Navigation primitives of the MAXQ trial (Fig. 7b).
    pub maxq_steps: u64,
    pub maxq_finished: bool,
    pub flat_reward: Option<f64>,
    pub flat_steps: Option<u64>,
}

/// What training produced.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainReport {
    pub trials: u32,
    pub seed: u64,
    /// Values MAXQ-Q ever wrote (V of primitives and C of subtasks).
    pub maxq_q_values: usize,
    /// Values flat Q ever wrote.
    pub flat_q_values: usize,
    /// States the flat learner met.
    pub flat_states: usize,
    /// Primitive steps learned from.
    pub maxq_primitive_steps: u64,
    pub flat_primitive_steps: u64,
    pub curve: Vec<TrialPoint>,
}

impl TrainReport {
    /// MAXQ-Q's stored values as a share of flat Q's (the §VI-A memory comparison; flat Q
    /// counted as at least 1).
    pub fn maxq_over_flat(&self) -> f64 {
        self.maxq_q_values as f64 / self.flat_q_values.max(1) as f64
    }
}

/// The seed of trial `t` (scene, start, streams).
pub fn trial_seed(seed: u64, t: u32) -> u64 {
    seed.wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (u64::from(t) + 1).wrapping_mul(0xD1B5_4A32_D192_ED03)
}

/// A training scene (the random style of §VI-A) and its start.
pub fn training_scene(seed: u64, t: u32) -> (RescueScene, (usar_world::Cell, u8)) {
    let s = trial_seed(seed, t);
    let scene = RescueScene::new(generate_rubble(
        s,
        &RubbleParams::with_style(RubbleStyle::Random),
    ));
    let mut rng = Pcg64Mcg::seed_from_u64(s ^ 0xA11CE);
    let starts = scene.scene.start_poses.len().max(1);
    let k = rng.random_range(0..starts);
    let start = scene
        .start(k)
        .or_else(|| scene.start(0))
        .unwrap_or((usar_world::Cell::new(0, 0), 0));
    (scene, start)
}

/// A training trial prepared ahead of learning: its scene, start and sensors with every
/// reading taken ([`Perception::sense_all`]).
pub struct PreparedTrial {
    pub scene: RescueScene,
    pub start: (usar_world::Cell, u8),
    pub perception: Perception,
}

/// Trial `t` of a training run from `seed`, prepared (a pure function of both).
pub fn prepare_trial(seed: u64, t: u32) -> PreparedTrial {
    let (scene, start) = training_scene(seed, t);
    let mut perception =
        RescueDomain::<SimulatedOperator>::perception(&scene, start, trial_seed(seed, t));
    perception.sense_all(&scene.scene, &scene.view);
    PreparedTrial {
        scene,
        start,
        perception,
    }
}

/// A fresh learner for the USAR hierarchy.
pub fn new_learner(params: &LearningParams) -> MaxqQ {
    MaxqQ::new(RescueHierarchy::new().nodes().to_vec(), params.clone())
}

/// The flat learner's actions: F, B, rotate left, rotate right, Tag, Exit.
const FLAT_ACTIONS: [usize; 6] = [
    action::FORWARD,
    action::BACKWARD,
    action::ROTATE_LEFT,
    action::ROTATE_RIGHT,
    action::TAG,
    action::EXIT,
];

/// The domain as the flat learner sees it: its own action numbering.
struct FlatDomain<'d, 'a>(&'d mut RescueDomain<'a, SimulatedOperator>);

impl Domain for FlatDomain<'_, '_> {
    type State = RescueState;
    fn step(&mut self, s: &RescueState, a: usize) -> (RescueState, f64) {
        self.0.step(s, FLAT_ACTIONS[a])
    }
    fn is_terminal(&self, s: &RescueState) -> bool {
        s.done()
    }
    /// The same preconditions as the hierarchy's.
    fn available(&self, s: &RescueState, a: usize) -> bool {
        crate::hierarchy::action_available(FLAT_ACTIONS[a], s)
    }
}

/// Trains MAXQ-Q (and flat Q) over `config.trials` scenes; `progress(trials_done)` after each.
/// Trials (scene, start, sensor readings) are prepared in parallel batches ahead of the
/// learners (each is a pure function of its seed); learning itself is sequential, so the
/// result is independent of the thread count.
pub fn train(config: &TrainConfig, mut progress: impl FnMut(u32)) -> (MaxqQ, TrainReport) {
    let h = RescueHierarchy::new();
    let mut maxq = new_learner(&config.params);
    let mut flat = SparseFlatQ::new(FLAT_ACTIONS.len(), config.params.clone());
    let mut maxq_rng = Pcg64Mcg::seed_from_u64(config.seed ^ 0x3A70_u64);
    let mut flat_rng = Pcg64Mcg::seed_from_u64(config.seed ^ 0xF1A7);
    // Grown as trials end: the count is the caller's, never an allocation size.
    let mut curve = Vec::new();
    const BATCH: u32 = 32;
    let mut t0 = 0;
    while t0 < config.trials {
        let t1 = (t0 + BATCH).min(config.trials);
        let trials: Vec<_> = (t0..t1)
            .into_par_iter()
            .map(|t| prepare_trial(config.seed, t))
            .collect();
        for (t, trial) in (t0..t1).zip(&trials) {
            let (scene, start) = (&trial.scene, &trial.start);
            let s = trial_seed(config.seed, t);
            // Both learners meet the same trial: scene, start, operator and noise.
            let new_domain = || {
                let operator = SimulatedOperator::new(config.operator.clone(), s ^ 0x0DE);
                RescueDomain::with_perception(
                    scene,
                    *start,
                    config.weights.clone(),
                    config.domain.clone(),
                    operator,
                    s,
                    trial.perception.clone(),
                )
            };
            let mut domain = new_domain();
            let s0 = domain.state();
            let e = maxq.learn_episode(&h, &mut domain, s0, &mut maxq_rng);
            let mut point = TrialPoint {
                trial: t,
                maxq_reward: e.reward,
                maxq_steps: domain.agent.stats.steps,
                maxq_finished: e.finished,
                flat_reward: None,
                flat_steps: None,
            };
            if config.flat {
                let mut domain = new_domain();
                let s0 = domain.state();
                let e = flat.learn_episode(
                    &mut FlatDomain(&mut domain),
                    RescueState::flat_key,
                    s0,
                    &mut flat_rng,
                );
                point.flat_reward = Some(e.reward);
                point.flat_steps = Some(domain.agent.stats.steps);
            }
            curve.push(point);
            progress(t + 1);
        }
        t0 = t1;
    }
    let report = TrainReport {
        trials: config.trials,
        seed: config.seed,
        maxq_q_values: maxq.stored_values(),
        flat_q_values: flat.stored_values(),
        flat_states: flat.states(),
        maxq_primitive_steps: maxq.steps,
        flat_primitive_steps: flat.steps,
        curve,
    };
    (maxq, report)
}

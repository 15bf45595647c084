//! Flat Q-learning (Watkins 1989) over the full state, for comparison with MAXQ:
//! Q(s, a) ← (1 − α) Q(s, a) + α [r + γ max_a′ Q(s′, a′)], ε-greedy, with the same schedules.

use crate::maxq::{Domain, Episode, LearningParams, Table};
use rand::Rng;
use serde::{Deserialize, Serialize};

/// A tabular Q-function over `states` × `actions`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlatQ {
    pub states: usize,
    pub actions: usize,
    pub params: LearningParams,
    pub q: Table,
    pub steps: u64,
}

impl FlatQ {
    pub fn new(states: usize, actions: usize, params: LearningParams) -> Self {
        Self {
            states,
            actions,
            params,
            q: Table {
                values: vec![0.0; states * actions],
                written: vec![false; states * actions],
            },
            steps: 0,
        }
    }

    /// Values ever written.
    pub fn stored_values(&self) -> usize {
        self.q.stored()
    }

    fn greedy(&self, s: usize) -> (usize, f64) {
        let row = &self.q.values[s * self.actions..(s + 1) * self.actions];
        row.iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (a, &q)| {
                if q > best.1 { (a, q) } else { best }
            })
    }

    /// One learning episode; `index` maps a state to `0..states`.
    pub fn learn_episode<S: Clone, D: Domain<State = S>>(
        &mut self,
        domain: &mut D,
        index: impl Fn(&S) -> usize,
        s0: S,
        rng: &mut impl Rng,
    ) -> Episode {
        let mut episode = Episode::default();
        let mut s = s0;
        while !domain.is_terminal(&s) && episode.steps < self.params.max_steps_per_episode {
            let si = index(&s);
            let a = if rng.random::<f64>() < self.params.epsilon.at(self.steps) {
                rng.random_range(0..self.actions)
            } else {
                self.greedy(si).0
            };
            let (next, r) = domain.step(&s, a);
            let future = if domain.is_terminal(&next) {
                0.0
            } else {
                self.greedy(index(&next)).1
            };
            let alpha = self.params.alpha.at(self.steps);
            self.q
                .update(si * self.actions + a, alpha, r + self.params.gamma * future);
            self.steps += 1;
            episode.reward += r;
            episode.steps += 1;
            s = next;
        }
        episode.finished = domain.is_terminal(&s);
        episode
    }

    /// Runs the greedy policy from `s0` without learning.
    pub fn greedy_episode<S: Clone, D: Domain<State = S>>(
        &self,
        domain: &mut D,
        index: impl Fn(&S) -> usize,
        s0: S,
    ) -> Episode {
        let mut episode = Episode::default();
        let mut s = s0;
        while !domain.is_terminal(&s) && episode.steps < self.params.max_steps_per_episode {
            let (next, r) = domain.step(&s, self.greedy(index(&s)).0);
            episode.reward += r;
            episode.steps += 1;
            s = next;
        }
        episode.finished = domain.is_terminal(&s);
        episode
    }
}

/// Flat Q-learning over a state space too large to allocate (paper 000's flat learner sees
/// the robot's cell, heading and every state variable of the hierarchy at once): a row of
/// `actions` values is created the first time a state is met. Same update, schedules and
/// greedy tie-break (lowest action) as [`FlatQ`]; [`SparseFlatQ::stored_values`] counts the
/// entries ever written, as the paper counts "Q-values stored".
#[derive(Clone, Debug)]
pub struct SparseFlatQ {
    pub actions: usize,
    pub params: LearningParams,
    /// Row of each state key met so far (unsorted: only looked up, never iterated).
    rows_unsorted: std::collections::HashMap<u64, u32, BuildKeyHasher>,
    values: Vec<f64>,
    written: Vec<bool>,
    pub steps: u64,
}

impl SparseFlatQ {
    pub fn new(actions: usize, params: LearningParams) -> Self {
        Self {
            actions,
            params,
            rows_unsorted: std::collections::HashMap::default(),
            values: Vec::new(),
            written: Vec::new(),
            steps: 0,
        }
    }

    fn params(&self) -> &LearningParams {
        &self.params
    }

    /// States met so far.
    pub fn states(&self) -> usize {
        self.rows_unsorted.len()
    }

    /// Values ever written.
    pub fn stored_values(&self) -> usize {
        self.written.iter().filter(|&&w| w).count()
    }

    fn row(&mut self, key: u64) -> usize {
        let next = self.rows_unsorted.len() as u32;
        let row = *self.rows_unsorted.entry(key).or_insert(next) as usize;
        if row == next as usize {
            self.values.extend(std::iter::repeat_n(0.0, self.actions));
            self.written
                .extend(std::iter::repeat_n(false, self.actions));
        }
        row
    }

    fn greedy_in(&self, row: Option<usize>) -> (usize, f64) {
        let Some(row) = row else { return (0, 0.0) };
        let values = &self.values[row * self.actions..(row + 1) * self.actions];
        values
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (a, &q)| {
                if q > best.1 { (a, q) } else { best }
            })
    }

    /// The greedy action of a state (action 0 for a state never met).
    pub fn greedy(&self, key: u64) -> usize {
        self.greedy_in(self.rows_unsorted.get(&key).map(|&r| r as usize))
            .0
    }

    /// One learning episode; `key` maps a state to its identity.
    pub fn learn_episode<S: Clone, D: Domain<State = S>>(
        &mut self,
        domain: &mut D,
        key: impl Fn(&S) -> u64,
        s0: S,
        rng: &mut impl Rng,
    ) -> Episode {
        let mut episode = Episode::default();
        let mut s = s0;
        let max_steps = self.params().max_steps_per_episode;
        while !domain.is_terminal(&s) && episode.steps < max_steps {
            let row = self.row(key(&s));
            let a = if rng.random::<f64>() < self.params().epsilon.at(self.steps) {
                rng.random_range(0..self.actions)
            } else {
                self.greedy_in(Some(row)).0
            };
            let (next, r) = domain.step(&s, a);
            let future = if domain.is_terminal(&next) {
                0.0
            } else {
                let next_row = self.rows_unsorted.get(&key(&next)).map(|&r| r as usize);
                self.greedy_in(next_row).1
            };
            let alpha = self.params().alpha.at(self.steps);
            let target = r + self.params().gamma * future;
            let i = row * self.actions + a;
            self.values[i] = (1.0 - alpha) * self.values[i] + alpha * target;
            self.written[i] = true;
            self.steps += 1;
            episode.reward += r;
            episode.steps += 1;
            s = next;
        }
        episode.finished = domain.is_terminal(&s);
        episode
    }
}

/// A fast multiplicative hasher for integer keys (deterministic; no iteration reaches an output).
#[derive(Clone, Copy, Debug, Default)]
pub struct BuildKeyHasher;

impl std::hash::BuildHasher for BuildKeyHasher {
    type Hasher = KeyHasher;
    fn build_hasher(&self) -> KeyHasher {
        KeyHasher(0)
    }
}

/// See [`BuildKeyHasher`].
#[derive(Clone, Copy, Debug, Default)]
pub struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(5) ^ u64::from(b)).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
        }
    }
    fn write_u64(&mut self, n: u64) {
        self.0 = (self.0.rotate_left(5) ^ n).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

//! Flat Q-learning (Watkins 1989) over the full state, for comparison with MAXQ:
//! Q(s, a) ← (1 − α) Q(s, a) + α [r + γ max_a′ Q(s′, a′)], ε-greedy, with the same schedules.

use crate::maxq::{Domain, Episode, LearningParams, Table};
use rand::Rng;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// The best action of a row of Q-values and its value; ties go to the lowest action.
fn greedy_action(row: &[f64]) -> (usize, f64) {
    row.iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, (a, &q)| {
            if q > best.1 { (a, q) } else { best }
        })
}

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
            q: Table::new(states * actions),
            steps: 0,
        }
    }

    /// Values ever written.
    pub fn stored_values(&self) -> usize {
        self.q.stored()
    }

    fn greedy(&self, s: usize) -> (usize, f64) {
        greedy_action(&self.q.values[s * self.actions..(s + 1) * self.actions])
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
/// the whole unabstracted state: the robot's map, its pose and every other state variable of
/// the hierarchy): a row of `actions` values is created the first time a state is met. Same
/// update, schedules and greedy tie-break (lowest action) as [`FlatQ`], over the actions
/// [`Domain::available`] in the state;
/// [`SparseFlatQ::stored_values`] counts the entries ever written, as the paper counts
/// "Q-values stored". Millions of states are met, so a row is stored compactly: `f32` values
/// and a bit per action saying whether it was written (at most 8 actions).
#[derive(Clone, Debug)]
pub struct SparseFlatQ {
    pub actions: usize,
    pub params: LearningParams,
    /// Row of each state key met so far (only looked up, never iterated).
    rows: FxHashMap<u64, u32>,
    values: Vec<f32>,
    /// Bit a of row r set when Q(r, a) was written.
    written: Vec<u8>,
    stored: usize,
    pub steps: u64,
}

impl SparseFlatQ {
    /// A learner over `actions` ≤ 8 actions.
    pub fn new(actions: usize, params: LearningParams) -> Self {
        assert!(actions <= 8, "SparseFlatQ supports at most 8 actions");
        Self {
            actions,
            params,
            rows: FxHashMap::default(),
            values: Vec::new(),
            written: Vec::new(),
            stored: 0,
            steps: 0,
        }
    }

    /// States met so far.
    pub fn states(&self) -> usize {
        self.rows.len()
    }

    /// Values ever written.
    pub fn stored_values(&self) -> usize {
        self.stored
    }

    /// The row of a state key, created (unwritten zeros) the first time it is met.
    fn row(&mut self, key: u64) -> usize {
        let next = self.rows.len() as u32;
        let row = *self.rows.entry(key).or_insert(next) as usize;
        if row == next as usize {
            self.values.extend(std::iter::repeat_n(0.0, self.actions));
            self.written.push(0);
        }
        row
    }

    /// The greedy action among those `available` (bit a) and its value; a state never met
    /// has only zeros.
    fn greedy_in(&self, row: Option<usize>, available: u8) -> (usize, f64) {
        let mut best = (0, f64::NEG_INFINITY);
        for a in 0..self.actions {
            if available & (1 << a) == 0 {
                continue;
            }
            let q = row.map_or(0.0, |row| f64::from(self.values[row * self.actions + a]));
            if q > best.1 {
                best = (a, q);
            }
        }
        if best.1 == f64::NEG_INFINITY {
            (0, 0.0)
        } else {
            best
        }
    }

    /// The actions available in `s` as a bit mask.
    fn available<S, D: Domain<State = S>>(&self, domain: &D, s: &S) -> u8 {
        (0..self.actions)
            .filter(|&a| domain.available(s, a))
            .fold(0, |m, a| m | 1 << a)
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
        // The next state's key, row (if stored) and available actions, from the step before.
        let mut carried: Option<(u64, Option<usize>, u8)> = None;
        while !domain.is_terminal(&s) && episode.steps < self.params.max_steps_per_episode {
            let (k, known, available) = carried
                .take()
                .unwrap_or_else(|| (key(&s), None, self.available(domain, &s)));
            let row = known.unwrap_or_else(|| self.row(k));
            let a = if rng.random::<f64>() < self.params.epsilon.at(self.steps) {
                let pick = rng.random_range(0..available.count_ones());
                (0..self.actions)
                    .filter(|&a| available & (1 << a) != 0)
                    .nth(pick as usize)
                    .unwrap_or(0)
            } else {
                self.greedy_in(Some(row), available).0
            };
            let (next, r) = domain.step(&s, a);
            let future = if domain.is_terminal(&next) {
                0.0
            } else {
                let k = key(&next);
                let row = self.rows.get(&k).map(|&r| r as usize);
                let available = self.available(domain, &next);
                carried = Some((k, row, available));
                self.greedy_in(row, available).1
            };
            let alpha = self.params.alpha.at(self.steps);
            let i = row * self.actions + a;
            let q = f64::from(self.values[i]);
            self.values[i] = ((1.0 - alpha) * q + alpha * (r + self.params.gamma * future)) as f32;
            if self.written[row] & (1 << a) == 0 {
                self.written[row] |= 1 << a;
                self.stored += 1;
            }
            self.steps += 1;
            episode.reward += r;
            episode.steps += 1;
            s = next;
        }
        episode.finished = domain.is_terminal(&s);
        episode
    }
}

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

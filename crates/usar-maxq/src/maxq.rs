//! MAXQ-Q learning (Dietterich 2000, "Hierarchical reinforcement learning with the MAXQ value
//! function decomposition", Table 4; paper 000 eq. 1–3).
//!
//! A task graph of composite subtasks and primitive actions. The value of a subtask i in state
//! s decomposes as (paper 000 eq. 1–2)
//!
//! ```text
//! Q(i, s, a) = V(a, s) + C(i, s, a)
//! V(i, s)    = max_a Q(i, s, a)          (i composite)
//! V(i, s)    = E[r | s, i]               (i primitive)
//! ```
//!
//! where the completion function C(i, s, a) is the expected discounted reward for finishing i
//! after a. Learning (eq. 3): a primitive updates V(a, s) ← (1 − α)V(a, s) + α·r; when child a
//! of i terminates after N primitive steps in s′, for each state s visited during a (the last
//! one with N = 1, earlier ones with larger N)
//!
//! ```text
//! a*          = argmax_a′ [ C̃(i, s′, a′) + V(a′, s′) ]
//! C̃(i, s, a) ← (1 − α) C̃(i, s, a) + α γᴺ [ R̃ᵢ(s′) + C̃(i, s′, a*) + V(a*, s′) ]
//! C(i, s, a)  ← (1 − α) C(i, s, a)  + α γᴺ [ C(i, s′, a*) + V(a*, s′) ]
//! ```
//!
//! C̃ includes the subtask's pseudo-reward R̃ᵢ and drives the choices inside i; C, without it,
//! is what i's parents see. Each node reads and writes its tables through its own state
//! abstraction, so a subtask only stores values for the state variables relevant to it.

use crate::schedule::{ParamError, Schedule};
use rand::Rng;
use serde::{Deserialize, Serialize};

/// Index of a node in the task graph.
pub type NodeId = usize;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum NodeKind {
    /// A primitive action of the domain.
    Primitive { action: usize },
    /// A subtask choosing among its children.
    Composite { children: Vec<NodeId> },
}

/// A node of the task graph; `states` is the size of its abstract state space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub name: String,
    pub kind: NodeKind,
    pub states: usize,
}

/// The environment: executes primitive actions.
pub trait Domain {
    type State: Clone;
    /// Executes `action` in `s`: the next state and the reward.
    fn step(&mut self, s: &Self::State, action: usize) -> (Self::State, f64);
    /// Whether the episode has ended in `s`.
    fn is_terminal(&self, s: &Self::State) -> bool;
    /// Whether `action` may be executed in `s` (its precondition), for learners that choose
    /// primitive actions directly ([`crate::SparseFlatQ`]). Default: always.
    fn available(&self, _s: &Self::State, _action: usize) -> bool {
        true
    }
    /// A choice among the `children` of composite `node` made outside the learner — a human
    /// operator answering a hand-off (paper 000 §IV-A-5) — or `None` to let the learner choose.
    /// MAXQ-Q learns from a delegated choice exactly as from its own (it is off-policy), so the
    /// hierarchy "continues to learn by observing the implemented actions of the operator".
    fn delegated_choice(&mut self, _node: NodeId, _s: &Self::State) -> Option<usize> {
        None
    }
}

/// The hierarchy over a domain: state abstraction, termination and pseudo-rewards per node.
pub trait Hierarchy<S> {
    /// The task graph (node ids index this slice).
    fn nodes(&self) -> &[Node];
    fn root(&self) -> NodeId;
    /// The abstract state of `s` as node `node` sees it, in `0..nodes()[node].states`.
    fn abstraction(&self, node: NodeId, s: &S) -> usize;
    /// Whether composite `node` has terminated in `s` (primitives are never asked). A child
    /// that is terminated in the current state is not eligible.
    fn terminated(&self, node: NodeId, s: &S) -> bool;
    /// Whether primitive `node` may be executed in `s` (its precondition; default: always).
    /// An unavailable primitive is not eligible, like a terminated subtask.
    fn available(&self, _node: NodeId, _s: &S) -> bool {
        true
    }
    /// Whether composite `node`, started in `start`, has ended in `now` because of what
    /// happened since it started (e.g. "the robot entered a new cell"). Unlike
    /// [`Hierarchy::terminated`] this does not make the node ineligible. Default: never.
    fn ended_since(&self, _node: NodeId, _start: &S, _now: &S) -> bool {
        false
    }
    /// R̃ᵢ(s): the pseudo-reward of composite `node` when it terminates in `s`.
    fn pseudo_reward(&self, _node: NodeId, _s: &S) -> f64 {
        0.0
    }
    /// A composite node whose executed children also teach `Some(apprentice)` (a composite
    /// with the same children, in the same order): the completion function of the apprentice is
    /// updated with every child the node runs, as if the apprentice had run that child itself
    /// from the state the child started in: it ends (with its pseudo-reward) where it would
    /// have ended ([`Hierarchy::terminated`] or [`Hierarchy::ended_since`] that state). Paper
    /// 000 §IV-A-5: while the operator drives (HC), the navigation subtask learns from the
    /// operator's actions.
    fn apprentice(&self, _node: NodeId) -> Option<NodeId> {
        None
    }
}

/// Learning parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LearningParams {
    /// Discount γ per primitive step.
    pub gamma: f64,
    pub alpha: Schedule,
    pub epsilon: Schedule,
    /// Primitive steps after which an episode is cut off.
    pub max_steps_per_episode: u64,
}

impl LearningParams {
    /// Checks γ ∈ (0, 1], the α and ε schedules ([`Schedule::validate`]) and an episode cut
    /// of at least one step; the error names the field (`gamma`, `alpha.min`, …).
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(self.gamma > 0.0 && self.gamma <= 1.0) {
            return Err(ParamError::new("gamma", self.gamma, "a discount in (0, 1]"));
        }
        self.alpha.validate().map_err(|e| e.within("alpha"))?;
        self.epsilon.validate().map_err(|e| e.within("epsilon"))?;
        if self.max_steps_per_episode == 0 {
            return Err(ParamError::new("max_steps_per_episode", 0, "at least 1"));
        }
        Ok(())
    }
}

/// The outcome of an episode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Episode {
    /// Sum of the (undiscounted) rewards.
    pub reward: f64,
    /// Primitive steps taken.
    pub steps: u64,
    /// Whether the domain reached a terminal state (not cut off).
    pub finished: bool,
}

/// A table with a flag per entry saying whether it was ever written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Table {
    pub values: Vec<f64>,
    pub written: Vec<bool>,
}

impl Table {
    pub(crate) fn new(len: usize) -> Self {
        Self {
            values: vec![0.0; len],
            written: vec![false; len],
        }
    }

    pub(crate) fn update(&mut self, i: usize, alpha: f64, target: f64) {
        self.values[i] = (1.0 - alpha) * self.values[i] + alpha * target;
        self.written[i] = true;
    }

    /// Entries ever written.
    pub fn stored(&self) -> usize {
        self.written.iter().filter(|&&w| w).count()
    }
}

/// The learned value function of a task graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaxqQ {
    pub nodes: Vec<Node>,
    pub params: LearningParams,
    /// V(a, s) of primitive nodes (empty for composites).
    pub v: Vec<Table>,
    /// C(i, s, a) of composite nodes, index `s · children + k`.
    pub c: Vec<Table>,
    /// C̃(i, s, a), with the pseudo-rewards.
    pub c_tilde: Vec<Table>,
    /// Primitive steps learned from so far (drives the schedules).
    pub steps: u64,
}

struct Run<'a, D: Domain> {
    domain: &'a mut D,
    budget: u64,
    episode: Episode,
    /// States in which primitives were executed, in order: a subtask's visited states are the
    /// tail it appended (no allocation per step).
    visited: Vec<D::State>,
}

impl MaxqQ {
    pub fn new(nodes: Vec<Node>, params: LearningParams) -> Self {
        let (mut v, mut c) = (Vec::new(), Vec::new());
        for n in &nodes {
            match &n.kind {
                NodeKind::Primitive { .. } => {
                    v.push(Table::new(n.states));
                    c.push(Table::default());
                }
                NodeKind::Composite { children } => {
                    v.push(Table::default());
                    c.push(Table::new(n.states * children.len()));
                }
            }
        }
        Self {
            c_tilde: c.clone(),
            nodes,
            params,
            v,
            c,
            steps: 0,
        }
    }

    /// Values ever written in V and C (the paper's count of stored Q-values). C̃ is not
    /// counted: it differs from C only where pseudo-rewards are given.
    pub fn stored_values(&self) -> usize {
        self.v.iter().chain(&self.c).map(Table::stored).sum()
    }

    /// The task graph.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The children of node `i` (none for a primitive).
    pub fn children_of(&self, i: NodeId) -> &[NodeId] {
        self.children(i)
    }

    /// The child of composite `i` the greedy policy picks in `s` (its index among the
    /// children), as [`MaxqQ::greedy_episode`] picks it; `None` when no child is eligible.
    pub fn greedy_child<S>(&self, h: &impl Hierarchy<S>, i: NodeId, s: &S) -> Option<usize> {
        self.best_child(h, i, s, true).map(|(k, _)| k)
    }

    fn children(&self, i: NodeId) -> &[NodeId] {
        match &self.nodes[i].kind {
            NodeKind::Composite { children } => children,
            NodeKind::Primitive { .. } => &[],
        }
    }

    fn eligible<S>(&self, h: &impl Hierarchy<S>, child: NodeId, s: &S) -> bool {
        match self.nodes[child].kind {
            NodeKind::Primitive { .. } => h.available(child, s),
            NodeKind::Composite { .. } => !h.terminated(child, s),
        }
    }

    /// V(i, s) (eq. 2): the primitive's expected reward, or the best Q(i, s, a) over eligible
    /// children (0 when none is eligible).
    pub fn value<S>(&self, h: &impl Hierarchy<S>, i: NodeId, s: &S) -> f64 {
        match self.nodes[i].kind {
            NodeKind::Primitive { .. } => self.v[i].values[h.abstraction(i, s)],
            NodeKind::Composite { .. } => self.best_child(h, i, s, false).map_or(0.0, |(_, q)| q),
        }
    }

    /// The eligible child of `i` with the largest Q (with C̃ when `tilde`), lowest index on
    /// ties, and its Q.
    fn best_child<S>(
        &self,
        h: &impl Hierarchy<S>,
        i: NodeId,
        s: &S,
        tilde: bool,
    ) -> Option<(usize, f64)> {
        self.best_child_value(h, i, s, tilde)
            .map(|(k, q, _)| (k, q))
    }

    /// As [`MaxqQ::best_child`], with V(child, s) of the chosen child as well (so that eq. 3
    /// does not evaluate it twice).
    fn best_child_value<S>(
        &self,
        h: &impl Hierarchy<S>,
        i: NodeId,
        s: &S,
        tilde: bool,
    ) -> Option<(usize, f64, f64)> {
        let abs = h.abstraction(i, s);
        let children = self.children(i);
        let table = if tilde { &self.c_tilde[i] } else { &self.c[i] };
        let mut best: Option<(usize, f64, f64)> = None;
        for (k, &a) in children.iter().enumerate() {
            if !self.eligible(h, a, s) {
                continue;
            }
            let v = self.value(h, a, s);
            let q = v + table.values[abs * children.len() + k];
            if best.is_none_or(|(_, b, _)| q > b) {
                best = Some((k, q, v));
            }
        }
        best
    }

    /// One learning episode from `s0`.
    pub fn learn_episode<S: Clone, D: Domain<State = S>>(
        &mut self,
        h: &impl Hierarchy<S>,
        domain: &mut D,
        s0: S,
        rng: &mut impl Rng,
    ) -> Episode {
        let mut run = Run {
            domain,
            budget: self.params.max_steps_per_episode,
            episode: Episode::default(),
            visited: Vec::new(),
        };
        let root = h.root();
        let end = self.maxq_q(h, &mut run, root, s0, rng);
        run.episode.finished = run.domain.is_terminal(&end);
        run.episode
    }

    /// Whether subtask `i`, started in `start`, is over in `s`.
    fn over<S, D: Domain<State = S>>(
        h: &impl Hierarchy<S>,
        run: &Run<'_, D>,
        i: NodeId,
        start: &S,
        s: &S,
    ) -> bool {
        h.terminated(i, s) || h.ended_since(i, start, s) || run.domain.is_terminal(s)
    }

    /// MAXQ-Q(i, s) (Dietterich 2000, Table 4): runs subtask i from s, learning; appends the
    /// states visited to `run.visited` and returns the state it ended in.
    fn maxq_q<S: Clone, D: Domain<State = S>>(
        &mut self,
        h: &impl Hierarchy<S>,
        run: &mut Run<'_, D>,
        i: NodeId,
        s: S,
        rng: &mut impl Rng,
    ) -> S {
        if let NodeKind::Primitive { action } = self.nodes[i].kind {
            let (next, r) = run.domain.step(&s, action);
            let alpha = self.params.alpha.at(self.steps);
            let abs = h.abstraction(i, &s);
            self.v[i].update(abs, alpha, r);
            self.steps += 1;
            run.budget -= 1;
            run.episode.reward += r;
            run.episode.steps += 1;
            run.visited.push(s);
            return next;
        }
        let n_children = self.children(i).len();
        let start = s.clone();
        let mut s = s;
        while !Self::over(h, run, i, &start, &s) && run.budget > 0 {
            let k = match run.domain.delegated_choice(i, &s) {
                Some(k) if k < n_children => k,
                _ => match self.choose(h, i, &s, rng) {
                    Some(k) => k,
                    None => break,
                },
            };
            let child = self.children(i)[k];
            let child_start = run.visited.len();
            let apprentice = h.apprentice(i).map(|j| (j, s.clone()));
            let next = self.maxq_q(h, run, child, s, rng);
            let ended = Self::over(h, run, i, &start, &next);
            self.learn_completion(h, i, k, &run.visited[child_start..], &next, ended);
            if let Some((j, before)) = apprentice {
                // The apprentice learns as if it had run this child itself from `before`:
                // it ends where it would have ended then.
                let ended = Self::over(h, run, j, &before, &next);
                self.learn_completion(h, j, k, &run.visited[child_start..], &next, ended);
            }
            s = next;
        }
        s
    }

    /// Eq. 3 for child k of `i` that ran through `visited` and stopped in `next`: C and C̃ of
    /// every visited state move toward γᴺ times the best continuation from `next` (none when
    /// `i` ended there).
    fn learn_completion<S>(
        &mut self,
        h: &impl Hierarchy<S>,
        i: NodeId,
        k: usize,
        visited: &[S],
        next: &S,
        ended: bool,
    ) {
        let n_children = self.children(i).len();
        let alpha = self.params.alpha.at(self.steps);
        let gamma = self.params.gamma;
        let (target, target_tilde) = if ended {
            (0.0, h.pseudo_reward(i, next))
        } else {
            match self.best_child_value(h, i, next, true) {
                Some((best, _, v)) => {
                    let abs_next = h.abstraction(i, next) * n_children + best;
                    (
                        self.c[i].values[abs_next] + v,
                        self.c_tilde[i].values[abs_next] + v,
                    )
                }
                None => (0.0, 0.0),
            }
        };
        let mut discount = gamma;
        for visited in visited.iter().rev() {
            let idx = h.abstraction(i, visited) * n_children + k;
            self.c_tilde[i].update(idx, alpha, discount * target_tilde);
            self.c[i].update(idx, alpha, discount * target);
            discount *= gamma;
        }
    }

    /// ε-greedy choice among the eligible children of `i` (greedy with respect to C̃).
    fn choose<S>(
        &self,
        h: &impl Hierarchy<S>,
        i: NodeId,
        s: &S,
        rng: &mut impl Rng,
    ) -> Option<usize> {
        let epsilon = self.params.epsilon.at(self.steps);
        if rng.random::<f64>() < epsilon {
            let children = self.children(i);
            let eligible = children.iter().filter(|&&a| self.eligible(h, a, s)).count();
            if eligible == 0 {
                return None;
            }
            let pick = rng.random_range(0..eligible);
            return children
                .iter()
                .enumerate()
                .filter(|&(_, &a)| self.eligible(h, a, s))
                .nth(pick)
                .map(|(k, _)| k);
        }
        self.best_child(h, i, s, true).map(|(k, _)| k)
    }

    /// Runs the learned hierarchical policy greedily from `s0`, without learning.
    pub fn greedy_episode<S: Clone, D: Domain<State = S>>(
        &self,
        h: &impl Hierarchy<S>,
        domain: &mut D,
        s0: S,
    ) -> Episode {
        let mut run = Run {
            domain,
            budget: self.params.max_steps_per_episode,
            episode: Episode::default(),
            visited: Vec::new(),
        };
        let end = self.execute(h, &mut run, h.root(), s0);
        run.episode.finished = run.domain.is_terminal(&end);
        run.episode
    }

    fn execute<S: Clone, D: Domain<State = S>>(
        &self,
        h: &impl Hierarchy<S>,
        run: &mut Run<'_, D>,
        i: NodeId,
        s: S,
    ) -> S {
        if let NodeKind::Primitive { action } = self.nodes[i].kind {
            let (next, r) = run.domain.step(&s, action);
            run.budget -= 1;
            run.episode.reward += r;
            run.episode.steps += 1;
            return next;
        }
        let n_children = self.children(i).len();
        let start = s.clone();
        let mut s = s;
        while !Self::over(h, run, i, &start, &s) && run.budget > 0 {
            let k = match run.domain.delegated_choice(i, &s) {
                Some(k) if k < n_children => k,
                _ => match self.best_child(h, i, &s, true) {
                    Some((k, _)) => k,
                    None => break,
                },
            };
            s = self.execute(h, run, self.children(i)[k], s);
        }
        s
    }
}

/// A domain shown to an observer after each primitive step (a recorder, a viewer): it sees,
/// it does not steer; every other call goes to the domain unchanged.
pub struct Observed<D, F> {
    pub domain: D,
    pub observe: F,
}

impl<D: Domain, F: FnMut(&D)> Domain for Observed<D, F> {
    type State = D::State;

    fn step(&mut self, s: &Self::State, action: usize) -> (Self::State, f64) {
        let out = self.domain.step(s, action);
        (self.observe)(&self.domain);
        out
    }

    fn is_terminal(&self, s: &Self::State) -> bool {
        self.domain.is_terminal(s)
    }

    fn available(&self, s: &Self::State, action: usize) -> bool {
        self.domain.available(s, action)
    }

    fn delegated_choice(&mut self, node: NodeId, s: &Self::State) -> Option<usize> {
        self.domain.delegated_choice(node, s)
    }
}

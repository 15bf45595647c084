//! The learned hierarchical policy one primitive at a time, for a controller that cannot run
//! an episode in one call: a robot on a shared simulator or a real one executes a primitive
//! over many control steps, and an operator's answer to a hand-off arrives later.
//!
//! [`GreedyStepper`] keeps the stack of subtasks that [`MaxqQ::greedy_episode`] keeps on the
//! call stack, so stepping it through a domain gives the same primitives, in the same order.

use crate::maxq::{Hierarchy, MaxqQ, NodeId, NodeKind};

/// What the policy does next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Next {
    /// Execute this primitive action, then call [`GreedyStepper::next`] with the state it led to.
    Act(usize),
    /// A delegated choice is not answered yet: call again later with the same state.
    Wait,
    /// The root subtask is over (or the step budget is spent).
    Finished,
}

/// A choice at a composite node made outside the learner (paper 000 §IV-A-5: the operator's
/// answer to a hand-off).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Delegation {
    /// The learner chooses.
    Learner,
    /// This child (its index among the node's children).
    Child(usize),
    /// The choice is someone else's and they have not answered yet.
    Pending,
}

/// The greedy policy's place in the task graph: the subtasks entered and the states they
/// started in.
#[derive(Clone, Debug)]
pub struct GreedyStepper<S> {
    stack: Vec<(NodeId, S)>,
    started: bool,
    budget: u64,
}

impl<S: Clone> GreedyStepper<S> {
    /// A run of at most `max_steps` primitives.
    pub fn new(max_steps: u64) -> Self {
        Self {
            stack: Vec::new(),
            started: false,
            budget: max_steps,
        }
    }

    /// The subtasks entered, root first.
    pub fn active(&self) -> impl Iterator<Item = NodeId> + '_ {
        self.stack.iter().map(|(i, _)| *i)
    }

    /// The next primitive in state `s` (`terminal`: the domain's episode has ended in `s`).
    /// `delegate` is asked at each composite's choice, like [`crate::Domain::delegated_choice`].
    pub fn next(
        &mut self,
        q: &MaxqQ,
        h: &impl Hierarchy<S>,
        s: &S,
        terminal: bool,
        mut delegate: impl FnMut(NodeId, &S) -> Delegation,
    ) -> Next {
        if !self.started {
            self.started = true;
            self.stack.push((h.root(), s.clone()));
        }
        loop {
            let Some((i, start)) = self.stack.last() else {
                return Next::Finished;
            };
            let i = *i;
            if terminal || self.budget == 0 || h.terminated(i, s) || h.ended_since(i, start, s) {
                self.stack.pop();
                continue;
            }
            let children = q.children_of(i);
            let k = match delegate(i, s) {
                Delegation::Child(k) if k < children.len() => k,
                Delegation::Pending => return Next::Wait,
                _ => match q.greedy_child(h, i, s) {
                    Some(k) => k,
                    None => {
                        self.stack.pop();
                        continue;
                    }
                },
            };
            let child = children[k];
            match q.nodes()[child].kind {
                NodeKind::Primitive { action } => {
                    self.budget -= 1;
                    return Next::Act(action);
                }
                NodeKind::Composite { .. } => self.stack.push((child, s.clone())),
            }
        }
    }
}

//! An apprentice subtask learns from the children its teacher runs as if it had run them
//! itself: it ends, with its pseudo-reward, where it would have ended.

use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use usar_maxq::{Domain, Hierarchy, LearningParams, MaxqQ, Node, NodeId, NodeKind, Schedule};

const ROOT: NodeId = 0;
const LEARNER: NodeId = 1;
const TEACHER: NodeId = 2;
const STEP: NodeId = 3;
const PSEUDO: f64 = 10.0;
const GAMMA: f64 = 0.9;

/// A corridor of three cells: one action moves one cell on (reward −1); the last cell ends
/// the episode.
struct Corridor;

impl Domain for Corridor {
    type State = u8;
    fn step(&mut self, s: &u8, _action: usize) -> (u8, f64) {
        (s + 1, -1.0)
    }
    fn is_terminal(&self, s: &u8) -> bool {
        *s >= 2
    }
    /// The root always hands over to the teacher, whose only child is the step.
    fn delegated_choice(&mut self, node: NodeId, _s: &u8) -> Option<usize> {
        match node {
            ROOT => Some(1),
            TEACHER => Some(0),
            _ => None,
        }
    }
}

/// Root → {Learner, Teacher} → Step; the learner ends once the cell changed (as NG does), the
/// teacher only at the end of the corridor.
struct Graph(Vec<Node>);

impl Hierarchy<u8> for Graph {
    fn nodes(&self) -> &[Node] {
        &self.0
    }
    fn root(&self) -> NodeId {
        ROOT
    }
    fn abstraction(&self, _node: NodeId, s: &u8) -> usize {
        usize::from(*s)
    }
    fn terminated(&self, _node: NodeId, _s: &u8) -> bool {
        false
    }
    fn ended_since(&self, node: NodeId, start: &u8, now: &u8) -> bool {
        node == LEARNER && start != now
    }
    fn pseudo_reward(&self, node: NodeId, _s: &u8) -> f64 {
        if node == LEARNER { PSEUDO } else { 0.0 }
    }
    fn apprentice(&self, node: NodeId) -> Option<NodeId> {
        (node == TEACHER).then_some(LEARNER)
    }
}

#[test]
fn the_apprentice_ends_where_it_would_have_ended() {
    let composite = |name: &str, children: Vec<NodeId>| Node {
        name: name.into(),
        kind: NodeKind::Composite { children },
        states: 3,
    };
    let graph = Graph(vec![
        composite("Root", vec![LEARNER, TEACHER]),
        composite("Learner", vec![STEP]),
        composite("Teacher", vec![STEP]),
        Node {
            name: "Step".into(),
            kind: NodeKind::Primitive { action: 0 },
            states: 3,
        },
    ]);
    let params = LearningParams {
        gamma: GAMMA,
        alpha: Schedule::constant(1.0),
        epsilon: Schedule::constant(0.0),
        max_steps_per_episode: 10,
    };
    let mut q = MaxqQ::new(graph.0.clone(), params);
    let mut rng = Pcg64Mcg::seed_from_u64(1);
    let episode = q.learn_episode(&graph, &mut Corridor, 0, &mut rng);
    assert_eq!(episode.steps, 2);
    // Each step the teacher took moved the robot on: for the learner the step ended it, so
    // its completion is the pseudo-reward alone (C̃ = γ·R̃, C = 0), not a continuation.
    for s in 0..2 {
        assert_eq!(q.c_tilde[LEARNER].values[s], GAMMA * PSEUDO, "state {s}");
        assert_eq!(q.c[LEARNER].values[s], 0.0, "state {s}");
        assert!(q.c_tilde[LEARNER].written[s]);
    }
}

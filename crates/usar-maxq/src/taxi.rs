//! Dietterich's Taxi domain (Dietterich 2000, §3.1): the correctness check of the MAXQ engine.
//!
//! A 5 × 5 grid with walls and four depots R, G, Y, B. A passenger waits at one depot and
//! wants to go to one of the four (possibly the same one). Actions North, South, East, West,
//! Pickup, Putdown; every action costs −1, a successful Putdown at the destination gives +20
//! (instead of −1) and ends the episode, an illegal Pickup or Putdown costs −10.
//!
//! ```text
//! +---------+        row 0 is the top row, as in Dietterich's figure
//! |R: | : :G|
//! | : | : : |
//! | : : : : |
//! | | : | : |
//! |Y| : |B: |
//! +---------+
//! ```
//!
//! The task graph (Dietterich's Fig. 2): Root → {Get, Put}; Get → {Pickup, Navigate(t)};
//! Put → {Putdown, Navigate(t)}; Navigate(t) → {North, South, East, West} for the four depots t,
//! with his state abstractions: Navigate(t) sees only the taxi's cell, Get the taxi's cell and
//! the passenger's location, Put the taxi's cell and the destination, Root the passenger's
//! location and the destination.

use crate::flat_q::FlatQ;
use crate::maxq::{Domain, Episode, Hierarchy, LearningParams, MaxqQ, Node, NodeId, NodeKind};
use crate::schedule::Schedule;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::Serialize;

/// Depots (row, column): R, G, Y, B.
pub const DEPOTS: [(u8, u8); 4] = [(0, 0), (0, 4), (4, 0), (4, 3)];
/// The passenger location meaning "in the taxi".
pub const IN_TAXI: u8 = 4;
pub const NORTH: usize = 0;
pub const SOUTH: usize = 1;
pub const EAST: usize = 2;
pub const WEST: usize = 3;
pub const PICKUP: usize = 4;
pub const PUTDOWN: usize = 5;
/// Number of flat states: 25 taxi cells × 5 passenger locations × 4 destinations.
pub const STATES: usize = 500;

/// A Taxi state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct TaxiState {
    pub row: u8,
    pub col: u8,
    /// A depot index 0–3, or [`IN_TAXI`].
    pub passenger: u8,
    /// A depot index 0–3; 255 once delivered (terminal).
    pub destination: u8,
}

impl TaxiState {
    pub fn taxi_cell(&self) -> usize {
        usize::from(self.row) * 5 + usize::from(self.col)
    }

    /// Index in `0..STATES` (terminal states share the index of their last live state).
    pub fn index(&self) -> usize {
        (self.taxi_cell() * 5 + usize::from(self.passenger)) * 4 + usize::from(self.destination % 4)
    }

    pub fn delivered(&self) -> bool {
        self.destination == 255
    }
}

/// Whether a wall blocks moving east from (row, col) (the bars of the map).
fn wall_east(row: u8, col: u8) -> bool {
    matches!(
        (row, col),
        (0, 1) | (1, 1) | (3, 0) | (4, 0) | (3, 2) | (4, 2)
    )
}

/// The Taxi environment (deterministic).
#[derive(Clone, Copy, Debug, Default)]
pub struct Taxi;

impl Domain for Taxi {
    type State = TaxiState;

    fn step(&mut self, s: &TaxiState, action: usize) -> (TaxiState, f64) {
        let mut n = *s;
        let at = |d: u8| DEPOTS[usize::from(d)] == (s.row, s.col);
        let reward = match action {
            NORTH => {
                n.row = s.row.saturating_sub(1);
                -1.0
            }
            SOUTH => {
                n.row = (s.row + 1).min(4);
                -1.0
            }
            EAST => {
                if s.col < 4 && !wall_east(s.row, s.col) {
                    n.col += 1;
                }
                -1.0
            }
            WEST => {
                if s.col > 0 && !wall_east(s.row, s.col - 1) {
                    n.col -= 1;
                }
                -1.0
            }
            PICKUP if s.passenger < IN_TAXI && at(s.passenger) => {
                n.passenger = IN_TAXI;
                -1.0
            }
            PUTDOWN if s.passenger == IN_TAXI && at(s.destination) => {
                n.passenger = s.destination;
                n.destination = 255;
                20.0
            }
            _ => -10.0,
        };
        (n, reward)
    }

    fn is_terminal(&self, s: &TaxiState) -> bool {
        s.delivered()
    }
}

/// Node ids of the Taxi task graph.
const ROOT: NodeId = 0;
const GET: NodeId = 1;
const PUT: NodeId = 2;
const NAV: NodeId = 3; // NAV + t for depot t
const PRIM: NodeId = 7; // PRIM + action

/// Dietterich's Taxi hierarchy.
pub struct TaxiHierarchy {
    nodes: Vec<Node>,
}

impl Default for TaxiHierarchy {
    fn default() -> Self {
        let prim = |a: usize, name: &str, states: usize| Node {
            name: name.into(),
            kind: NodeKind::Primitive { action: a },
            states,
        };
        let nav: Vec<NodeId> = (0..4).map(|t| NAV + t).collect();
        let mut nodes = vec![
            Node {
                name: "Root".into(),
                kind: NodeKind::Composite {
                    children: vec![GET, PUT],
                },
                states: 5 * 4,
            },
            Node {
                name: "Get".into(),
                kind: NodeKind::Composite {
                    children: [vec![PRIM + PICKUP], nav.clone()].concat(),
                },
                states: 25 * 5,
            },
            Node {
                name: "Put".into(),
                kind: NodeKind::Composite {
                    children: [vec![PRIM + PUTDOWN], nav].concat(),
                },
                states: 25 * 4,
            },
        ];
        for t in ["R", "G", "Y", "B"] {
            nodes.push(Node {
                name: format!("Navigate({t})"),
                kind: NodeKind::Composite {
                    children: (PRIM..PRIM + 4).collect(),
                },
                states: 25,
            });
        }
        // Moves cost −1 whatever the state: one value each. Pickup and Putdown depend on the
        // taxi's cell, the passenger and (Putdown) the destination.
        nodes.extend([
            prim(NORTH, "North", 1),
            prim(SOUTH, "South", 1),
            prim(EAST, "East", 1),
            prim(WEST, "West", 1),
            prim(PICKUP, "Pickup", 25 * 5),
            prim(PUTDOWN, "Putdown", 25 * 5 * 4),
        ]);
        Self { nodes }
    }
}

impl Hierarchy<TaxiState> for TaxiHierarchy {
    fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    fn root(&self) -> NodeId {
        ROOT
    }

    fn abstraction(&self, node: NodeId, s: &TaxiState) -> usize {
        let (cell, p, d) = (
            s.taxi_cell(),
            usize::from(s.passenger),
            usize::from(s.destination % 4),
        );
        match node {
            ROOT => p * 4 + d,
            GET => cell * 5 + p,
            PUT => cell * 4 + d,
            n if (NAV..NAV + 4).contains(&n) => cell,
            n if n == PRIM + PICKUP => cell * 5 + p,
            n if n == PRIM + PUTDOWN => (cell * 5 + p) * 4 + d,
            _ => 0,
        }
    }

    fn terminated(&self, node: NodeId, s: &TaxiState) -> bool {
        match node {
            ROOT => s.delivered(),
            GET => s.passenger == IN_TAXI || s.delivered(),
            PUT => s.passenger != IN_TAXI,
            n if (NAV..NAV + 4).contains(&n) => (s.row, s.col) == DEPOTS[n - NAV],
            _ => false,
        }
    }
}

/// A random start: taxi anywhere, passenger at a depot, destination any depot.
pub fn random_start(rng: &mut impl Rng) -> TaxiState {
    TaxiState {
        row: rng.random_range(0..5),
        col: rng.random_range(0..5),
        passenger: rng.random_range(0..4),
        destination: rng.random_range(0..4),
    }
}

/// V*(s) for every state by value iteration on the flat MDP (γ = 1, deterministic), indexed
/// by [`TaxiState::index`].
pub fn optimal_values() -> Vec<f64> {
    let mut taxi = Taxi;
    let states: Vec<TaxiState> = (0..5u8)
        .flat_map(|row| {
            (0..5u8).flat_map(move |col| {
                (0..5u8).flat_map(move |passenger| {
                    (0..4u8).map(move |destination| TaxiState {
                        row,
                        col,
                        passenger,
                        destination,
                    })
                })
            })
        })
        .collect();
    let mut v = vec![0.0; STATES];
    loop {
        let mut change = 0.0f64;
        for s in &states {
            let best = (0..6)
                .map(|a| {
                    let (n, r) = taxi.step(s, a);
                    r + if n.delivered() { 0.0 } else { v[n.index()] }
                })
                .fold(f64::NEG_INFINITY, f64::max);
            change = change.max((best - v[s.index()]).abs());
            v[s.index()] = best;
        }
        if change < 1e-12 {
            return v;
        }
    }
}

/// Settings of the Taxi experiment.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TaxiConfig {
    pub seed: u64,
    /// Learning episodes per learner.
    pub episodes: u64,
    /// Random starts the greedy policies are evaluated on.
    pub eval_starts: usize,
    /// Evaluate every this many episodes to find when a learner first reaches the optimum.
    pub eval_every: u64,
    pub params: LearningParams,
}

impl Default for TaxiConfig {
    fn default() -> Self {
        Self {
            seed: 1,
            episodes: 4000,
            eval_starts: 1000,
            eval_every: 25,
            params: LearningParams {
                gamma: 1.0,
                // Chosen on seeds 1–6: MAXQ reaches the optimum after 475–1000 episodes, flat Q
                // after 1800–2400; with ε falling to 0.05 within 10 000 steps MAXQ's Navigate
                // subtasks stop exploring before their far cells converge.
                alpha: Schedule::constant(0.5),
                epsilon: Schedule {
                    start: 1.0,
                    decrement: 0.01,
                    every_steps: 300,
                    min: 0.1,
                },
                max_steps_per_episode: 500,
            },
        }
    }
}

/// The outcome of `usar maxq taxi`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TaxiReport {
    pub config: TaxiConfig,
    /// Mean optimal return over the evaluation starts (value iteration on the flat MDP).
    pub optimal_return: f64,
    /// Mean return of the greedy hierarchical policy after training, same starts.
    pub maxq_return: f64,
    /// Mean return of the greedy flat Q policy after training, same starts.
    pub flat_return: f64,
    /// First evaluation (in episodes) at which the greedy policy came within 0.5 of the
    /// optimum; `None` if it never did.
    pub maxq_episodes_to_optimal: Option<u64>,
    pub flat_episodes_to_optimal: Option<u64>,
    pub maxq_stored_values: usize,
    pub flat_stored_values: usize,
    /// Mean greedy return after every `eval_every` episodes: (episode, MAXQ, flat).
    pub curve: Vec<(u64, f64, f64)>,
}

/// Trains MAXQ-Q and flat Q on Taxi with the same seed and schedules, and compares their greedy
/// policies with the optimum.
pub fn run_taxi(config: &TaxiConfig) -> TaxiReport {
    let mut rng = Pcg64Mcg::seed_from_u64(config.seed);
    let starts: Vec<TaxiState> = (0..config.eval_starts)
        .map(|_| random_start(&mut rng))
        .collect();
    let optimal = optimal_values();
    let mean = |xs: &mut dyn Iterator<Item = f64>| {
        let (sum, n) = xs.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
        sum / n.max(1) as f64
    };
    let optimal_return = mean(&mut starts.iter().map(|s| optimal[s.index()]));
    let h = TaxiHierarchy::default();
    let mut maxq = MaxqQ::new(h.nodes().to_vec(), config.params.clone());
    let mut flat = FlatQ::new(STATES, 6, config.params.clone());
    let (mut maxq_rng, mut flat_rng) = (
        Pcg64Mcg::seed_from_u64(config.seed ^ 0x6d61_7871),
        Pcg64Mcg::seed_from_u64(config.seed ^ 0x666c_6174),
    );
    let mut taxi = Taxi;
    let evaluate_maxq = |m: &MaxqQ| {
        let mut t = Taxi;
        mean(
            &mut starts
                .iter()
                .map(|&s| m.greedy_episode(&h, &mut t, s).reward),
        )
    };
    let evaluate_flat = |f: &FlatQ| {
        let mut t = Taxi;
        mean(
            &mut starts
                .iter()
                .map(|&s| f.greedy_episode(&mut t, TaxiState::index, s).reward),
        )
    };
    let (mut maxq_at, mut flat_at) = (None, None);
    let mut curve = Vec::new();
    for episode in 1..=config.episodes {
        let s0 = random_start(&mut maxq_rng);
        let _: Episode = maxq.learn_episode(&h, &mut taxi, s0, &mut maxq_rng);
        let s0 = random_start(&mut flat_rng);
        flat.learn_episode(&mut taxi, TaxiState::index, s0, &mut flat_rng);
        if episode % config.eval_every.max(1) == 0 {
            let (m, f) = (evaluate_maxq(&maxq), evaluate_flat(&flat));
            if maxq_at.is_none() && m >= optimal_return - 0.5 {
                maxq_at = Some(episode);
            }
            if flat_at.is_none() && f >= optimal_return - 0.5 {
                flat_at = Some(episode);
            }
            curve.push((episode, m, f));
        }
    }
    TaxiReport {
        config: config.clone(),
        optimal_return,
        maxq_return: evaluate_maxq(&maxq),
        flat_return: evaluate_flat(&flat),
        maxq_episodes_to_optimal: maxq_at,
        flat_episodes_to_optimal: flat_at,
        maxq_stored_values: maxq.stored_values(),
        flat_stored_values: flat.stored_values(),
        curve,
    }
}

//! The USAR domain of paper 000 as a MAXQ [`Domain`]: a cell robot in a rubble scene, its own
//! cell map built by its sensors, the direction-based exploration, possible victims and the
//! operator behind the hand-off interface.
//!
//! **Actions**: F, B, rotate left θ, rotate right θ (θ = 90°), Tag, Reject (the operator's
//! answer in HC₂), Exit USAR Scene.
//!
//! **Rewards** (Table I, [`crate::rewards`]), recognised as follows:
//! - a move into an unvisited cell along the exploration heading: +15; into an unvisited cell
//!   off it: 0; into a visited cell: −1;
//! - a move that does not take effect because the tracks slip on climbable rubble: −1 (the
//!   robot stays in visited area); a turn: −1, except a turn right after driving forward up
//!   to an obstacle (the robot turns instead of colliding): +10 ("avoiding an obstacle"), once
//!   per obstacle cell;
//! - a move into non-climbable rubble, a drop, a victim or the boundary: −20 (the robot stays);
//! - Tag at a possible victim that is a real, untagged victim: +10; any other Tag: −10;
//! - Exit with no cell of interest left: +10, plus +100 (Root) when no possible victim is left
//!   undecided; Exit earlier: −10. Exit ends the episode.
//!
//! **Hand-offs**: after `stuck_after_slips` slips in a row the robot is stuck and asks the
//! operator to drive (HC₃) until a command takes effect; after `stuck_after_idle_steps`
//! navigation primitives without exploration progress it is stuck too and the operator drives
//! until progress is made; a possible victim at hand with 0.3 ≤ p ≤ 0.7 is handed to the
//! operator (HC₂).

use crate::agent::{Begun, RescueAgent, tag_reward};
use crate::exploration::{Direction, ExplorationWeights, Guidance};
use crate::hierarchy;
use crate::operator::{HandOff, NavigationRequest, VictimDecision, VictimRequest};
use crate::perception::Perception;
use crate::state::RescueState;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use usar_maxq::{Domain, NodeId};
use usar_sim::sensors::HeatTruth;
use usar_sim::{CellAction, CellOutcome};
use usar_world::cellview::{CellClass, CellView, CellViewParams};
use usar_world::{Cell, Scene};

/// A scene prepared for the cell robot: its cell view and where the victims lie.
pub struct RescueScene {
    pub scene: Scene,
    pub view: CellView,
    /// Cells holding a real victim (row-major): the robot must never enter them.
    pub victim_cell: Vec<bool>,
}

impl RescueScene {
    pub fn new(scene: Scene) -> Self {
        let view = CellView::from_scene(&scene, &CellViewParams::default());
        let mut victim_cell = vec![false; view.classes.len()];
        for v in &scene.victims {
            if let Some(c) = view.cell_of(v.position) {
                victim_cell[view.geometry.index(c)] = true;
            }
        }
        Self {
            scene,
            view,
            victim_cell,
        }
    }

    /// The start cell and heading (0–3, counter-clockwise from east) of start pose `k`.
    pub fn start(&self, k: usize) -> Option<(Cell, u8)> {
        let pose = self.scene.start_poses.get(k)?;
        let cell = self.view.cell_of(pose.position())?;
        let quarter = (pose.theta / std::f64::consts::FRAC_PI_2).round() as i64;
        Some((cell, quarter.rem_euclid(4) as u8))
    }

    /// Ground truth for scoring: cells a climbing robot can reach from `start` without entering
    /// a victim's cell, and the victims lying next to one of them.
    pub fn reachable(&self, start: Cell) -> (Vec<bool>, Vec<u32>) {
        let view = &self.view;
        let mut mask = vec![false; view.classes.len()];
        let passable =
            |i: usize| view.terrain_classes[i].is_passable_terrain(true) && !self.victim_cell[i];
        let Some(s) = view.index(start).filter(|&s| passable(s)) else {
            return (mask, Vec::new());
        };
        let mut stack = vec![s];
        mask[s] = true;
        while let Some(i) = stack.pop() {
            let c = view.geometry.cell_of_index(i);
            for d in Direction::ALL {
                let (dc, dr) = d.step();
                if let Some(k) = view.index(Cell::new(c.col + dc, c.row + dr))
                    && !mask[k]
                    && passable(k)
                {
                    mask[k] = true;
                    stack.push(k);
                }
            }
        }
        let victims = self
            .scene
            .victims
            .iter()
            .filter(|v| {
                view.cell_of(v.position).is_some_and(|c| {
                    Direction::ALL.iter().any(|d| {
                        let (dc, dr) = d.step();
                        view.index(Cell::new(c.col + dc, c.row + dr))
                            .is_some_and(|k| mask[k])
                    })
                })
            })
            .map(|v| v.id)
            .collect();
        (mask, victims)
    }
}

/// Physical and timing parameters of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DomainConfig {
    /// Probability that a move onto climbable rubble does not take effect (tracks slip).
    pub slip_probability: f64,
    /// Slips in a row after which the robot is stuck and hands navigation to the operator.
    pub stuck_after_slips: u32,
    /// Navigation primitives of the robot without exploration progress after which it is
    /// stuck too ("unable to navigate autonomously", §IV-A-5): the operator drives until
    /// progress is made.
    #[serde(default = "default_idle_steps")]
    pub stuck_after_idle_steps: u32,
    /// Seconds per primitive action while the robot is in control.
    pub robot_step_s: f64,
}

impl Default for DomainConfig {
    /// Slips 0.3 and stuck after 2 in a row: on a scene with ~30 climbable cells a robot is
    /// stuck about three times per run, close to the paper's "on average ... five times"
    /// hand-offs of both kinds (§VII-B). 1.5 s per primitive.
    fn default() -> Self {
        Self {
            slip_probability: 0.3,
            stuck_after_slips: 2,
            stuck_after_idle_steps: default_idle_steps(),
            robot_step_s: 1.5,
        }
    }
}

/// 40 primitives: twice the longest straight path across the 20 × 20 arena.
fn default_idle_steps() -> u32 {
    40
}

/// What a run did (ground truth used only here, for scoring).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RunStats {
    /// Navigation primitives (F, B, rotations) executed, by robot and operator.
    pub steps: u64,
    pub robot_collisions: u32,
    pub operator_collisions: u32,
    pub victims_found: u32,
    pub false_tags: u32,
    pub handoffs_stuck: u32,
    pub handoffs_victim: u32,
    pub time_s: f64,
}

/// What became of a possible victim, as an operator display shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VictimMark {
    /// Not decided yet.
    Pending,
    /// Tagged as a victim (by the robot or the operator).
    Tagged,
    /// Rejected or dismissed (p below the dismiss threshold).
    Dismissed,
}

/// See the [module documentation](self): the robot's mind ([`RescueAgent`]) on a scene's
/// cell physics and sensors, with an operator behind the hand-off interface.
pub struct RescueDomain<'a, O: HandOff> {
    scene: &'a RescueScene,
    perception: Perception,
    /// What the robot knows and decides; its `stats` are the run's.
    pub agent: RescueAgent<HeatTruth>,
    pub operator: O,
    config: DomainConfig,
    rng: Pcg64Mcg,
}

impl<'a, O: HandOff> RescueDomain<'a, O> {
    /// A run from `start` (cell, heading 0–3) with the robot's and the sensors' streams from
    /// `seed`.
    pub fn new(
        scene: &'a RescueScene,
        start: (Cell, u8),
        weights: ExplorationWeights,
        config: DomainConfig,
        operator: O,
        seed: u64,
    ) -> Self {
        let perception = Self::perception(scene, start, seed);
        Self::with_perception(scene, start, weights, config, operator, seed, perception)
    }

    /// The sensors a run from `start` with `seed` uses (see [`RescueDomain::with_perception`]).
    pub fn perception(scene: &RescueScene, start: (Cell, u8), seed: u64) -> Perception {
        Perception::new(&scene.scene, &scene.view, start.0, seed ^ 0x5eed_0000_d15e)
    }

    /// As [`RescueDomain::new`] with sensors prepared beforehand (e.g. with
    /// [`Perception::sense_all`]).
    pub fn with_perception(
        scene: &'a RescueScene,
        start: (Cell, u8),
        weights: ExplorationWeights,
        config: DomainConfig,
        operator: O,
        seed: u64,
        mut perception: Perception,
    ) -> Self {
        let view = &scene.view;
        let i = view.geometry.index(start.0);
        let mut agent = RescueAgent::new(
            view.cols as i32,
            view.rows as i32,
            start,
            weights,
            config.clone(),
            view.terrain_classes[i],
        );
        agent.start(perception.read(&scene.scene, view, start.0, direction(start.1)));
        let mut d = Self {
            scene,
            perception,
            agent,
            operator,
            config,
            rng: Pcg64Mcg::seed_from_u64(seed),
        };
        d.charge_handoffs();
        d
    }

    /// Switches to the teleoperated mode: the operator chooses every command and identifies
    /// victims by looking; the robot only reports what its sensors show.
    pub fn teleoperated(mut self) -> Self {
        self.agent.set_teleoperated();
        self
    }

    /// The current observation of the engine.
    pub fn state(&self) -> RescueState {
        self.agent.state()
    }

    pub fn guidance(&self) -> &Guidance {
        self.agent.guidance()
    }

    /// Each hand-off the robot asked for costs the operator's response time.
    fn charge_handoffs(&mut self) {
        for _ in 0..self.agent.take_handoffs_asked() {
            self.agent.stats.time_s += self.operator.response_delay_s();
        }
    }

    /// Executes one primitive action (see [`hierarchy::action`]) and returns its reward.
    pub fn act(&mut self, a: usize) -> f64 {
        let reward = match self.agent.begin(a) {
            Begun::Done(r) => r,
            Begun::Tagged(source) => {
                match source {
                    Some(HeatTruth::Victim(_)) => self.agent.stats.victims_found += 1,
                    Some(HeatTruth::Other(_)) => self.agent.stats.false_tags += 1,
                    None => {}
                }
                tag_reward(source)
            }
            Begun::Move(m) => {
                self.agent.stats.time_s += if m.by_operator {
                    self.operator.command_time_s()
                } else {
                    self.config.robot_step_s
                };
                let outcome = self.drive(m.action);
                let scene = self.scene;
                let view = &scene.view;
                let cell = self.agent.robot.cell;
                let felt = view.terrain_classes[view.geometry.index(cell)];
                let heading = direction(self.agent.robot.heading);
                let reading = self.perception.read(&scene.scene, view, cell, heading);
                self.agent.finish(m, outcome, felt, reading)
            }
        };
        self.charge_handoffs();
        reward
    }

    /// The cell physics: the robot never enters a victim's cell, and its tracks slip on
    /// climbable rubble with `slip_probability`.
    fn drive(&mut self, act: CellAction) -> CellOutcome {
        let scene = self.scene;
        let slip = self.config.slip_probability;
        let rng = &mut self.rng;
        let victim_cell = &scene.victim_cell;
        let view = &scene.view;
        let (w, h) = (view.cols as i32, view.rows as i32);
        self.agent.robot.apply_with(
            act,
            view,
            |c| {
                c.col >= 0
                    && c.row >= 0
                    && c.col < w
                    && c.row < h
                    && victim_cell[(c.row * w + c.col) as usize]
            },
            |_| rng.random::<f64>() < slip,
        )
    }

    /// What the operator is shown when asked to drive.
    pub fn navigation_request(&self) -> NavigationRequest {
        let c = self.agent.robot.cell;
        let view = &self.scene.view;
        let mut camera = [(CellClass::NonClimbable, false); 4];
        for d in Direction::ALL {
            let (dc, dr) = d.step();
            let n = Cell::new(c.col + dc, c.row + dr);
            camera[d.index()] = (
                view.terrain_class(n),
                view.index(n).is_some_and(|i| self.scene.victim_cell[i]),
            );
        }
        self.agent.navigation_request(camera)
    }

    /// The uncertain victim at hand, as shown to the operator.
    pub fn victim_request(&self) -> Option<VictimRequest> {
        self.agent.uncertain_victim().map(|v| VictimRequest {
            cell: v.cell,
            probability: v.probability,
            size_m2: v.size_m2,
            truth: v.source,
        })
    }

    /// Replaces the exploration weights while the robot runs (see
    /// [`RescueAgent::set_exploration_weights`]).
    pub fn set_exploration_weights(&mut self, weights: ExplorationWeights) {
        self.agent.set_exploration_weights(weights);
        self.charge_handoffs();
    }

    /// The possible victims met so far: cell, status and measured probability (if measured).
    pub fn possible_victims(
        &self,
    ) -> impl Iterator<Item = ((i32, i32), VictimMark, Option<f64>)> + '_ {
        self.agent.possible_victims()
    }

    /// The scene the run is on (ground truth: for evaluation and pictures).
    pub fn scene(&self) -> &RescueScene {
        self.scene
    }

    /// Whether the robot is stuck (its navigation is handed to the operator).
    pub fn is_stuck(&self) -> bool {
        self.agent.is_stuck()
    }

    /// Whether the run is over (the robot exited).
    pub fn is_done(&self) -> bool {
        self.agent.is_done()
    }

    /// Cells the robot has visited (row-major).
    pub fn visited(&self) -> impl Iterator<Item = bool> + '_ {
        self.agent.visited()
    }

    /// The operator's answer to a hand-off at `node`, if `node` is an HC node.
    fn operator_choice(&mut self, node: NodeId) -> Option<usize> {
        match node {
            hierarchy::HC_SHARE => {
                let request = self.victim_request()?;
                self.agent.operator_takes_turn();
                Some(match self.operator.identify_victim(&request) {
                    VictimDecision::Tag => 0,
                    VictimDecision::Reject => 1,
                })
            }
            hierarchy::HC_NAV => {
                let request = self.navigation_request();
                self.agent.operator_takes_turn();
                Some(match self.operator.drive(&request) {
                    CellAction::Forward => 0,
                    CellAction::Backward => 1,
                    CellAction::RotateLeft => 2,
                    CellAction::RotateRight => 3,
                })
            }
            _ => None,
        }
    }
}

/// Heading `h` (0–3, counter-clockwise from east) as a direction.
fn direction(h: u8) -> Direction {
    Direction::from_index(usize::from(h))
}

impl<O: HandOff> Domain for RescueDomain<'_, O> {
    type State = RescueState;

    fn step(&mut self, _s: &RescueState, action: usize) -> (RescueState, f64) {
        let r = self.act(action);
        (self.state(), r)
    }

    fn is_terminal(&self, s: &RescueState) -> bool {
        s.done()
    }

    fn delegated_choice(&mut self, node: NodeId, _s: &RescueState) -> Option<usize> {
        self.operator_choice(node)
    }
}

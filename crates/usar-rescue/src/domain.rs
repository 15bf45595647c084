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

use crate::cell_map::{CellMap, MapCell};
use crate::exploration::{Direction, ExplorationWeights, Explorer, Guidance};
use crate::hierarchy::{self, action};
use crate::operator::{HandOff, NavigationRequest, VictimDecision, VictimRequest};
use crate::perception::{
    DISMISS_THRESHOLD, INFRARED_NEIGHBOURS, Perception, TAG_THRESHOLD, victim_probability,
};
use crate::rewards;
use crate::state::{RescueState, VictimStatus};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use usar_maxq::{Domain, NodeId};
use usar_sim::sensors::HeatTruth;
use usar_sim::{CellAction, CellOutcome, CellRobot, RotationStep};
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

#[derive(Clone, Copy, Debug, PartialEq)]
enum Status {
    Pending,
    CertainAtHand,
    UncertainAtHand,
    Tagged,
    Rejected,
}

#[derive(Clone, Copy, Debug)]
struct PossibleVictim {
    cell: (i32, i32),
    truth: HeatTruth,
    /// Size of the warm region when first seen, m².
    first_size_m2: f64,
    probability: Option<f64>,
    status: Status,
}

/// See the [module documentation](self).
pub struct RescueDomain<'a, O: HandOff> {
    scene: &'a RescueScene,
    perception: Perception,
    pub robot: CellRobot,
    pub map: CellMap,
    explorer: Explorer,
    guidance: Guidance,
    victims: Vec<PossibleVictim>,
    /// The possible victim being dealt with and the heading toward it.
    current: Option<(usize, Option<Direction>)>,
    pub operator: O,
    config: DomainConfig,
    rng: Pcg64Mcg,
    avoided: Vec<bool>,
    slips_in_row: u32,
    /// The robot drove forward into its cell and found an obstacle ahead: turning now avoids it.
    facing_obstacle_after_move: bool,
    stuck: bool,
    /// The guidance and the victim to deal with must be recomputed (the map, the robot's cell
    /// or a victim's status changed since).
    stale: bool,
    /// Zobrist hash of the robot's whole map M (the flat learner's state includes M).
    map_hash: u64,
    progress: u32,
    /// The last primitive moved the robot one cell along the desired heading or made progress.
    on_course: bool,
    /// The last navigation primitive collided.
    collided: bool,
    /// The robot's navigation primitives since the last exploration progress.
    idle_steps: u32,
    /// Stuck for want of progress (cleared by progress, not by a move).
    stuck_idle: bool,
    operator_turn: bool,
    /// The last navigation primitive was the operator's.
    operator_drove: bool,
    done: bool,
    pub stats: RunStats,
    /// Whether the operator drives alone (teleoperated mode): no learning, no automatic tags.
    teleoperated: bool,
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
        perception: Perception,
    ) -> Self {
        let view = &scene.view;
        let map = CellMap::new(view.cols as i32, view.rows as i32);
        let explorer = Explorer::new(weights, &map);
        let mut d = Self {
            scene,
            perception,
            robot: CellRobot::new(start.0, start.1, RotationStep::Quarter, true),
            map,
            explorer,
            guidance: Guidance::default(),
            victims: Vec::new(),
            current: None,
            operator,
            config,
            rng: Pcg64Mcg::seed_from_u64(seed),
            avoided: vec![false; view.classes.len()],
            slips_in_row: 0,
            facing_obstacle_after_move: false,
            stuck: false,
            stale: true,
            map_hash: initial_map_hash(view.classes.len()),
            progress: 0,
            on_course: false,
            collided: false,
            idle_steps: 0,
            stuck_idle: false,
            operator_turn: false,
            operator_drove: false,
            done: false,
            stats: RunStats::default(),
            teleoperated: false,
        };
        let i = d.index(start.0);
        d.set_cell(i, MapCell::OpenVisited.visited_on(view.terrain_classes[i]));
        d.perceive();
        d.replan();
        d
    }

    /// Switches to the teleoperated mode: the operator chooses every command and identifies
    /// victims by looking; the robot only reports what its sensors show.
    pub fn teleoperated(mut self) -> Self {
        self.teleoperated = true;
        self
    }

    /// Writes cell `i` of the robot's map, keeping the exploration coefficients and the map's
    /// Zobrist hash (part of the flat learner's state) up to date.
    fn set_cell(&mut self, i: usize, cell: MapCell) {
        let was = self.map.cells[i];
        if was == cell {
            return;
        }
        self.map_hash ^= zobrist(i, was) ^ zobrist(i, cell);
        self.stale = true;
        self.map.cells[i] = cell;
        let cols = self.map.cols;
        self.explorer
            .cell_changed(&self.map, i as i32 % cols, i as i32 / cols);
    }

    fn index(&self, c: Cell) -> usize {
        (c.row * self.map.cols + c.col) as usize
    }

    fn heading(&self) -> Direction {
        Direction::from_index(usize::from(self.robot.heading))
    }

    /// The current observation of the engine.
    pub fn state(&self) -> RescueState {
        let victim = self.victim_status();
        let heading = self.desired_heading();
        let h = self.heading().index();
        let rel = |k: usize| Direction::from_index(h + k);
        let category = |d: Direction| -> usize {
            let (dc, dr) = d.step();
            let c = self.robot.cell;
            match self.map.get(c.col + dc, c.row + dr) {
                MapCell::Unknown | MapCell::UnknownObstacle => 0,
                MapCell::OpenUnvisited | MapCell::ClimbableUnvisited => 1,
                MapCell::OpenVisited | MapCell::ClimbableVisited => 2,
                MapCell::NonClimbable | MapCell::Victim => 3,
            }
        };
        let (front, left, back, right) = (
            category(rel(0)),
            category(rel(1)),
            category(rel(2)),
            category(rel(3)),
        );
        let heading_rel = heading.map_or(0, |d| (d.index() + 4 - h) % 4);
        let victim_mode = usize::from(victim != VictimStatus::None);
        let ng =
            ((((front * 4 + left) * 4 + right) * 4 + back) * 4 + heading_rel) * 2 + victim_mode;
        let forward = front * 2 + usize::from(heading.is_some() && heading_rel == 0);
        let backward = back * 2 + usize::from(heading.is_some() && heading_rel == 2);
        let (dc, dr) = rel(0).step();
        let ahead = self
            .map
            .index(self.robot.cell.col + dc, self.robot.cell.row + dr);
        let rotate =
            usize::from(self.facing_obstacle_after_move && ahead.is_some_and(|i| !self.avoided[i]));
        RescueState::new(
            self.stuck || self.stuck_idle,
            self.guidance.heading.is_some(),
            self.done,
            heading.is_some(),
            victim,
            ng as u16,
            forward as u8,
            backward as u8,
            rotate as u8,
            self.progress,
            self.index(self.robot.cell) as u16,
            self.robot.heading,
        )
        .with_on_course(self.on_course)
        .with_flat_key(self.flat_key(victim, heading))
    }

    /// The flat learner's state (paper 000 §VI-A: flat Q-learning with "the same state
    /// parameters"): every state variable of the hierarchy's subtasks without abstraction —
    /// the whole map M (its Zobrist hash; it holds C₁…C₈ and the D_xy class ahead), the
    /// robot's location L_R (cell and heading), the victim status V and the location L_V/R of
    /// the possible victim being dealt with relative to the robot, the exploration direction
    /// D_E and the heading toward its target, and whether the robot is stuck.
    fn flat_key(&self, victim: VictimStatus, heading: Option<Direction>) -> u64 {
        let c = self.robot.cell;
        let relative_victim = self.current.map_or(0, |(k, _)| {
            let (vc, vr) = self.victims[k].cell;
            (((vc - c.col + 64) as u64) << 7) | (vr - c.row + 64) as u64
        });
        let small = (self.index(c) as u64) << 32
            | u64::from(self.robot.heading) << 28
            | (victim as u64) << 24
            | self.guidance.direction.map_or(0, |d| d.index() as u64 + 1) << 20
            | heading.map_or(0, |d| d.index() as u64 + 1) << 16
            | u64::from(self.stuck || self.stuck_idle) << 15
            | relative_victim;
        splitmix64(self.map_hash ^ splitmix64(small))
    }

    fn victim_status(&self) -> VictimStatus {
        match self.current.map(|(k, _)| self.victims[k].status) {
            Some(Status::Pending) => VictimStatus::ToReach,
            Some(Status::CertainAtHand) => VictimStatus::CertainAtHand,
            Some(Status::UncertainAtHand) => VictimStatus::UncertainAtHand,
            _ => VictimStatus::None,
        }
    }

    /// The heading NG follows: toward the victim being approached, else the exploration's.
    fn desired_heading(&self) -> Option<Direction> {
        match self.current {
            Some((_, heading)) => heading,
            None => self.guidance.heading,
        }
    }

    pub fn guidance(&self) -> &Guidance {
        &self.guidance
    }

    /// Senses from the robot's pose and updates the map; counts progress.
    fn perceive(&mut self) {
        let scene = self.scene;
        let cell = self.robot.cell;
        let heading = self.heading();
        let (dc, dr) = heading.step();
        let (ac, ar) = (cell.col + dc, cell.row + dr);
        if let Some(class) = self
            .perception
            .front(&scene.scene, &scene.view, cell, heading)
            && let Some(i) = self.map.index(ac, ar)
            && self.map.cells[i].is_unclassified()
        {
            let seen = match class {
                CellClass::Open => MapCell::OpenUnvisited,
                CellClass::Climbable => MapCell::ClimbableUnvisited,
                _ => MapCell::NonClimbable,
            };
            self.set_cell(i, seen);
            self.progress += 1;
        }
        let infrared = self
            .perception
            .infrared(&scene.scene, &scene.view, cell, heading);
        let (lc, lr) = Direction::from_index(heading.index() + 1).step();
        for (k, &(fwd, left)) in INFRARED_NEIGHBOURS.iter().enumerate() {
            if infrared & (1 << k) == 0 {
                continue;
            }
            let (c, r) = (
                cell.col + fwd * dc + left * lc,
                cell.row + fwd * dr + left * lr,
            );
            if let Some(i) = self.map.index(c, r)
                && self.map.cells[i] == MapCell::Unknown
            {
                self.set_cell(i, MapCell::UnknownObstacle);
            }
        }
        let first_new = self.victims.len();
        for h in self
            .perception
            .heat(&scene.scene, &scene.view, cell, heading)
        {
            if !h.human_signature
                || self.victims.iter().any(|v| v.cell == h.cell)
                || h.cell == (cell.col, cell.row)
            {
                continue;
            }
            self.victims.push(PossibleVictim {
                cell: h.cell,
                truth: h.truth,
                first_size_m2: h.size_m2,
                probability: None,
                status: Status::Pending,
            });
        }
        for k in first_new..self.victims.len() {
            let (c, r) = self.victims[k].cell;
            if let Some(i) = self.map.index(c, r) {
                self.set_cell(i, MapCell::Victim);
            }
        }
    }

    /// Recomputes the exploration guidance and the victim to deal with.
    fn replan(&mut self) {
        if !self.stale {
            // Same map, cell and victims: the same guidance and victim; only a turn may have
            // brought the pending victim in view.
            if !self.teleoperated {
                self.check_at_hand();
            }
            return;
        }
        self.stale = false;
        let c = self.robot.cell;
        self.guidance =
            self.explorer
                .guide(&self.map, c.col, c.row, self.heading(), Some(self.guidance));
        if self.teleoperated {
            self.current = None;
            return;
        }
        // Keep a victim at hand; otherwise the nearest pending one the robot can reach.
        if let Some((k, _)) = self.current
            && matches!(
                self.victims[k].status,
                Status::CertainAtHand | Status::UncertainAtHand
            )
        {
            return;
        }
        let mut best: Option<(u32, usize, Option<Direction>)> = None;
        let heading = self.heading();
        if self
            .victims
            .iter()
            .filter(|v| v.status == Status::Pending)
            .nth(1)
            .is_some()
        {
            self.explorer.several_victims_pending();
        }
        for (k, v) in self.victims.iter().enumerate() {
            if v.status != Status::Pending {
                continue;
            }
            if let Some((dir, d)) = self
                .explorer
                .toward_victim(&self.map, c.col, c.row, heading, v.cell.0, v.cell.1)
                && best.is_none_or(|(bd, _, _)| d < bd)
            {
                best = Some((d, k, Some(dir)));
            }
        }
        self.current = best.map(|(_, k, dir)| (k, dir));
        self.check_at_hand();
    }

    /// A pending victim is at hand when the robot is next to it and faces it: measure p.
    fn check_at_hand(&mut self) {
        let Some((k, _)) = self.current else { return };
        if self.victims[k].status != Status::Pending {
            return;
        }
        let (dc, dr) = self.heading().step();
        let c = self.robot.cell;
        if self.victims[k].cell != (c.col + dc, c.row + dr) {
            return;
        }
        let scene = self.scene;
        let heading = self.heading();
        let v = self.victims[k];
        let measured = self
            .perception
            .heat(&scene.scene, &scene.view, c, heading)
            .iter()
            .find(|h| h.cell == v.cell && h.truth == v.truth)
            .map(|h| (h.human_signature, h.size_m2));
        let (human, size) = measured.unwrap_or((true, v.first_size_m2));
        let p = victim_probability(human, size);
        self.victims[k].probability = Some(p);
        self.progress += 1;
        if p > TAG_THRESHOLD {
            self.victims[k].status = Status::CertainAtHand;
        } else if p < DISMISS_THRESHOLD {
            self.release(k, Status::Rejected);
        } else {
            self.victims[k].status = Status::UncertainAtHand;
            self.stats.handoffs_victim += 1;
            self.stats.time_s += self.operator.response_delay_s();
        }
    }

    /// Ends the robot's dealing with possible victim `k`; a rejected one frees its cell.
    fn release(&mut self, k: usize, status: Status) {
        self.victims[k].status = status;
        self.stale = true;
        if status == Status::Rejected {
            let (c, r) = self.victims[k].cell;
            if let Some(i) = self.map.index(c, r) {
                self.set_cell(i, MapCell::Unknown);
            }
        }
        self.current = None;
        self.progress += 1;
    }

    fn navigate(&mut self, act: CellAction) -> f64 {
        let by_operator = std::mem::take(&mut self.operator_turn) || self.teleoperated;
        self.operator_drove = by_operator;
        self.stats.steps += 1;
        self.stats.time_s += if by_operator {
            self.operator.command_time_s()
        } else {
            self.config.robot_step_s
        };
        let scene = self.scene;
        let before = self.robot.cell;
        let heading_before = self.heading();
        let desired = self.desired_heading();
        let (dc, dr) = heading_before.step();
        let ahead = self.map.index(before.col + dc, before.row + dr);
        let came_against_obstacle = std::mem::take(&mut self.facing_obstacle_after_move);
        let progress_before = self.progress;
        let slip = self.config.slip_probability;
        let rng = &mut self.rng;
        let victim_cell = &scene.victim_cell;
        let cols = self.map.cols;
        let (w, h) = (scene.view.cols as i32, scene.view.rows as i32);
        let outcome = self.robot.apply_with(
            act,
            &scene.view,
            |c| {
                c.col >= 0
                    && c.row >= 0
                    && c.col < w
                    && c.row < h
                    && victim_cell[(c.row * cols + c.col) as usize]
            },
            |_| rng.random::<f64>() < slip,
        );
        let reward = match outcome {
            CellOutcome::Collided => {
                if by_operator {
                    self.stats.operator_collisions += 1;
                } else {
                    self.stats.robot_collisions += 1;
                }
                if let Some(t) = self.robot.move_target(act)
                    && let Some(i) = self.map.index(t.col, t.row)
                    && self.map.cells[i] != MapCell::NonClimbable
                    && self.map.cells[i] != MapCell::Victim
                {
                    // The bump corrects the map: whatever the depth sensor said, the robot
                    // cannot drive there.
                    self.set_cell(i, MapCell::NonClimbable);
                    self.progress += 1;
                }
                rewards::COLLISION
            }
            CellOutcome::Slipped => {
                self.slips_in_row += 1;
                if !self.stuck && self.slips_in_row >= self.config.stuck_after_slips {
                    self.stuck = true;
                    self.stats.handoffs_stuck += 1;
                    self.stats.time_s += self.operator.response_delay_s();
                }
                rewards::VISITED
            }
            CellOutcome::Moved => {
                self.stale = true;
                self.slips_in_row = 0;
                self.stuck = false;
                let c = self.robot.cell;
                let i = self.index(c);
                let was = self.map.cells[i];
                self.set_cell(i, was.visited_on(scene.view.terrain_classes[i]));
                if was.is_visited() {
                    rewards::VISITED
                } else {
                    self.progress += 1;
                    let moved = Direction::ALL
                        .into_iter()
                        .find(|d| d.step() == (c.col - before.col, c.row - before.row));
                    if moved.is_some() && moved == desired {
                        rewards::UNVISITED_IN_DIRECTION
                    } else {
                        0.0
                    }
                }
            }
            CellOutcome::Rotated => {
                if came_against_obstacle
                    && let Some(i) = ahead
                    && !self.avoided[i]
                {
                    self.avoided[i] = true;
                    rewards::OBSTACLE_AVOIDED
                } else {
                    rewards::VISITED
                }
            }
        };
        self.perceive();
        let moved_along = outcome == CellOutcome::Moved
            && desired.is_some_and(|d| {
                let c = self.robot.cell;
                d.step() == (c.col - before.col, c.row - before.row)
            });
        // A bump also corrects the map (progress), but it is never on course; nor is progress
        // off the heading (a cell classified while turning away from the one NG was sent to
        // face). Progress made by the replanning that follows (a victim brought at hand)
        // counts too (`act`).
        let faces_heading = desired == Some(self.heading());
        self.on_course = moved_along
            || (outcome != CellOutcome::Collided
                && self.progress != progress_before
                && faces_heading);
        self.collided = outcome == CellOutcome::Collided;
        if outcome == CellOutcome::Moved && act == CellAction::Forward {
            let (dc, dr) = self.heading().step();
            let c = self.robot.cell;
            self.facing_obstacle_after_move = matches!(
                self.map.get(c.col + dc, c.row + dr),
                MapCell::NonClimbable | MapCell::Victim
            );
        }
        reward
    }

    fn tag(&mut self) -> f64 {
        self.operator_turn = false;
        let at_hand = self.current.filter(|&(k, _)| {
            matches!(
                self.victims[k].status,
                Status::CertainAtHand | Status::UncertainAtHand
            )
        });
        let Some((k, _)) = at_hand else {
            return rewards::TAG_WRONG;
        };
        let truth = self.victims[k].truth;
        self.release(k, Status::Tagged);
        match truth {
            HeatTruth::Victim(_) => {
                self.stats.victims_found += 1;
                rewards::TAG_CORRECT
            }
            HeatTruth::Other(_) => {
                self.stats.false_tags += 1;
                rewards::TAG_WRONG
            }
        }
    }

    fn reject(&mut self) -> f64 {
        self.operator_turn = false;
        if let Some((k, _)) = self.current
            && matches!(
                self.victims[k].status,
                Status::CertainAtHand | Status::UncertainAtHand
            )
        {
            self.release(k, Status::Rejected);
        }
        0.0
    }

    fn exit(&mut self) -> f64 {
        self.done = true;
        if self.guidance.heading.is_some() {
            return rewards::EXIT_EARLY;
        }
        // A possible victim the robot could still reach and decide.
        if self.current.is_some() {
            rewards::EXIT_EXPLORED
        } else {
            rewards::EXIT_EXPLORED + rewards::TASK_COMPLETED
        }
    }

    /// Executes one primitive action (see [`action`]) and returns its reward.
    pub fn act(&mut self, a: usize) -> f64 {
        let progress_before = self.progress;
        let reward = match a {
            action::FORWARD => self.navigate(CellAction::Forward),
            action::BACKWARD => self.navigate(CellAction::Backward),
            action::ROTATE_LEFT => self.navigate(CellAction::RotateLeft),
            action::ROTATE_RIGHT => self.navigate(CellAction::RotateRight),
            action::TAG => self.tag(),
            action::REJECT => self.reject(),
            _ => self.exit(),
        };
        let progress_acted = self.progress;
        if !self.done {
            self.replan();
        }
        if a <= action::ROTATE_RIGHT {
            if self.progress != progress_before {
                // Progress of the replanning (a victim brought at hand) is on course.
                if self.progress != progress_acted {
                    self.on_course |= !self.collided;
                }
                self.idle_steps = 0;
                self.stuck_idle = false;
            } else if !std::mem::take(&mut self.operator_drove) {
                self.idle_steps += 1;
                if !self.stuck_idle && self.idle_steps >= self.config.stuck_after_idle_steps {
                    self.stuck_idle = true;
                    self.stats.handoffs_stuck += 1;
                    self.stats.time_s += self.operator.response_delay_s();
                }
            }
        }
        reward
    }

    /// What the operator is shown when asked to drive.
    pub fn navigation_request(&self) -> NavigationRequest {
        let c = self.robot.cell;
        let view = &self.scene.view;
        let mut neighbours = [MapCell::NonClimbable; 4];
        let mut camera = [(CellClass::NonClimbable, false); 4];
        for d in Direction::ALL {
            let (dc, dr) = d.step();
            let n = Cell::new(c.col + dc, c.row + dr);
            neighbours[d.index()] = self.map.get(n.col, n.row);
            camera[d.index()] = (
                view.terrain_class(n),
                view.index(n).is_some_and(|i| self.scene.victim_cell[i]),
            );
        }
        NavigationRequest {
            cell: (c.col, c.row),
            heading: self.heading(),
            neighbours,
            camera,
            suggested: self.desired_heading(),
        }
    }

    /// The uncertain victim at hand, as shown to the operator.
    pub fn victim_request(&self) -> Option<VictimRequest> {
        let (k, _) = self.current?;
        let v = &self.victims[k];
        (v.status == Status::UncertainAtHand).then(|| VictimRequest {
            cell: v.cell,
            probability: v.probability.unwrap_or(0.0),
            size_m2: v.first_size_m2,
            truth: v.truth,
        })
    }

    /// Replaces the exploration weights while the robot runs (the console's live w_l, w_p,
    /// w_q) and recomputes the guidance from the map as it is.
    pub fn set_exploration_weights(&mut self, weights: ExplorationWeights) {
        self.explorer = Explorer::new(weights, &self.map);
        if !self.done {
            self.replan();
        }
    }

    /// The possible victims met so far: cell, status and measured probability (if measured).
    pub fn possible_victims(
        &self,
    ) -> impl Iterator<Item = ((i32, i32), VictimMark, Option<f64>)> + '_ {
        self.victims.iter().map(|v| {
            let mark = match v.status {
                Status::Tagged => VictimMark::Tagged,
                Status::Rejected => VictimMark::Dismissed,
                _ => VictimMark::Pending,
            };
            (v.cell, mark, v.probability)
        })
    }

    /// Whether the robot is stuck (its navigation is handed to the operator).
    pub fn is_stuck(&self) -> bool {
        self.stuck
    }

    /// Whether the run is over (the robot exited).
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// Cells the robot has visited (row-major).
    pub fn visited(&self) -> impl Iterator<Item = bool> + '_ {
        self.map.cells.iter().map(|c| c.is_visited())
    }

    /// The operator's answer to a hand-off at `node`, if `node` is an HC node.
    fn operator_choice(&mut self, node: NodeId) -> Option<usize> {
        match node {
            hierarchy::HC_SHARE => {
                let request = self.victim_request()?;
                self.operator_turn = true;
                Some(match self.operator.identify_victim(&request) {
                    VictimDecision::Tag => 0,
                    VictimDecision::Reject => 1,
                })
            }
            hierarchy::HC_NAV => {
                let request = self.navigation_request();
                self.operator_turn = true;
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

/// SplitMix64's finaliser: a well-mixed 64-bit function of `x`.
#[inline]
fn splitmix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// The Zobrist key of cell `i` holding `cell`.
#[inline]
fn zobrist(i: usize, cell: MapCell) -> u64 {
    splitmix64(((i as u64) << 3 | cell as u64) ^ 0x2A5E_D0B1_57A7_E000)
}

/// The Zobrist hash of a map of `n` unknown cells.
fn initial_map_hash(n: usize) -> u64 {
    (0..n).fold(0, |h, i| h ^ zobrist(i, MapCell::Unknown))
}

impl MapCell {
    /// The visited category of a cell the robot stands on, from the terrain it feels.
    pub fn visited_on(self, terrain: CellClass) -> MapCell {
        match (self, terrain) {
            (MapCell::ClimbableUnvisited | MapCell::ClimbableVisited, _)
            | (_, CellClass::Climbable) => MapCell::ClimbableVisited,
            _ => MapCell::OpenVisited,
        }
    }
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

//! The rescue robot's own knowledge and decisions (paper 000 §IV–V): its cell map, the
//! possible victims it met, the direction-based exploration, when it is stuck, and the state
//! the MAXQ hierarchy sees — fed by readings, whatever produced them.
//!
//! [`RescueAgent`] never touches a scene. A navigation primitive is split in two: [`RescueAgent::begin`]
//! says what the body must do, [`RescueAgent::finish`] takes what the body felt (the outcome,
//! the terrain under it) and what the sensors then read. [`crate::RescueDomain`] joins the two
//! on a scene's cell physics in one call; a controller on the shared simulator
//! ([`crate::controller`]) drives the primitive over many steps in between.
//!
//! A heat reading names its source with `T`: the scene's [`HeatTruth`] in the cell-physics
//! runs (whose sensing cache is per source), an opaque [`DetectionId`] on the shared
//! simulator, where the robot tells sources apart only by their cell.

mod act;
mod views;

use crate::cell_map::{CellMap, MapCell};
use crate::domain::{DomainConfig, RunStats};
use crate::exploration::{Direction, ExplorationWeights, Explorer, Guidance};
use crate::perception::{
    DISMISS_THRESHOLD, INFRARED_NEIGHBOURS, TAG_THRESHOLD, victim_probability,
};
use crate::rewards;
use crate::state::{RescueState, VictimStatus};
use usar_sim::sensors::{DetectionId, HeatTruth};
use usar_sim::{CellAction, CellRobot, RotationStep};
use usar_world::Cell;
use usar_world::cellview::CellClass;

/// What a heat reading tells of its source.
pub trait HeatSource: Copy + std::fmt::Debug {
    /// Whether two readings of one cell come from the same source, as far as the robot can
    /// tell.
    fn same_source(&self, other: &Self) -> bool;
}

impl HeatSource for HeatTruth {
    fn same_source(&self, other: &Self) -> bool {
        self == other
    }
}

/// On the shared simulator every reading has a number of its own: one cell, one source.
impl HeatSource for DetectionId {
    fn same_source(&self, _other: &Self) -> bool {
        true
    }
}

/// One heat region seen from a (cell, heading).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatReading<T = HeatTruth> {
    /// The coarse cell of the region's global position.
    pub cell: (i32, i32),
    pub human_signature: bool,
    pub size_m2: f64,
    /// Its source: ground truth for scoring and the simulated operator only, or an opaque
    /// number the evaluator resolves.
    pub source: T,
}

/// What the robot's sensors read from its cell facing its heading.
#[derive(Clone, Copy, Debug)]
pub struct CellReading<'r, T> {
    /// Class of the cell ahead from D_xy (`None`: ahead lies outside the arena).
    pub front: Option<CellClass>,
    /// Infrared hits: bit k set for [`INFRARED_NEIGHBOURS`]\[k\] relative to the heading.
    pub infrared: u8,
    pub heat: &'r [HeatReading<T>],
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
struct PossibleVictim<T> {
    cell: (i32, i32),
    source: T,
    /// Size of the warm region when first seen, m².
    first_size_m2: f64,
    probability: Option<f64>,
    status: Status,
}

/// An uncertain possible victim at hand, as the robot would show it to its operator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UncertainVictim<T> {
    pub cell: (i32, i32),
    pub probability: f64,
    pub size_m2: f64,
    pub source: T,
}

/// A navigation primitive begun: what the body must do, and what the robot noted before.
#[derive(Clone, Copy, Debug)]
pub struct Move {
    pub action: CellAction,
    /// The operator commanded it (HC₃ or teleoperation).
    pub by_operator: bool,
    before: Cell,
    desired: Option<Direction>,
    ahead: Option<usize>,
    came_against_obstacle: bool,
    progress_before: u32,
}

/// What [`RescueAgent::begin`] leads to.
#[derive(Clone, Copy, Debug)]
pub enum Begun<T> {
    /// A navigation primitive for the body; [`RescueAgent::finish`] completes it.
    Move(Move),
    /// Done at once with this reward (Reject, Exit).
    Done(f64),
    /// A Tag: of the possible victim with this source, or of nothing at hand (`None`); its
    /// reward depends on what the source is (scored by the caller, see [`tag_reward`]).
    Tagged(Option<T>),
}

/// Table I's reward of a Tag of a source whose truth is `truth` (`None`: nothing at hand).
pub fn tag_reward(truth: Option<HeatTruth>) -> f64 {
    match truth {
        Some(HeatTruth::Victim(_)) => rewards::TAG_CORRECT,
        _ => rewards::TAG_WRONG,
    }
}

/// See the [module documentation](self).
pub struct RescueAgent<T> {
    pub robot: CellRobot,
    pub map: CellMap,
    explorer: Explorer,
    guidance: Guidance,
    victims: Vec<PossibleVictim<T>>,
    /// The possible victim being dealt with and the heading toward it.
    current: Option<(usize, Option<Direction>)>,
    config: DomainConfig,
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
    /// The heat regions of the latest reading.
    heat: Vec<HeatReading<T>>,
    /// Hand-offs asked since [`RescueAgent::take_handoffs_asked`] was last called.
    handoffs_asked: u32,
    pub stats: RunStats,
    /// Whether the operator drives alone (teleoperated mode): no automatic tags.
    teleoperated: bool,
}

impl<T: HeatSource> RescueAgent<T> {
    /// A robot at `start` (cell, heading 0–3) on a `cols` × `rows` cell map, standing on
    /// `start_terrain`; [`RescueAgent::start`] gives it its first reading.
    pub fn new(
        cols: i32,
        rows: i32,
        start: (Cell, u8),
        weights: ExplorationWeights,
        config: DomainConfig,
        start_terrain: CellClass,
    ) -> Self {
        let map = CellMap::new(cols, rows);
        let explorer = Explorer::new(weights, &map);
        let n = map.cells.len();
        let mut agent = Self {
            robot: CellRobot::new(start.0, start.1, RotationStep::Quarter, true),
            map,
            explorer,
            guidance: Guidance::default(),
            victims: Vec::new(),
            current: None,
            config,
            avoided: vec![false; n],
            slips_in_row: 0,
            facing_obstacle_after_move: false,
            stuck: false,
            stale: true,
            map_hash: initial_map_hash(n),
            progress: 0,
            on_course: false,
            collided: false,
            idle_steps: 0,
            stuck_idle: false,
            operator_turn: false,
            operator_drove: false,
            done: false,
            heat: Vec::new(),
            handoffs_asked: 0,
            stats: RunStats::default(),
            teleoperated: false,
        };
        let i = agent.index(start.0);
        agent.set_cell(i, MapCell::OpenVisited.visited_on(start_terrain));
        agent
    }

    /// The first reading, at the start cell: the robot plans from it.
    pub fn start(&mut self, reading: CellReading<'_, T>) {
        self.perceive(reading);
        self.replan();
    }

    /// Switches to the teleoperated mode: the operator chooses every command and identifies
    /// victims by looking; the robot only reports what its sensors show.
    pub fn set_teleoperated(&mut self) {
        self.teleoperated = true;
    }

    /// Hand-offs the robot asked for (stuck, or an uncertain victim at hand) since this was
    /// last called: each costs the operator's response time.
    pub fn take_handoffs_asked(&mut self) -> u32 {
        std::mem::take(&mut self.handoffs_asked)
    }

    /// The operator answers the hand-off now: the next primitive or Tag/Reject is theirs.
    pub fn operator_takes_turn(&mut self) {
        self.operator_turn = true;
    }

    /// The next navigation primitive will be the operator's.
    pub fn next_move_by_operator(&self) -> bool {
        self.operator_turn || self.teleoperated
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

    /// Updates the map from a reading at the robot's cell and heading; counts progress.
    pub fn perceive(&mut self, reading: CellReading<'_, T>) {
        let cell = self.robot.cell;
        let heading = self.heading();
        let (dc, dr) = heading.step();
        let (ac, ar) = (cell.col + dc, cell.row + dr);
        if let Some(class) = reading.front
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
        let (lc, lr) = Direction::from_index(heading.index() + 1).step();
        for (k, &(fwd, left)) in INFRARED_NEIGHBOURS.iter().enumerate() {
            if reading.infrared & (1 << k) == 0 {
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
        self.heat.clear();
        self.heat.extend_from_slice(reading.heat);
        let first_new = self.victims.len();
        for h in reading.heat {
            if !h.human_signature
                || self.victims.iter().any(|v| v.cell == h.cell)
                || h.cell == (cell.col, cell.row)
            {
                continue;
            }
            self.victims.push(PossibleVictim {
                cell: h.cell,
                source: h.source,
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
        let v = self.victims[k];
        let measured = self
            .heat
            .iter()
            .find(|h| h.cell == v.cell && h.source.same_source(&v.source))
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
            self.handoffs_asked += 1;
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

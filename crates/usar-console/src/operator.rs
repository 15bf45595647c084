//! The console's side of the hand-off interface (paper 000 §IV-A-5): [`ConsoleOperator`]
//! implements the same [`HandOff`] trait as the simulated operator, but its answers come from a
//! person in a browser. The MAXQ robot runs on its own thread inside MAXQ-Q's learning episode
//! ([`usar_maxq::MaxqQ::learn_episode`]), so a hand-off simply waits for the answer while the
//! rest of the mission goes on, and the hierarchy learns from the person's choices exactly as
//! from the simulated operator's (HC₂'s Tag/Reject, HC₃'s commands as NG's apprentice).
//!
//! The robot's primitives are paced by the [`crate::clock::MissionClock`]: 1.5 simulated
//! seconds per primitive in autonomy (the domain's `robot_step_s`), [`OPERATOR_STEP_S`] per
//! operator command.

use crate::images;
use crate::mission::{OperatorAnswer, Shared};
use crate::snapshot::{HandOffKind, HandOffView};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::Duration;
use usar_maxq::{Domain, MaxqQ, NodeId, Schedule};
use usar_rescue::cell_map::MapCell;
use usar_rescue::exploration::ExplorationWeights;
use usar_rescue::hierarchy::{RescueHierarchy, action};
use usar_rescue::operator::{HandOff, NavigationRequest, VictimDecision, VictimRequest};
use usar_rescue::{DomainConfig, RescueDomain, RescueScene, RescueState, VictimStatus};
use usar_sim::CellAction;
use usar_world::Cell;

/// Simulated seconds one operator command takes (a person at the console reacts at once).
pub const OPERATOR_STEP_S: f64 = 0.5;

/// Answers the robot's hand-offs with what a person sends from the console.
pub struct ConsoleOperator {
    shared: Arc<Shared>,
    scene: Arc<RescueScene>,
    answers: Receiver<OperatorAnswer>,
    /// Why the robot is stuck, set by the paced domain before it asks (see [`HandOffView::reason`]).
    stuck_reason: &'static str,
}

impl ConsoleOperator {
    pub(crate) fn new(
        shared: Arc<Shared>,
        scene: Arc<RescueScene>,
        answers: Receiver<OperatorAnswer>,
    ) -> Self {
        Self {
            shared,
            scene,
            answers,
            stuck_reason: "slipping",
        }
    }

    /// Puts a hand-off in the queue shown to viewers; returns its id.
    fn post(&self, mut view: HandOffView, thermal: Vec<u8>, depth: Vec<u8>) -> u64 {
        let id = self.shared.next_handoff.fetch_add(1, Ordering::SeqCst);
        view.id = id;
        if !thermal.is_empty() {
            view.thermal = Some(format!("/api/handoff/{id}/thermal.png"));
            view.depth = Some(format!("/api/handoff/{id}/depth.png"));
            self.shared.lock_images().insert(id, (thermal, depth));
        }
        let mut rescue = self.shared.lock_rescue();
        rescue.handoff = Some(view);
        rescue.mode = "operator";
        id
    }

    fn clear(&self) {
        let mut rescue = self.shared.lock_rescue();
        rescue.handoff = None;
        rescue.mode = "autonomous";
    }

    /// Waits for an answer `accept` takes; `None` when the mission stops.
    fn wait<T>(&self, mut accept: impl FnMut(OperatorAnswer) -> Option<T>) -> Option<T> {
        loop {
            match self.answers.recv_timeout(Duration::from_millis(100)) {
                Ok(answer) => {
                    if let Some(v) = accept(answer) {
                        return Some(v);
                    }
                }
                Err(RecvTimeoutError::Timeout) => {
                    if self.shared.clock.is_stopping() {
                        return None;
                    }
                }
                Err(RecvTimeoutError::Disconnected) => return None,
            }
        }
    }

    /// Answers sent before this hand-off are not for it.
    fn drain(&self) {
        while self.answers.try_recv().is_ok() {}
    }
}

impl HandOff for ConsoleOperator {
    fn identify_victim(&mut self, request: &VictimRequest) -> VictimDecision {
        self.drain();
        let view = &self.scene.view;
        let target = view.cell_center(Cell::new(request.cell.0, request.cell.1));
        let (robot_cell, heading) = {
            let r = self.shared.lock_rescue();
            (r.cell, r.heading)
        };
        let from = view.cell_center(robot_cell);
        let thermal = images::thermal_png(&self.scene.scene, target, view.geometry.resolution_m);
        let depth = images::depth_png(&self.scene.scene, from, heading, view.geometry.resolution_m);
        let id = self.post(
            HandOffView {
                id: 0,
                robot: 0,
                kind: HandOffKind::Victim,
                x: target.x,
                y: target.y,
                reason: None,
                suggested: None,
                probability: Some(request.probability),
                size_m2: Some(request.size_m2),
                thermal: None,
                depth: None,
            },
            thermal,
            depth,
        );
        let decision = self
            .wait(|a| match a {
                OperatorAnswer::Victim { handoff, tag } if handoff == id => Some(if tag {
                    VictimDecision::Tag
                } else {
                    VictimDecision::Reject
                }),
                _ => None,
            })
            .unwrap_or(VictimDecision::Reject);
        self.clear();
        decision
    }

    fn drive(&mut self, request: &NavigationRequest) -> CellAction {
        let suggested = request.suggested;
        let p = self
            .scene
            .view
            .cell_center(Cell::new(request.cell.0, request.cell.1));
        let posted = {
            let mut rescue = self.shared.lock_rescue();
            match rescue
                .handoff
                .as_mut()
                .filter(|h| h.kind == HandOffKind::Stuck)
            {
                Some(h) => {
                    // The same hand-off, updated as the person drives.
                    (h.x, h.y, h.suggested) = (p.x, p.y, suggested);
                    h.reason = Some(self.stuck_reason.into());
                    true
                }
                None => false,
            }
        };
        if !posted {
            self.drain();
            self.post(
                HandOffView {
                    id: 0,
                    robot: 0,
                    kind: HandOffKind::Stuck,
                    x: p.x,
                    y: p.y,
                    reason: Some(self.stuck_reason.into()),
                    suggested,
                    probability: None,
                    size_m2: None,
                    thermal: None,
                    depth: None,
                },
                Vec::new(),
                Vec::new(),
            );
        }
        self.wait(|a| match a {
            OperatorAnswer::Drive(c) => Some(c),
            _ => None,
        })
        .unwrap_or(CellAction::RotateLeft)
    }

    fn response_delay_s(&mut self) -> f64 {
        // The person's real delay passes on the mission clock while the robot waits.
        0.0
    }

    fn command_time_s(&self) -> f64 {
        OPERATOR_STEP_S
    }
}

/// The robot's domain paced by the mission clock, publishing its state after every step.
struct PacedDomain<'a> {
    inner: RescueDomain<'a, ConsoleOperator>,
    shared: Arc<Shared>,
    scene: &'a RescueScene,
    robot_step_s: f64,
    ready_at_s: f64,
    /// Tags (right or wrong) of the earlier episodes.
    tags_before: u32,
}

impl PacedDomain<'_> {
    fn publish(&self) {
        let state = self.inner.state();
        let view = &self.scene.view;
        let cell = self.inner.agent.robot.cell;
        let p = view.cell_center(cell);
        let task = if state.done() {
            "exited"
        } else if state.stuck() {
            "HC3: operator drives"
        } else {
            match state.victim_status() {
                VictimStatus::UncertainAtHand => "HC2: victim to operator",
                VictimStatus::CertainAtHand => "VI: tag",
                VictimStatus::ToReach => "VI: approach victim",
                VictimStatus::None => "NUR: explore (NG)",
            }
        };
        let mut r = self.shared.lock_rescue();
        r.cell = cell;
        r.heading = self.inner.agent.robot.heading;
        r.pose = [
            p.x,
            p.y,
            f64::from(self.inner.agent.robot.heading) * std::f64::consts::FRAC_PI_2,
        ];
        r.task = task.into();
        r.tags = self.tags_before
            + self.inner.agent.stats.victims_found
            + self.inner.agent.stats.false_tags;
        if r.handoff
            .as_ref()
            .is_some_and(|h| h.kind == HandOffKind::Stuck)
            && !state.stuck()
        {
            r.handoff = None;
            r.mode = "autonomous";
        }

        for (cell, mark, probability) in self.inner.possible_victims() {
            let entry = r.victims.entry(cell).or_insert((mark, probability));
            if entry.0 != usar_rescue::VictimMark::Tagged {
                *entry = (mark, probability.or(entry.1));
            }
        }
        if r.cell_map.len() != self.inner.agent.map.cells.len() {
            r.cell_map = vec![0; self.inner.agent.map.cells.len()];
        }
        let mut changed = false;
        for (k, c) in self.inner.agent.map.cells.iter().enumerate() {
            let code = cell_code(*c);
            if r.cell_map[k] != code {
                r.cell_map[k] = code;
                changed = true;
            }
        }
        if changed {
            r.cell_map_version += 1;
        }
    }
}

/// The display code of a cell-map category (see [`crate::snapshot::MapView::cell_map`]).
fn cell_code(c: MapCell) -> u8 {
    match c {
        MapCell::Unknown => 0,
        MapCell::OpenUnvisited => 1,
        MapCell::OpenVisited => 2,
        MapCell::ClimbableUnvisited => 3,
        MapCell::ClimbableVisited => 4,
        MapCell::NonClimbable => 5,
        MapCell::Victim => 6,
        MapCell::UnknownObstacle => 7,
    }
}

impl Domain for PacedDomain<'_> {
    type State = RescueState;

    fn step(&mut self, s: &RescueState, a: usize) -> (RescueState, f64) {
        let weights = self.shared.lock_rescue().weights_changed.take();
        if let Some([w_l, w_p, w_q]) = weights {
            self.inner
                .set_exploration_weights(ExplorationWeights::weighted("console", w_l, w_p, w_q));
        }
        if a <= action::ROTATE_RIGHT {
            let duration = if self.inner.is_stuck() {
                OPERATOR_STEP_S
            } else {
                self.robot_step_s
            };
            let clock = &self.shared.clock;
            self.ready_at_s = self.ready_at_s.max(clock.now_s()) + duration;
            clock.wait_until(self.ready_at_s);
        }
        let next = self.inner.step(s, a);
        self.publish();
        next
    }

    fn is_terminal(&self, s: &RescueState) -> bool {
        self.inner.is_terminal(s) || self.shared.clock.is_stopping()
    }

    fn delegated_choice(&mut self, node: NodeId, s: &RescueState) -> Option<usize> {
        self.inner.operator.stuck_reason = if self.inner.is_stuck() {
            "slipping"
        } else {
            "no progress"
        };
        self.publish();
        self.inner.delegated_choice(node, s)
    }
}

/// Runs the MAXQ robot until the mission stops: learning episodes with the console's operator;
/// when the robot exits while there is still something to explore, a new episode starts where
/// it stands (its map starts anew, the tagged victims stay tagged).
pub(crate) fn run_rescue_robot(
    shared: Arc<Shared>,
    scene: Arc<RescueScene>,
    mut learner: MaxqQ,
    config: DomainConfig,
    answers: Receiver<OperatorAnswer>,
    seed: u64,
) {
    let hierarchy = RescueHierarchy::new();
    let mut rng = Pcg64Mcg::seed_from_u64(seed ^ 0xC0_50_1E);
    learner.params.epsilon = Schedule::constant(0.05);
    learner.params.max_steps_per_episode = u64::MAX / 4;
    let Some(mut start) = scene.start(0) else {
        shared.lock_rescue().task = "no start cell".into();
        return;
    };
    let mut operator = ConsoleOperator::new(shared.clone(), scene.clone(), answers);
    let mut episode_seed = seed;
    loop {
        let weights = {
            let mut r = shared.lock_rescue();
            r.weights_changed = None;
            let [w_l, w_p, w_q] = r.weights;
            ExplorationWeights::weighted("console", w_l, w_p, w_q)
        };
        let domain = RescueDomain::new(
            &scene,
            start,
            weights,
            config.clone(),
            operator,
            episode_seed,
        );
        let mut paced = PacedDomain {
            inner: domain,
            shared: shared.clone(),
            scene: &scene,
            robot_step_s: config.robot_step_s,
            ready_at_s: shared.clock.now_s(),
            tags_before: shared.lock_rescue().tags,
        };
        paced.publish();
        let s0 = paced.inner.state();
        learner.learn_episode(&hierarchy, &mut paced, s0, &mut rng);
        paced.publish();
        let explored_all = paced.inner.guidance().heading.is_none();
        start = (
            paced.inner.agent.robot.cell,
            paced.inner.agent.robot.heading,
        );
        let ready = paced.ready_at_s;
        operator = paced.inner.operator;
        shared.lock_rescue().episodes += 1;
        if shared.clock.is_stopping() {
            return;
        }
        if explored_all {
            shared.lock_rescue().task = "exited: nothing left to explore".into();
            // Nothing left for this robot: wait for the mission to stop.
            shared.clock.wait_until(f64::INFINITY);
            return;
        }
        // A pause of two simulated seconds before the next episode.
        if !shared
            .clock
            .wait_until(ready.max(shared.clock.now_s()) + 2.0)
        {
            return;
        }
        episode_seed = episode_seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(1);
    }
}

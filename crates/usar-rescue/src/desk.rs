//! One operator for many robots (paper 000 §IV-A-5, §VII-B): hand-off questions wait in a
//! queue and the operator answers one at a time, each after a response time — so a robot
//! asking while the operator is busy waits longer. While the operator drives a stuck robot its
//! next command follows after the command time, not a fresh response.
//!
//! The desk stands for the person looking at the robots' cameras: it answers through a
//! [`SimulatedOperator`] from what the camera shows, which in simulation is the scene
//! (through the host's [`Evaluator`] and the scene's [`CellView`]). Robots never see it.

use crate::controller::{Answer, Question};
use crate::operator::{HandOff, SimulatedOperator, VictimRequest};
use serde::Serialize;
use std::collections::VecDeque;
use usar_sim::host::Evaluator;
use usar_sim::sensors::HeatTruth;
use usar_world::Point2;
use usar_world::cellview::{CellClass, CellView};

/// One hand-off, as the timeline shows it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HandOffRecord {
    /// The asking robot's number on the desk.
    pub robot: usize,
    /// `victim` (HC₂) or `drive` (HC₃).
    pub kind: &'static str,
    pub asked_s: f64,
    /// When the operator turned to it, and answered.
    pub started_s: f64,
    pub answered_s: f64,
    /// `tag`, `reject`, or the driving command.
    pub answer: String,
    /// For a victim question: whether the source really was a victim (evaluation only).
    pub was_victim: Option<bool>,
}

/// See the [module documentation](self).
pub struct OperatorDesk {
    operator: SimulatedOperator,
    view: CellView,
    queue: VecDeque<(usize, f64, Question)>,
    /// The question being answered: robot, asked, started, answer due, the answer.
    current: Option<(usize, f64, f64, f64, Answer, Option<bool>)>,
    /// The robot the operator drove last (its next command needs no new response).
    driving: Option<usize>,
    pub timeline: Vec<HandOffRecord>,
}

impl OperatorDesk {
    /// A desk with `operator`; `view` is the scene's cell view (what cameras show).
    pub fn new(operator: SimulatedOperator, view: CellView) -> Self {
        Self {
            operator,
            view,
            queue: VecDeque::new(),
            current: None,
            driving: None,
            timeline: Vec::new(),
        }
    }

    /// Robot `robot` asks `question` at `now_s`.
    pub fn ask(&mut self, robot: usize, now_s: f64, question: Question) {
        self.queue.push_back((robot, now_s, question));
    }

    /// Questions waiting, not counting the one being answered.
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    /// The answers due by `now_s`, each to its robot.
    pub fn answers(&mut self, now_s: f64, truth: &Evaluator<'_>) -> Vec<(usize, Answer)> {
        let mut out = Vec::new();
        loop {
            if self.current.is_none() {
                let Some((robot, asked_s, question)) = self.queue.pop_front() else {
                    break;
                };
                self.current = Some(self.attend(robot, asked_s, now_s, question, truth));
            }
            let Some((robot, asked_s, started_s, due_s, answer, was_victim)) = self.current else {
                break;
            };
            if due_s > now_s {
                break;
            }
            self.current = None;
            self.timeline.push(HandOffRecord {
                robot,
                kind: match answer {
                    Answer::Victim(_) => "victim",
                    Answer::Drive(_) => "drive",
                },
                asked_s,
                started_s,
                answered_s: due_s,
                answer: match answer {
                    Answer::Victim(d) => format!("{d:?}").to_lowercase(),
                    Answer::Drive(a) => format!("{a:?}").to_lowercase(),
                },
                was_victim,
            });
            out.push((robot, answer));
        }
        out
    }

    /// The operator turns to a question at `now_s`: the answer and when it is given.
    fn attend(
        &mut self,
        robot: usize,
        asked_s: f64,
        now_s: f64,
        question: Question,
        truth: &Evaluator<'_>,
    ) -> (usize, f64, f64, f64, Answer, Option<bool>) {
        match question {
            Question::Victim { victim, .. } => {
                self.driving = None;
                let delay = self.operator.response_delay_s();
                let source = truth.truth_of(victim.source);
                let request = VictimRequest {
                    cell: victim.cell,
                    probability: victim.probability,
                    size_m2: victim.size_m2,
                    // A reading the evaluator does not know is a heat source that is none.
                    truth: source.unwrap_or(HeatTruth::Other(u32::MAX)),
                };
                let answer = Answer::Victim(self.operator.identify_victim(&request));
                let was_victim = Some(matches!(source, Some(HeatTruth::Victim(_))));
                (robot, asked_s, now_s, now_s + delay, answer, was_victim)
            }
            Question::Drive {
                mut request,
                neighbours_at,
            } => {
                let delay = if self.driving == Some(robot) {
                    self.operator.command_time_s()
                } else {
                    self.operator.response_delay_s()
                };
                self.driving = Some(robot);
                request.camera = neighbours_at.map(|p| self.camera(p, truth));
                let answer = Answer::Drive(self.operator.drive(&request));
                (robot, asked_s, now_s, now_s + delay, answer, None)
            }
        }
    }

    /// What a camera shows of the cell around `p`: its terrain, and whether a victim lies there.
    fn camera(&self, p: Point2, truth: &Evaluator<'_>) -> (CellClass, bool) {
        let Some(cell) = self.view.cell_of(p) else {
            return (CellClass::NonClimbable, false);
        };
        let victim = truth
            .scene()
            .victims
            .iter()
            .any(|v| self.view.cell_of(v.position) == Some(cell));
        (self.view.terrain_class(cell), victim)
    }
}

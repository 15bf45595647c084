//! One operator for many robots (paper 000 §IV-A-5, §VII-B): hand-off questions wait in a
//! queue and the operator answers one at a time, each after a response time — so a robot
//! asking while the operator is busy waits longer. While the operator drives a stuck robot its
//! next command follows after the command time, not a fresh response.
//!
//! The desk stands for the person looking at the robots' cameras: it answers through a
//! [`SimulatedOperator`] from what the camera shows, which in simulation is the scene
//! (through the host's [`Evaluator`] and the scene's [`CellView`]). Robots never see it.

use crate::controller::{Answer, Question};
use crate::exploration::Direction;
use crate::operator::{HandOff, NavigationRequest, SimulatedOperator, VictimRequest};
use serde::Serialize;
use std::collections::VecDeque;
use usar_sim::CellAction;
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

/// The question the operator is answering.
#[derive(Clone, Copy, Debug)]
struct Attending {
    robot: usize,
    question: Question,
    asked_s: f64,
    started_s: f64,
    due_s: f64,
    answer: Answer,
    was_victim: Option<bool>,
}

/// The commands given to `robot` from one cell and heading that left it there.
#[derive(Clone, Debug)]
struct Tried {
    robot: usize,
    cell: (i32, i32),
    heading: Direction,
    commands: Vec<CellAction>,
}

/// An answer given: to which robot, for which question.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Answered {
    pub robot: usize,
    pub question: Question,
    pub answer: Answer,
    pub time_s: f64,
}

/// See the [module documentation](self).
pub struct OperatorDesk {
    operator: SimulatedOperator,
    view: CellView,
    queue: VecDeque<(usize, f64, Question)>,
    /// The question being answered.
    current: Option<Attending>,
    /// The robot the operator drove last (its next command needs no new response).
    driving: Option<usize>,
    /// Questions asked so far.
    pub asked: usize,
    /// Per robot driven: where it was asked from and the commands given there.
    tried: Vec<Tried>,
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
            asked: 0,
            tried: Vec::new(),
            timeline: Vec::new(),
        }
    }

    /// Robot `robot` asks `question` at `now_s`.
    pub fn ask(&mut self, robot: usize, now_s: f64, question: Question) {
        self.asked += 1;
        self.queue.push_back((robot, now_s, question));
    }

    /// Questions waiting, not counting the one being answered.
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    /// The answers due by `now_s`, each to its robot.
    pub fn answers(&mut self, now_s: f64, truth: &Evaluator<'_>) -> Vec<Answered> {
        let mut out = Vec::new();
        loop {
            let current = match self.current {
                Some(c) => c,
                None => {
                    let Some((robot, asked_s, question)) = self.queue.pop_front() else {
                        break;
                    };
                    let c = self.attend(robot, asked_s, now_s, question, truth);
                    self.current = Some(c);
                    c
                }
            };
            if current.due_s > now_s {
                break;
            }
            self.current = None;
            self.timeline.push(HandOffRecord {
                robot: current.robot,
                kind: match current.answer {
                    Answer::Victim(_) => "victim",
                    Answer::Drive(_) => "drive",
                },
                asked_s: current.asked_s,
                started_s: current.started_s,
                answered_s: current.due_s,
                answer: match current.answer {
                    Answer::Victim(d) => format!("{d:?}").to_lowercase(),
                    Answer::Drive(a) => format!("{a:?}").to_lowercase(),
                },
                was_victim: current.was_victim,
            });
            out.push(Answered {
                robot: current.robot,
                question: current.question,
                answer: current.answer,
                time_s: current.due_s,
            });
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
    ) -> Attending {
        let (delay, answer, was_victim) = match question {
            Question::Victim {
                source,
                probability,
                size_m2,
                at,
            } => {
                self.driving = None;
                let delay = self.operator.response_delay_s();
                let source = truth.truth_of(source);
                let cell = self.view.cell_of(at).map_or((-1, -1), |c| (c.col, c.row));
                let request = VictimRequest {
                    cell,
                    probability,
                    size_m2,
                    // A reading the evaluator does not know is a heat source that is none.
                    truth: source.unwrap_or(HeatTruth::Other(u32::MAX)),
                };
                let answer = Answer::Victim(self.operator.identify_victim(&request));
                (
                    delay,
                    answer,
                    Some(matches!(source, Some(HeatTruth::Victim(_)))),
                )
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
                (delay, Answer::Drive(self.drive(robot, &request)), None)
            }
        };
        Attending {
            robot,
            question,
            asked_s,
            started_s: now_s,
            due_s: now_s + delay,
            answer,
            was_victim,
        }
    }

    /// The operator's command for `robot`. A person does not repeat a command that left the
    /// robot where it was: asked again from the same cell and heading, the operator gives one
    /// not tried there yet (reverse first, then the turns, then forward), as long as one is
    /// left.
    fn drive(&mut self, robot: usize, request: &NavigationRequest) -> CellAction {
        let wanted = self.operator.drive(request);
        let here = Tried {
            robot,
            cell: request.cell,
            heading: request.heading,
            commands: Vec::new(),
        };
        let k = match self.tried.iter().position(|t| t.robot == robot) {
            Some(k) => k,
            None => {
                self.tried.push(here.clone());
                self.tried.len() - 1
            }
        };
        let entry = &mut self.tried[k];
        if (entry.cell, entry.heading) != (request.cell, request.heading) {
            *entry = here;
        }
        let command = if entry.commands.contains(&wanted) {
            [
                CellAction::Backward,
                CellAction::RotateLeft,
                CellAction::RotateRight,
                CellAction::Forward,
            ]
            .into_iter()
            .find(|a| !entry.commands.contains(a))
            .unwrap_or(wanted)
        } else {
            wanted
        };
        entry.commands.push(command);
        command
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

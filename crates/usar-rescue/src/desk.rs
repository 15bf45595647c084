//! One operator for many robots (paper 000 §IV-A-5, §VII-B): hand-off questions wait in a
//! queue and the operator answers one at a time, each after a response time — so a robot
//! asking while the operator is busy waits longer. While the operator drives a stuck robot its
//! next command follows after the command time, not a fresh response.
//!
//! The desk stands for the person looking at the robots' cameras. A simulated one
//! ([`OperatorDesk::new`]) answers through a [`SimulatedOperator`] from what the camera shows,
//! which in simulation is the scene (through the host's [`Evaluator`] and the scene's
//! [`CellView`]). A real one ([`OperatorDesk::person`], the operator console) is shown the
//! question being attended ([`OperatorDesk::attending`]) and answers it when they choose
//! ([`OperatorDesk::respond`]). Robots never see it.

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
    id: u64,
    robot: usize,
    question: Question,
    asked_s: f64,
    started_s: f64,
    /// The answer and when it is given; a person's is unknown until they give it.
    answer: Option<(Answer, f64)>,
    was_victim: Option<bool>,
}

/// The question the operator is looking at, as a display shows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attended {
    /// The question's number on the desk (from 1, in the order asked).
    pub id: u64,
    pub robot: usize,
    pub question: Question,
    pub asked_s: f64,
}

/// Who answers at the desk.
enum Attendant {
    Simulated(SimulatedOperator),
    /// A person, through [`OperatorDesk::respond`].
    Person,
}

/// Why a person's answer was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RespondError {
    #[error("no hand-off is waiting for an answer")]
    NothingAsked,
    #[error("hand-off {found} is not the one being answered ({expected})")]
    NotAttended { found: u64, expected: u64 },
    #[error("hand-off {0} asks for {1}")]
    WrongKind(u64, &'static str),
    #[error("the desk's operator is simulated")]
    Simulated,
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
    attendant: Attendant,
    view: CellView,
    queue: VecDeque<(u64, usize, f64, Question)>,
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
        Self::with(Attendant::Simulated(operator), view)
    }

    /// A desk a person answers at ([`Self::respond`]).
    pub fn person(view: CellView) -> Self {
        Self::with(Attendant::Person, view)
    }

    fn with(attendant: Attendant, view: CellView) -> Self {
        Self {
            attendant,
            view,
            queue: VecDeque::new(),
            current: None,
            driving: None,
            asked: 0,
            tried: Vec::new(),
            timeline: Vec::new(),
        }
    }

    /// Robot `robot` asks `question` at `now_s`; the question's number.
    pub fn ask(&mut self, robot: usize, now_s: f64, question: Question) -> u64 {
        self.asked += 1;
        let id = self.asked as u64;
        self.queue.push_back((id, robot, now_s, question));
        id
    }

    /// Questions waiting, not counting the one being answered.
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    /// The question being answered, then those waiting, in order.
    pub fn questions(&self) -> impl Iterator<Item = Attended> + '_ {
        let current = self.current.map(|c| Attended {
            id: c.id,
            robot: c.robot,
            question: c.question,
            asked_s: c.asked_s,
        });
        current
            .into_iter()
            .chain(
                self.queue
                    .iter()
                    .map(|&(id, robot, asked_s, question)| Attended {
                        id,
                        robot,
                        question,
                        asked_s,
                    }),
            )
    }

    /// The question the operator is looking at.
    pub fn attending(&self) -> Option<Attended> {
        self.current.and(self.questions().next())
    }

    /// A person's answer to question `id` (the one being attended) at `now_s`; it reaches the
    /// robot through the next [`Self::answers`].
    pub fn respond(&mut self, id: u64, answer: Answer, now_s: f64) -> Result<(), RespondError> {
        if matches!(self.attendant, Attendant::Simulated(_)) {
            return Err(RespondError::Simulated);
        }
        let current = self.current.as_mut().ok_or(RespondError::NothingAsked)?;
        if current.id != id || current.answer.is_some() {
            return Err(RespondError::NotAttended {
                found: id,
                expected: current.id,
            });
        }
        match (current.question, answer) {
            (Question::Victim { .. }, Answer::Victim(_))
            | (Question::Drive { .. }, Answer::Drive(_)) => {}
            (Question::Victim { .. }, Answer::Drive(_)) => {
                return Err(RespondError::WrongKind(id, "tag or reject"));
            }
            (Question::Drive { .. }, Answer::Victim(_)) => {
                return Err(RespondError::WrongKind(id, "a driving command"));
            }
        }
        current.answer = Some((answer, now_s.max(current.started_s)));
        Ok(())
    }

    /// The answers due by `now_s`, each to its robot.
    pub fn answers(&mut self, now_s: f64, truth: &Evaluator<'_>) -> Vec<Answered> {
        let mut out = Vec::new();
        loop {
            let current = match self.current {
                Some(c) => c,
                None => {
                    let Some((id, robot, asked_s, question)) = self.queue.pop_front() else {
                        break;
                    };
                    let c = self.attend(id, robot, asked_s, now_s, question, truth);
                    self.current = Some(c);
                    c
                }
            };
            let Some((answer, due_s)) = current.answer.filter(|&(_, due)| due <= now_s) else {
                break;
            };
            self.current = None;
            self.timeline.push(HandOffRecord {
                robot: current.robot,
                kind: match answer {
                    Answer::Victim(_) => "victim",
                    Answer::Drive(_) => "drive",
                },
                asked_s: current.asked_s,
                started_s: current.started_s,
                answered_s: due_s,
                answer: match answer {
                    Answer::Victim(d) => format!("{d:?}").to_lowercase(),
                    Answer::Drive(a) => format!("{a:?}").to_lowercase(),
                },
                was_victim: current.was_victim,
            });
            out.push(Answered {
                robot: current.robot,
                question: current.question,
                answer,
                time_s: due_s,
            });
        }
        out
    }

    /// The operator turns to question `id` at `now_s`: a simulated operator decides its answer
    /// and when it is given; a person answers later.
    fn attend(
        &mut self,
        id: u64,
        robot: usize,
        asked_s: f64,
        now_s: f64,
        question: Question,
        truth: &Evaluator<'_>,
    ) -> Attending {
        let was_victim = match question {
            Question::Victim { source, .. } => {
                Some(matches!(truth.truth_of(source), Some(HeatTruth::Victim(_))))
            }
            Question::Drive { .. } => None,
        };
        // The operator is taken off the desk while it decides, and put back.
        let answer = match std::mem::replace(&mut self.attendant, Attendant::Person) {
            Attendant::Person => None,
            Attendant::Simulated(mut operator) => {
                let (delay, answer) = self.simulated_answer(&mut operator, robot, question, truth);
                self.attendant = Attendant::Simulated(operator);
                Some((answer, now_s + delay))
            }
        };
        Attending {
            id,
            robot,
            question,
            asked_s,
            started_s: now_s,
            answer,
            was_victim,
        }
    }

    /// The simulated operator's answer to `question` from `robot`, and its delay.
    fn simulated_answer(
        &mut self,
        operator: &mut SimulatedOperator,
        robot: usize,
        question: Question,
        truth: &Evaluator<'_>,
    ) -> (f64, Answer) {
        match question {
            Question::Victim {
                source,
                probability,
                size_m2,
                at,
            } => {
                self.driving = None;
                let delay = operator.response_delay_s();
                let cell = self.view.cell_of(at).map_or((-1, -1), |c| (c.col, c.row));
                let request = VictimRequest {
                    cell,
                    probability,
                    size_m2,
                    // A reading the evaluator does not know is a heat source that is none.
                    truth: truth.truth_of(source).unwrap_or(HeatTruth::Other(u32::MAX)),
                };
                (delay, Answer::Victim(operator.identify_victim(&request)))
            }
            Question::Drive {
                mut request,
                neighbours_at,
            } => {
                let delay = if self.driving == Some(robot) {
                    operator.command_time_s()
                } else {
                    operator.response_delay_s()
                };
                self.driving = Some(robot);
                request.camera = neighbours_at.map(|p| self.camera(p, truth));
                (delay, Answer::Drive(self.drive(operator, robot, &request)))
            }
        }
    }

    /// The operator's command for `robot`. A person does not repeat a command that left the
    /// robot where it was: asked again from the same cell and heading, the operator gives one
    /// not tried there yet (reverse first, then the turns, then forward), as long as one is
    /// left.
    fn drive(
        &mut self,
        operator: &mut SimulatedOperator,
        robot: usize,
        request: &NavigationRequest,
    ) -> CellAction {
        let wanted = operator.drive(request);
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

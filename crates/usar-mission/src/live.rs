//! A mission with someone beside it (the operator console, a recorder): the same host,
//! controllers and evaluation as [`crate::run_mission`] ([`crate::run_mission_live`]), stepped
//! one simulation step at a time with a
//! [`MissionHook`] called between the controllers' decisions and the world's move. Through a
//! [`LiveMission`] the hook looks at what the robots report, answers hand-offs as a person at
//! the desk ([`Operator::Person`]), takes a team robot's wheels (teleoperation), changes the
//! team's hypothesis or the rescuer's exploration weights, paces the run or ends it.

use crate::board::VictimBoard;
use crate::mission::Mission;
use usar_btm::build::{BuildError, Explorer, StopReason};
use usar_rescue::controller::{Answer, RescueController};
use usar_rescue::desk::{OperatorDesk, RespondError};
use usar_sim::RobotId;
use usar_sim::Velocity;
use usar_sim::host::Evaluator;
use usar_team::TeamController;

/// Who answers the hand-offs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operator {
    /// The mission file's simulated operator (`[operator]`).
    Simulated,
    /// A person, through [`LiveMission::respond`].
    Person,
}

/// Called once per simulation step (see the [module documentation](self)).
pub trait MissionHook {
    /// After every controller decided and the hand-offs were exchanged, before the world
    /// moves; `false` ends the mission.
    fn after_decide(&mut self, mission: &mut LiveMission<'_, '_>) -> bool;
}

/// Two hooks beside one mission (the console and a recorder): each is called every step; the
/// mission ends when either ends it.
impl<A: MissionHook + ?Sized, B: MissionHook + ?Sized> MissionHook for (&mut A, &mut B) {
    fn after_decide(&mut self, mission: &mut LiveMission<'_, '_>) -> bool {
        let a = self.0.after_decide(mission);
        let b = self.1.after_decide(mission);
        a && b
    }
}

/// The hook of a mission nobody watches.
pub(crate) struct Unwatched;

impl MissionHook for Unwatched {
    fn after_decide(&mut self, _: &mut LiveMission<'_, '_>) -> bool {
        true
    }
}

/// A running mission as its hook sees it.
pub struct LiveMission<'m, 'a> {
    pub(crate) mission: &'m mut Mission<'a>,
}

impl LiveMission<'_, '_> {
    /// Simulated seconds since the start.
    pub fn time_s(&self) -> f64 {
        self.mission.host.time_s()
    }

    /// The simulated time limit, seconds.
    pub fn end_s(&self) -> f64 {
        self.mission.steps as f64 * self.mission.host.dt_s()
    }

    /// The world as the evaluation sees it (true poses, the scene): for pictures, such as the
    /// camera images a person at the desk is shown. Never hand it to a controller.
    pub fn evaluator(&self) -> Evaluator<'_> {
        self.mission.host.evaluator()
    }

    /// The team's controller (its base station, its robots' beliefs).
    pub fn team(&self) -> &TeamController {
        &self.mission.team.team
    }

    pub fn team_mut(&mut self) -> &mut TeamController {
        &mut self.mission.team.team
    }

    /// The host's id of team robot `k` (from 0).
    pub fn team_robot(&self, k: usize) -> Option<RobotId> {
        self.mission
            .host
            .fleet(self.mission.team_fleet)
            .get(k)
            .copied()
    }

    /// How many robots the team has.
    pub fn team_len(&self) -> usize {
        self.mission.host.fleet(self.mission.team_fleet).len()
    }

    /// Replaces the command the team gave robot `k` this step (teleoperation).
    pub fn override_team(&mut self, k: usize, command: Velocity) {
        if let Some(id) = self.team_robot(k) {
            self.mission.host.override_command(id, command);
        }
    }

    /// The crawler building the Behavioral Trace Map, if the mission has one.
    pub fn crawler(&self) -> Option<&Explorer<'_>> {
        self.mission
            .crawler
            .as_ref()
            .map(|c| &c.controller.explorer)
    }

    /// The host's id of the crawler.
    pub fn crawler_robot(&self) -> Option<RobotId> {
        let c = self.mission.crawler.as_ref()?;
        self.mission.host.fleet(c.fleet).first().copied()
    }

    /// Why the crawler's exploration ended, once it has.
    pub fn crawler_finished(&self) -> Option<&Result<StopReason, BuildError>> {
        self.mission.crawler.as_ref()?.controller.finished.as_ref()
    }

    /// Paper 000's rescuer, if the mission has one.
    pub fn rescuer(&self) -> Option<&RescueController> {
        self.mission.rescuer.as_ref().map(|r| &r.controller)
    }

    pub fn rescuer_mut(&mut self) -> Option<&mut RescueController> {
        self.mission.rescuer.as_mut().map(|r| &mut r.controller)
    }

    /// The host's id of the rescuer.
    pub fn rescuer_robot(&self) -> Option<RobotId> {
        let r = self.mission.rescuer.as_ref()?;
        self.mission.host.fleet(r.fleet).first().copied()
    }

    /// The operator's desk: the question attended and those waiting.
    pub fn desk(&self) -> &OperatorDesk {
        &self.mission.desk
    }

    /// A person's answer to hand-off `id`, now; it reaches its robot at the next step.
    pub fn respond(&mut self, id: u64, answer: Answer) -> Result<(), RespondError> {
        let now = self.time_s();
        self.mission.desk.respond(id, answer, now)
    }

    /// The base station's board of the team's victim reports.
    pub fn board(&self) -> &VictimBoard {
        &self.mission.board
    }

    /// Coverage of the reachable free floor by the team's merged map (evaluation).
    pub fn coverage(&self) -> f64 {
        self.mission.eval.coverage()
    }

    /// Relevant area the team's merged map knows, m² (evaluation).
    pub fn relevant_area_m2(&self) -> f64 {
        self.mission.eval.relevant_area_m2()
    }
}

/// The desk `operator` sits at: the simulated operator's, or a person's.
pub(crate) fn desk_for(
    operator: Operator,
    simulated: usar_rescue::operator::SimulatedOperator,
    view: usar_world::cellview::CellView,
) -> OperatorDesk {
    match operator {
        Operator::Simulated => OperatorDesk::new(simulated, view),
        Operator::Person => OperatorDesk::person(view),
    }
}

//! The mission with someone beside it: watching changes nothing, a person at the desk answers
//! every hand-off, and a team robot's wheels can be taken.

use std::sync::Arc;
use usar_mission::{
    LiveMission, MissionConfig, MissionHook, Operator, run_mission, run_mission_live,
};
use usar_rescue::controller::{Answer, Question};
use usar_rescue::operator::VictimDecision;
use usar_sim::{CellAction, Velocity};
use usar_world::generate::{SceneKind, generate};

fn config(minutes: f64) -> MissionConfig {
    let mut c = MissionConfig {
        minutes,
        ..MissionConfig::default()
    };
    c.team.robots = 2;
    c.crawler.enabled = false;
    c.rescuer.train_trials = 100;
    c
}

/// Looks at everything a console looks at, every step, and changes nothing.
struct Watcher {
    steps: u64,
}

impl MissionHook for Watcher {
    fn after_decide(&mut self, live: &mut LiveMission<'_, '_>) -> bool {
        self.steps += 1;
        let _ = (
            live.team().pose(0),
            live.desk().attending(),
            live.board().entries.len(),
        );
        let _ = (live.rescuer().map(|r| r.log.primitives), live.coverage());
        true
    }
}

#[test]
fn a_watched_mission_is_the_unwatched_one() {
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let config = config(1.0);
    let plain = run_mission(scene.clone(), &config, 4, None, |_| {}).unwrap();
    let mut watcher = Watcher { steps: 0 };
    let watched = run_mission_live(
        scene,
        &config,
        4,
        None,
        Operator::Simulated,
        |_| {},
        &mut watcher,
    )
    .unwrap();
    assert_eq!(
        serde_json::to_string(&plain).unwrap(),
        serde_json::to_string(&watched).unwrap()
    );
    // One call per step, the last included.
    assert_eq!(watcher.steps, (60.0 / 0.1) as u64 + 1);
}

/// A person who confirms every victim and turns the stuck robot right, at once.
struct Person {
    answered: Vec<u64>,
}

impl MissionHook for Person {
    fn after_decide(&mut self, live: &mut LiveMission<'_, '_>) -> bool {
        if let Some(q) = live.desk().attending()
            && !self.answered.contains(&q.id)
        {
            let answer = match q.question {
                Question::Victim { .. } => Answer::Victim(VictimDecision::Tag),
                Question::Drive { .. } => Answer::Drive(CellAction::RotateRight),
            };
            live.respond(q.id, answer).unwrap();
            // The same question cannot be answered twice, nor with the other kind.
            assert!(live.respond(q.id, answer).is_err());
            self.answered.push(q.id);
        }
        true
    }
}

#[test]
fn a_person_at_the_desk_answers_every_hand_off() {
    let scene = Arc::new(generate(SceneKind::Office, 1));
    // Run seed 4: the rescuer gets stuck in its first minute and a team robot reports a warm
    // region within eight (as with the simulated operator).
    let config = config(10.0);
    let mut person = Person {
        answered: Vec::new(),
    };
    let out = run_mission_live(
        scene,
        &config,
        4,
        None,
        Operator::Person,
        |_| {},
        &mut person,
    )
    .unwrap();
    let kinds = |k: &str| out.handoffs.iter().filter(|h| h.kind == k).count();
    assert!(
        kinds("victim") >= 1 && kinds("drive") >= 1,
        "{:?}",
        out.handoffs
    );
    // Every answer given reached its robot (the last may be given as time runs out).
    assert!(out.handoffs.len() + 1 >= person.answered.len());
    assert!(
        out.handoffs
            .iter()
            .all(|h| h.answer == "tag" || h.answer == "rotateright")
    );
    // A person answers at once: no response time.
    assert!(
        out.handoffs
            .iter()
            .all(|h| h.answered_s <= h.started_s + 0.1 + 1e-9)
    );
    assert!(
        out.victims.iter().any(|v| v.confirmed_by.is_some()),
        "{:?}",
        out.victims
    );
}

/// Takes team robot 0's wheels: full speed ahead for ten seconds, then gives them back.
struct Teleoperator;

impl MissionHook for Teleoperator {
    fn after_decide(&mut self, live: &mut LiveMission<'_, '_>) -> bool {
        if live.time_s() < 10.0 {
            live.override_team(
                0,
                Velocity {
                    linear_mps: 0.0,
                    angular_radps: 0.5,
                },
            );
        }
        true
    }
}

#[test]
fn a_teleoperated_team_robot_obeys_the_operator_not_its_team() {
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let config = config(0.2);
    let out = run_mission_live(
        scene,
        &config,
        1,
        None,
        Operator::Simulated,
        |_| {},
        &mut Teleoperator,
    )
    .unwrap();
    // Turning in place for ten seconds: the robot's first trajectory samples stay put.
    let trajectory = &out.team_trajectories[0];
    let start = trajectory[0];
    assert!(
        trajectory.iter().take(10).all(|p| p.distance(start) < 0.05),
        "{trajectory:?}"
    );
    let plain = run_mission(
        Arc::new(generate(SceneKind::Office, 1)),
        &config,
        1,
        None,
        |_| {},
    )
    .unwrap();
    assert!(
        plain.team_trajectories[0]
            .iter()
            .take(10)
            .any(|p| p.distance(start) > 0.2)
    );
}

//! Driving and recovering from bumps.

use std::sync::Arc;
use usar_sim::{RobotSpec, SimConfig, Simulation, Velocity};
use usar_team::driver::{PathFollower, Recovery, RecoveryStep};
use usar_world::scene::obstacle;
use usar_world::{Cell, GridGeometry, Point2, Pose2, Scene};

/// A floor at 5 cm where all is blocked but an open box (x < 2 m, 3 m ≤ y ≤ 5 m) and, leading
/// out of it, a quarter-circle slot 0.6 m wide round (2, 5.2) m with radius 1.2 m, closed at its
/// north end: the wheeled robot (0.5 × 0.4 m) follows the bend but cannot turn in it.
fn bent_slot() -> Arc<Scene> {
    let g = GridGeometry::new(120, 140, 0.05, Point2::new(0.0, 0.0));
    let mut scene = Scene::empty("bent slot", g);
    let centre = Point2::new(2.0, 5.2);
    for row in 0..g.height as i32 {
        for col in 0..g.width as i32 {
            let c = g.cell_center(Cell::new(col, row));
            let in_box = c.x > 0.1 && c.x < 2.0 && c.y > 3.0 && c.y < 5.0;
            let in_slot = c.x >= 2.0 && c.y <= 5.2 && (c.distance(centre) - 1.2).abs() <= 0.3;
            if !(in_box || in_slot) {
                scene.obstacle[Cell::new(col, row)] = obstacle::WALL;
            }
        }
    }
    Arc::new(scene)
}

/// Drives `spec` into the dead end of [`bent_slot`], then sends it back out with the path
/// follower and `recovery`; returns when it left the slot (None: still in it after 300 s).
fn backs_out_of_the_bent_slot(spec: RobotSpec, mut recovery: Recovery) -> Option<f64> {
    let mut sim = Simulation::new(bent_slot(), SimConfig::default(), 1);
    let id = sim
        .add_robot(spec.clone(), Pose2::new(1.0, 4.0, 0.0))
        .unwrap();
    // Drive 1 m east, then round the bend (radius 1.2 m) until the dead end stops the robot.
    let v = spec.max_linear_mps;
    while !sim.robot(id).in_contact() {
        let turning = if sim.robot(id).pose.x < 2.0 {
            0.0
        } else {
            v / 1.2
        };
        sim.step(&[Velocity {
            linear_mps: v,
            angular_radps: turning,
        }]);
        recovery.record(sim.robot(id).last_motion(), sim.config().dt_s);
        assert!(sim.time_s() < 100.0, "never reached the dead end");
    }
    let end = sim.robot(id).pose;
    assert!(end.y > 4.8 && end.theta > 1.2, "stopped early at {end:?}");
    // Now it is sent back out: the path follower wants to turn round, which bumps.
    let goal = Point2::new(0.5, 4.0);
    let mut follower = PathFollower::new(vec![sim.robot(id).pose.position(), goal]);
    let start = sim.time_s();
    while sim.time_s() < start + 300.0 {
        let r = sim.robot(id);
        let command = match recovery.step(sim.time_s(), r.in_contact()) {
            RecoveryStep::Escape(v) => v,
            RecoveryStep::Ended | RecoveryStep::Free => follower.command(r.pose, &spec),
        };
        sim.step(&[command]);
        recovery.record(sim.robot(id).last_motion(), sim.config().dt_s);
        if sim.robot(id).pose.x < 1.6 {
            return Some(sim.time_s() - start);
        }
    }
    None
}

#[test]
fn a_robot_that_bumps_at_the_end_of_a_bent_slot_too_narrow_to_turn_in_backs_out_the_way_it_came() {
    let spec = RobotSpec::wheeled();
    assert!(backs_out_of_the_bent_slot(spec.clone(), Recovery::for_robot(&spec)).is_some());
}

#[test]
fn a_slow_robot_retraces_as_far_as_a_fast_one_and_backs_out_sooner() {
    // The wheeled robot at 0.6 × its speeds: recovery manoeuvres timed for 0.5 m/s undo too
    // little of its motion at each bump; timed for its own speeds, it is out sooner.
    let spec = RobotSpec {
        max_linear_mps: 0.3,
        max_angular_radps: 0.72,
        ..RobotSpec::wheeled()
    };
    let fixed = backs_out_of_the_bent_slot(spec.clone(), Recovery::default()).unwrap();
    let own = backs_out_of_the_bent_slot(spec.clone(), Recovery::for_robot(&spec)).unwrap();
    assert!(
        own < fixed,
        "{own} s with its own timing, {fixed} s with the fixed one"
    );
}

#[test]
fn a_very_slow_robot_backs_out_too_because_each_failed_recovery_retraces_twice_as_far() {
    // The wheeled robot at paper 002's pace (0.3 × its speeds): a retrace of 0.5 m undoes
    // little more than the turn that bumped it in the bend; repeated, the retraces lengthen.
    let spec = RobotSpec::wheeled_paper_pace();
    assert!(backs_out_of_the_bent_slot(spec.clone(), Recovery::for_robot(&spec)).is_some());
}

/// How many 0.1 s steps the retrace started by a bump at `now_s` lasts (the robot is free of
/// contact while it retraces).
fn retrace_steps(recovery: &mut Recovery, now_s: &mut f64) -> usize {
    let mut steps = 0;
    let mut contact = true;
    while let RecoveryStep::Escape(v) = recovery.step(*now_s, contact) {
        recovery.record(v, 0.1);
        contact = false;
        steps += 1;
        *now_s += 0.1;
    }
    steps
}

#[test]
fn a_retrace_doubles_after_a_recovery_that_did_not_free_the_robot_and_not_after_one_that_did() {
    let forward = Velocity {
        linear_mps: 0.5,
        angular_radps: 0.0,
    };
    let turn = Velocity {
        linear_mps: 0.0,
        angular_radps: 0.8,
    };
    let mut recovery = Recovery::default();
    let mut now = 0.0;
    for _ in 0..200 {
        recovery.record(forward, 0.1);
    }
    // A first bump retraces 1 s; turning on the spot and bumping again, 2 s, then 4 s.
    let first = retrace_steps(&mut recovery, &mut now);
    assert!((10..=11).contains(&first), "{first} steps");
    recovery.record(turn, 0.1);
    let second = retrace_steps(&mut recovery, &mut now);
    assert!(second.abs_diff(2 * first) <= 2, "{second} after {first}");
    recovery.record(turn, 0.1);
    let third = retrace_steps(&mut recovery, &mut now);
    assert!(third.abs_diff(4 * first) <= 4, "{third} after {first}");
    // Having driven 1 m away, a bump is a new one: 1 s again.
    for _ in 0..20 {
        recovery.record(forward, 0.1);
    }
    assert!(retrace_steps(&mut recovery, &mut now).abs_diff(first) <= 1);
}

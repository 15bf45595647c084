//! The team decides from its robots' sensors only: with the semantic oracle off, garbage in the
//! scene's layers a robot cannot sense — room ids, labels, doors, corridor links, the victim
//! list, junctions — changes none of its decisions (the targets it allocates, the ways its
//! robots drive). With the oracle on, the same garbage does change them: the test can fail.

use super::explore::small_office;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;
use usar_team::coordination::Coordination;
use usar_team::{Exploration, Semantics, Strategy, TeamConfig, TeamMission, TeamOutcome};
use usar_world::{Door, Junction, JunctionKind, Point2, RoomLabel, Scene, Victim};

/// `scene` with every layer a robot cannot sense replaced by random values.
fn garbage(scene: &Scene, seed: u64) -> Scene {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut s = scene.clone();
    let rooms = s.rooms.len() as u16;
    for id in s.room_id.as_mut_slice() {
        *id = rng.random_range(0..=rooms);
    }
    for room in &mut s.rooms {
        room.label = RoomLabel::ALL[rng.random_range(0..4)];
        room.door_ids = (0..rng.random_range(0..6)).collect();
        room.intersecting_corridors = (0..rng.random_range(0..3)).map(|k| k + 1).collect();
    }
    let (w, h) = s.geometry().extent_m();
    let somewhere =
        |rng: &mut Pcg64Mcg| Point2::new(rng.random_range(0.0..w), rng.random_range(0.0..h));
    s.doors = (0..7)
        .map(|id| Door {
            id,
            position: somewhere(&mut rng),
            width_m: rng.random_range(0.5..2.0),
            rooms: [rng.random_range(0..=rooms), rng.random_range(0..=rooms)],
        })
        .collect();
    s.victims = (0..5)
        .map(|id| Victim {
            id,
            position: somewhere(&mut rng),
            heat_c: rng.random_range(30.0..37.0),
            visible_size_m2: 0.4,
            buried_fraction: rng.random_range(0.0..0.8),
        })
        .collect();
    s.ground_truth.junctions = (0..9)
        .map(|_| Junction {
            kind: JunctionKind::Crossing,
            position: somewhere(&mut rng),
        })
        .collect();
    s
}

fn run(scene: Scene, semantics: Semantics) -> TeamOutcome {
    let mut config = TeamConfig::paper_002(
        4,
        2.0,
        Exploration {
            strategy: Strategy::SMcdm,
            coordination: Coordination::Mrv1,
            ..Exploration::default()
        },
    );
    config.semantics = semantics;
    TeamMission::new(Arc::new(scene), config, 5)
        .unwrap()
        .run(|_| {})
}

/// What the team decided: every allocation (when, who, where, with which perceived label and
/// bid) and every robot's way.
fn decisions(out: &TeamOutcome) -> String {
    let allocations: Vec<String> = out
        .allocations
        .iter()
        .map(|a| {
            format!(
                "{:.1} {} ({:.2}, {:.2}) {:?} {:.6} {}",
                a.time_s, a.robot, a.x_m, a.y_m, a.label, a.utility, a.ideal_robots
            )
        })
        .collect();
    let ways: Vec<String> = out
        .per_robot
        .iter()
        .map(|r| format!("{:?}", r.trajectory))
        .collect();
    format!("{allocations:#?}\n{ways:#?}")
}

#[test]
fn garbage_in_what_robots_cannot_sense_changes_no_decision_of_the_team() {
    let scene = small_office();
    let spoiled = garbage(&scene, 11);
    let clean = run(scene.clone(), Semantics::Segmented);
    assert!(
        clean.allocations.len() >= 4,
        "the team allocated {} targets",
        clean.allocations.len()
    );
    assert_eq!(
        decisions(&clean),
        decisions(&run(spoiled.clone(), Semantics::Segmented))
    );
    let oracle = run(scene, Semantics::Oracle);
    let fooled = run(spoiled, Semantics::Oracle);
    assert_ne!(
        decisions(&oracle),
        decisions(&fooled),
        "with the semantic oracle on, the room layer steers the team"
    );
}

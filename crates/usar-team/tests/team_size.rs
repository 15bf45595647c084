//! The fuzzy ideal team size against the sample rules of paper 002's Algorithms 1–2.

use usar_team::fuzzy::Mamdani;
use usar_team::team_size::{corridor_system, ideal_robots, room_system};

/// The consequent of the rule whose antecedents are `terms` (names, one per input).
fn consequent(system: &Mamdani, terms: &[&str]) -> String {
    let idx: Vec<usize> = system
        .inputs
        .iter()
        .zip(terms)
        .map(|(v, t)| v.term(t).unwrap())
        .collect();
    let rule = system.rules.iter().find(|r| r.antecedents == idx).unwrap();
    system.output.terms[rule.consequent].0.clone()
}

#[test]
fn the_rule_bases_contain_every_sample_rule_of_algorithms_1_and_2() {
    let room = room_system();
    assert_eq!(room.rules.len(), 81);
    assert_eq!(
        consequent(&room, &["SMALL", "HIGH", "LOW", "MEDIUM"]),
        "MEDIUM"
    );
    assert_eq!(consequent(&room, &["BIG", "LOW", "LOW", "HIGH"]), "LOW");
    assert_eq!(
        consequent(&room, &["BIG", "MEDIUM", "MEDIUM", "LOW"]),
        "HIGH"
    );
    let corridor = corridor_system();
    assert_eq!(corridor.rules.len(), 81);
    assert_eq!(
        consequent(&corridor, &["SMALL", "HIGH", "MEDIUM", "MEDIUM"]),
        "LOW"
    );
    assert_eq!(
        consequent(&corridor, &["SMALL", "MEDIUM", "LOW", "LOW"]),
        "MEDIUM"
    );
    assert_eq!(
        consequent(&corridor, &["MEDIUM", "MEDIUM", "MEDIUM", "LOW"]),
        "HIGH"
    );
    assert_eq!(
        consequent(&corridor, &["BIG", "HIGH", "MEDIUM", "LOW"]),
        "VERY_HIGH"
    );
}

#[test]
fn crisp_team_sizes_follow_the_prose() {
    let room = room_system();
    // A big, open, unseen room with three doors: more robots.
    assert_eq!(ideal_robots(&room, &[90.0, 3.0, 0.95, 0.0], 3), 3);
    // A small cluttered room already mostly seen: one.
    assert_eq!(ideal_robots(&room, &[10.0, 1.0, 0.4, 0.9], 3), 1);
    // Monotone in the perceived area.
    let mut last = usize::MAX;
    for seen in [0.0, 0.3, 0.6, 0.9] {
        let n = ideal_robots(&room, &[50.0, 2.0, 0.7, seen], 3);
        assert!(n <= last);
        last = n;
    }
    // Whatever its size, doors and visibility, a room or corridor mostly seen: one.
    assert_eq!(ideal_robots(&room, &[200.0, 4.0, 0.95, 0.9], 3), 1);
    let corridor = corridor_system();
    assert_eq!(ideal_robots(&corridor, &[100.0, 8.0, 3.0, 0.9], 3), 1);
    assert_eq!(ideal_robots(&corridor, &[100.0, 8.0, 2.0, 0.0], 3), 3);
    assert_eq!(ideal_robots(&corridor, &[10.0, 1.0, 0.0, 0.9], 3), 1);
    assert!(ideal_robots(&corridor, &[100.0, 8.0, 2.0, 0.0], 4) == 4);
}

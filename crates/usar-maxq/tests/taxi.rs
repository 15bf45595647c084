//! The MAXQ engine's correctness check on Dietterich's Taxi domain.

use usar_maxq::maxq::Domain;
use usar_maxq::taxi::{
    EAST, NORTH, PICKUP, PUTDOWN, SOUTH, Taxi, TaxiConfig, TaxiState, WEST, optimal_values,
    run_taxi,
};

fn state(row: u8, col: u8, passenger: u8, destination: u8) -> TaxiState {
    TaxiState {
        row,
        col,
        passenger,
        destination,
    }
}

#[test]
fn walls_rewards_and_delivery_follow_dietterich() {
    let mut t = Taxi;
    // The wall between columns 1 and 2 in the top row.
    assert_eq!(t.step(&state(0, 1, 0, 1), EAST).0, state(0, 1, 0, 1));
    assert_eq!(t.step(&state(2, 1, 0, 1), EAST).0, state(2, 2, 0, 1));
    assert_eq!(t.step(&state(4, 1, 0, 1), WEST).0, state(4, 1, 0, 1));
    assert_eq!(t.step(&state(0, 0, 0, 1), NORTH), (state(0, 0, 0, 1), -1.0));
    assert_eq!(t.step(&state(4, 0, 0, 1), SOUTH).0, state(4, 0, 0, 1));
    // Pickup at the passenger's depot, illegal elsewhere.
    assert_eq!(
        t.step(&state(0, 0, 0, 1), PICKUP),
        (state(0, 0, 4, 1), -1.0)
    );
    assert_eq!(t.step(&state(0, 1, 0, 1), PICKUP).1, -10.0);
    // Putdown only at the destination with the passenger aboard.
    let (end, r) = t.step(&state(0, 4, 4, 1), PUTDOWN);
    assert_eq!(r, 20.0);
    assert!(t.is_terminal(&end));
    assert_eq!(t.step(&state(0, 0, 4, 1), PUTDOWN).1, -10.0);
}

#[test]
fn value_iteration_gives_the_known_optimum_of_simple_starts() {
    let v = optimal_values();
    // At R with the passenger, destination R: pick up, put down = −1 + 20.
    assert_eq!(v[state(0, 0, 0, 0).index()], 19.0);
    // At R, passenger at R, destination G (0,4): pickup, 2 south, 3 east... the shortest legal
    // route R→G avoiding the wall is 8 moves: −1 (pickup) − 8 + 20.
    assert_eq!(v[state(0, 0, 0, 1).index()], 11.0);
}

#[test]
fn maxq_reaches_the_optimum_and_sooner_than_flat_q() {
    let report = run_taxi(&TaxiConfig::default());
    assert!(
        report.maxq_return >= report.optimal_return - 0.5,
        "MAXQ {} vs optimal {}",
        report.maxq_return,
        report.optimal_return
    );
    let maxq_at = report
        .maxq_episodes_to_optimal
        .expect("MAXQ reaches the optimum");
    assert!(
        report.flat_episodes_to_optimal.is_none_or(|f| maxq_at < f),
        "MAXQ at {maxq_at}, flat at {:?}",
        report.flat_episodes_to_optimal
    );
    // The state abstractions store fewer values than the 500 × 6 flat table.
    assert!(report.maxq_stored_values < report.flat_stored_values);
}

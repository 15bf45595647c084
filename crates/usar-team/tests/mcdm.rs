//! The Choquet integral and fuzzy measures of paper 002.

use usar_team::mcdm::{
    FuzzyMeasure, MeasureError, MeasureSpec, Sense, d_mcdm_table_1, normalize, s_mcdm_table_1,
};

fn mask(m: &FuzzyMeasure, names: &[&str]) -> usize {
    names
        .iter()
        .map(|n| 1 << m.criteria.iter().position(|c| c == n).unwrap())
        .sum()
}

#[test]
fn table_1_completes_to_a_monotone_normalised_measure() {
    for spec in [s_mcdm_table_1(), d_mcdm_table_1()] {
        let m = FuzzyMeasure::new(&spec).unwrap();
        let n = m.criteria.len();
        let full = (1 << n) - 1;
        assert_eq!((m.mu(0), m.mu(full)), (0.0, 1.0));
        for s in 0..=full {
            assert!(m.mu(s) <= 1.0);
            for i in 0..n {
                assert!(m.mu(s | 1 << i) >= m.mu(s), "not monotone at {s:b} + {i}");
            }
        }
    }
    let s = FuzzyMeasure::new(&s_mcdm_table_1()).unwrap();
    // Listed values are kept; unlisted ones are sums of singletons.
    assert_eq!(s.mu(mask(&s, &["d", "S"])), 0.8);
    assert!((s.mu(mask(&s, &["S", "ND"])) - 0.8).abs() < 1e-12);
    assert!((s.mu(mask(&s, &["A", "ND"])) - 0.39).abs() < 1e-12);
    // {A, d, S, ND}: 0.98 by sum, above μ({A, d, S}) = 0.8.
    assert!((s.mu(mask(&s, &["A", "d", "S", "ND"])) - 0.98).abs() < 1e-12);
}

#[test]
fn choquet_integral_follows_equation_1() {
    let d = FuzzyMeasure::new(&d_mcdm_table_1()).unwrap();
    // Equal utilities give that utility (μ(N) = 1).
    assert!((d.choquet(&[0.4, 0.4, 0.4]) - 0.4).abs() < 1e-12);
    // u_A = 0.2, u_d = 0.6, u_b = 1: 0.2·μ(N) + 0.4·μ({d, b}) + 0.4·μ({b}) = 0.2 + 0.16 + 0.08.
    assert!((d.choquet(&[0.2, 0.6, 1.0]) - 0.44).abs() < 1e-12);
    // A and d are synergic: both good beats the weighted average.
    assert!(d.choquet(&[1.0, 1.0, 0.0]) > 0.4 + 0.4);
    // An additive measure gives the weighted sum.
    let additive = FuzzyMeasure::new(&MeasureSpec {
        criteria: vec!["x".into(), "y".into()],
        weights: vec![(vec!["x".into()], 0.3), (vec!["y".into()], 0.7)],
    })
    .unwrap();
    assert!((additive.choquet(&[0.5, 0.9]) - (0.3 * 0.5 + 0.7 * 0.9)).abs() < 1e-12);
}

#[test]
fn bad_measures_are_errors_naming_the_subset() {
    let mut spec = d_mcdm_table_1();
    spec.weights.push((vec!["A".into(), "z".into()], 0.5));
    let err = FuzzyMeasure::new(&spec).unwrap_err();
    assert!(
        matches!(&err, MeasureError::UnknownCriterion { criterion, .. } if criterion == "z"),
        "{err:?}"
    );
    assert!(err.to_string().contains("unknown criterion `z`"), "{err}");
    let mut spec = d_mcdm_table_1();
    spec.weights[3].1 = 0.1; // μ({A, d}) below μ({A}) = 0.4
    let err = FuzzyMeasure::new(&spec).unwrap_err();
    assert!(err.to_string().contains("μ({A, d}) = 0.1"), "{err}");
    let mut spec = d_mcdm_table_1();
    spec.weights.remove(2);
    assert_eq!(
        FuzzyMeasure::new(&spec).unwrap_err(),
        MeasureError::MissingSingleton("b".into())
    );
}

#[test]
fn normalisation_is_linear_and_relative() {
    let u = normalize(&[Some(2.0), None, Some(6.0), Some(4.0)], Sense::Benefit);
    assert_eq!(u, vec![Some(0.0), None, Some(1.0), Some(0.5)]);
    let c = normalize(&[Some(2.0), Some(6.0)], Sense::Cost);
    assert_eq!(c, vec![Some(1.0), Some(0.0)]);
    assert_eq!(
        normalize(&[Some(3.0), Some(3.0)], Sense::Cost),
        vec![Some(1.0), Some(1.0)]
    );
}

mod criteria {
    use usar_team::criteria::{CandidateInfo, Hypothesis, travel_time_s, utilities};
    use usar_team::mcdm::{FuzzyMeasure, d_mcdm_table_1, s_mcdm_table_1};
    use usar_world::{Point2, RoomLabel};

    #[test]
    fn travel_time_counts_driving_and_turning() {
        let path = [
            Point2::new(0.0, 0.0),
            Point2::new(2.0, 0.0),
            Point2::new(2.0, 2.0),
        ];
        // 4 m at 0.5 m/s, a quarter turn at 1 rad/s.
        let t = travel_time_s(&path, 0.0, 0.5, 1.0);
        assert!((t - (8.0 + std::f64::consts::FRAC_PI_2)).abs() < 1e-12);
    }

    #[test]
    fn s_mcdm_goes_to_the_relevant_room_where_d_mcdm_goes_to_the_nearest() {
        let robots = [Point2::new(0.0, 0.0)];
        let cand = |x: f64, label, doors| CandidateInfo {
            position: Point2::new(x, 0.0),
            frontier_cells: 30,
            label: Some(label),
            doors,
        };
        // A near small room and a farther big room.
        let cands = [
            cand(4.0, RoomLabel::SmallRoom, 1),
            cand(12.0, RoomLabel::BigRoom, 2),
        ];
        let travel = vec![vec![Some(9.0), Some(25.0)]];
        let big = Hypothesis::big_rooms();
        let s = FuzzyMeasure::new(&s_mcdm_table_1()).unwrap();
        let d = FuzzyMeasure::new(&d_mcdm_table_1()).unwrap();
        let us = utilities(&s, &robots, &cands, &travel, &big).unwrap();
        let ud = utilities(&d, &robots, &cands, &travel, &big).unwrap();
        assert!(us[0][1] > us[0][0], "{us:?}");
        assert!(ud[0][0] > ud[0][1], "{ud:?}");
        // With the small-room hypothesis S-MCDM prefers the near small room too.
        let small = Hypothesis::small_rooms();
        let us = utilities(&s, &robots, &cands, &travel, &small).unwrap();
        assert!(us[0][0] > us[0][1]);
        assert_eq!(big.relevance(Some(RoomLabel::Corridor)), 0.15);
        // Unreachable pairs get no utility.
        let none = utilities(&d, &robots, &cands, &[vec![None, Some(3.0)]], &big).unwrap();
        assert_eq!(none[0][0], None);
    }
}

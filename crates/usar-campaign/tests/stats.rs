//! The statistics against reference values computed once with SciPy 1.17.1 / NumPy 2.4.6
//! (`scipy.stats.ttest_ind(a, b, equal_var=False, alternative=…)`, `ttest_rel`, `f_oneway`,
//! `shapiro`, `t.interval(0.95, n − 1, loc=mean, scale=sem)`), printed with `repr`.
//! SciPy's Shapiro–Wilk runs in single precision (swilk.f), so W and its p are compared to
//! 1e-5 there; everything else to 1e-9.

use usar_campaign::stats::{
    Tails, one_way_anova, paired_t_test, shapiro_wilk, summarize, welch_t_test,
};

const A: [f64; 8] = [0.81, 0.77, 0.93, 0.88, 0.79, 0.85, 0.91, 0.74];
const B: [f64; 8] = [0.72, 0.70, 0.84, 0.80, 0.69, 0.83, 0.77, 0.71];
const C: [f64; 8] = [0.95, 0.90, 0.97, 0.91, 0.99, 0.93, 0.96, 0.94];
const D: [f64; 13] = [
    2.1, 3.4, 1.9, 5.6, 2.2, 2.8, 3.1, 9.7, 2.5, 2.0, 4.4, 2.9, 3.3,
];
const E: [f64; 3] = [1.2, 1.9, 2.3];
const F: [f64; 5] = [12.0, 15.5, 11.2, 19.8, 14.1];
/// `np.round(np.random.default_rng(3).normal(10, 2, 30), 3)`.
const G: [f64; 30] = [
    14.082, 4.889, 10.836, 8.864, 9.095, 9.569, 5.96, 9.536, 8.27, 16.646, 10.452, 9.295, 9.437,
    8.664, 7.89, 9.218, 10.964, 9.523, 11.916, 9.6, 10.049, 13.092, 11.09, 8.99, 9.634, 11.081,
    13.87, 9.461, 9.513, 12.005,
];

fn close(found: f64, expected: f64, tol: f64) {
    assert!(
        (found - expected).abs() <= tol,
        "found {found}, expected {expected} (±{tol})"
    );
}

#[test]
fn summary_matches_scipy() {
    let s = summarize(&A).unwrap();
    assert_eq!(s.n, 8);
    close(s.mean, 0.835, 1e-12);
    close(s.sd.unwrap(), 0.06845227743263395, 1e-12);
    let (lo, hi) = s.ci95.unwrap();
    close(lo, 0.7777724639331166, 1e-9);
    close(hi, 0.8922275360668833, 1e-9);
    let one = summarize(&[3.0]).unwrap();
    assert_eq!((one.mean, one.sd, one.ci95), (3.0, None, None));
    assert!(summarize(&[]).is_none());
}

#[test]
fn welch_t_test_matches_scipy_for_every_alternative() {
    for (tails, p) in [
        (Tails::TwoSided, 0.031058286366822764),
        (Tails::Greater, 0.015529143183411382),
        (Tails::Less, 0.9844708568165886),
    ] {
        let r = welch_t_test(&A, &B, tails).unwrap();
        close(r.statistic, 2.400906712470934, 1e-9);
        close(r.df[0], 13.78715234642212, 1e-9);
        close(r.p, p, 1e-9);
    }
    let r = welch_t_test(&D, &F, Tails::TwoSided).unwrap();
    close(r.statistic, -6.729549796532201, 1e-9);
    close(r.df[0], 5.248091620727685, 1e-9);
    close(r.p, 0.0009066669697568538, 1e-9);
}

#[test]
fn paired_t_test_matches_scipy_for_every_alternative() {
    for (tails, p) in [
        (Tails::TwoSided, 0.0007348446736560649),
        (Tails::Greater, 0.00036742233682803243),
        (Tails::Less, 0.9996325776631719),
    ] {
        let r = paired_t_test(&A, &B, tails).unwrap();
        close(r.statistic, 5.700665271796163, 1e-9);
        assert_eq!(r.df, vec![7.0]);
        close(r.p, p, 1e-9);
    }
}

#[test]
fn anova_matches_scipy() {
    let r = one_way_anova(&[&A, &B, &C]).unwrap();
    close(r.statistic, 22.716547596061005, 1e-9);
    assert_eq!(r.df, vec![2.0, 21.0]);
    close(r.p, 5.600998796319876e-06, 1e-12);
    let r = one_way_anova(&[&D, &E, &F]).unwrap();
    close(r.statistic, 44.02558230769938, 1e-9);
    assert_eq!(r.df, vec![2.0, 18.0]);
    close(r.p, 1.1689974576165475e-07, 1e-12);
}

#[test]
fn shapiro_wilk_matches_scipy_from_three_to_thirty_values() {
    for (xs, w, p) in [
        (&E[..], 0.9758064516129028, 0.701724147845761),
        (&F[..], 0.9278742138669346, 0.581947515924063),
        (&A[..], 0.957995250908318, 0.7908009904986593),
        (&C[..], 0.9833024986329791, 0.9773680346897917),
        (&D[..], 0.7188656705243295, 0.0008626067821176654),
        (&G[..], 0.9291938527462297, 0.04674284150656962),
    ] {
        let r = shapiro_wilk(xs).unwrap();
        close(r.statistic, w, 1e-5);
        close(r.p, p, 1e-5);
    }
}

#[test]
fn degenerate_samples_are_errors_not_nan() {
    assert!(welch_t_test(&[1.0], &A, Tails::TwoSided).is_err());
    assert!(welch_t_test(&[1.0, 1.0], &[2.0, 2.0], Tails::TwoSided).is_err());
    assert!(paired_t_test(&A, &E, Tails::TwoSided).is_err());
    assert!(paired_t_test(&A, &A, Tails::TwoSided).is_err());
    assert!(one_way_anova(&[&A]).is_err());
    assert!(shapiro_wilk(&[1.0, 2.0]).is_err());
    assert!(shapiro_wilk(&[5.0; 6]).is_err());
}

//! The statistics the papers report: mean, standard deviation and 95 % confidence interval;
//! one-way ANOVA; paired and Welch t-tests (one- or two-tailed); the Shapiro–Wilk normality test.
//!
//! Distributions (Student t, Fisher–Snedecor F, normal) come from `statrs`; the tests themselves
//! are written out here beside their formulas. Every function is checked in `tests/stats.rs`
//! against values computed with SciPy.

use serde::Serialize;
use statrs::distribution::{ContinuousCDF, FisherSnedecor, Normal, StudentsT};

/// Mean, standard deviation (n − 1 in the denominator) and the 95 % confidence interval of the
/// mean of a sample.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    pub n: usize,
    pub mean: f64,
    /// Sample standard deviation; `None` for fewer than two values.
    pub sd: Option<f64>,
    /// mean ± t₀.₉₇₅,ₙ₋₁ · sd / √n; `None` for fewer than two values.
    pub ci95: Option<(f64, f64)>,
}

/// Describes a sample; `None` when it is empty.
pub fn summarize(xs: &[f64]) -> Option<Summary> {
    let n = xs.len();
    if n == 0 {
        return None;
    }
    let mean = mean(xs);
    let sd = variance(xs).map(f64::sqrt);
    let ci95 = sd.map(|sd| {
        let t = students_t(n as f64 - 1.0).inverse_cdf(0.975);
        let half = t * sd / (n as f64).sqrt();
        (mean - half, mean + half)
    });
    Some(Summary { n, mean, sd, ci95 })
}

/// Arithmetic mean (NaN for an empty sample).
pub fn mean(xs: &[f64]) -> f64 {
    xs.iter().sum::<f64>() / xs.len() as f64
}

/// Sample variance Σ(x − x̄)² / (n − 1), two-pass; `None` for fewer than two values.
pub fn variance(xs: &[f64]) -> Option<f64> {
    if xs.len() < 2 {
        return None;
    }
    let m = mean(xs);
    Some(xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (xs.len() - 1) as f64)
}

/// Which alternative hypothesis a t-test takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tails {
    /// The means differ.
    TwoSided,
    /// The first group's mean is greater.
    Greater,
    /// The first group's mean is less.
    Less,
}

/// The outcome of a test: its statistic, degrees of freedom and p-value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TestResult {
    pub statistic: f64,
    /// Degrees of freedom: one value for t, (between, within) for F, none for Shapiro–Wilk.
    pub df: Vec<f64>,
    pub p: f64,
}

/// Why a test could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StatsError {
    #[error("{test} needs at least {needed} values per group, found {found}")]
    TooFew {
        test: &'static str,
        needed: usize,
        found: usize,
    },
    #[error("{test} is undefined: every value is the same (zero variance)")]
    ZeroVariance { test: &'static str },
    #[error("paired t-test needs samples of equal length, found {0} and {1}")]
    Unpaired(usize, usize),
    #[error("ANOVA needs at least two groups, found {0}")]
    TooFewGroups(usize),
}

fn students_t(df: f64) -> StudentsT {
    StudentsT::new(0.0, 1.0, df).expect("positive degrees of freedom")
}

/// p-value of a t statistic with `df` degrees of freedom.
fn t_p(t: f64, df: f64, tails: Tails) -> f64 {
    let dist = students_t(df);
    match tails {
        Tails::TwoSided => 2.0 * dist.sf(t.abs()),
        Tails::Greater => dist.sf(t),
        Tails::Less => dist.cdf(t),
    }
}

/// Welch's t-test (unequal variances):
/// t = (x̄₁ − x̄₂) / √(s₁²/n₁ + s₂²/n₂),
/// ν = (s₁²/n₁ + s₂²/n₂)² / ((s₁²/n₁)²/(n₁ − 1) + (s₂²/n₂)²/(n₂ − 1)).
pub fn welch_t_test(a: &[f64], b: &[f64], tails: Tails) -> Result<TestResult, StatsError> {
    let test = "Welch t-test";
    for s in [a, b] {
        if s.len() < 2 {
            return Err(StatsError::TooFew {
                test,
                needed: 2,
                found: s.len(),
            });
        }
    }
    let (va, vb) = (
        variance(a).expect("n ≥ 2") / a.len() as f64,
        variance(b).expect("n ≥ 2") / b.len() as f64,
    );
    if va + vb == 0.0 {
        return Err(StatsError::ZeroVariance { test });
    }
    let t = (mean(a) - mean(b)) / (va + vb).sqrt();
    let df =
        (va + vb).powi(2) / (va.powi(2) / (a.len() - 1) as f64 + vb.powi(2) / (b.len() - 1) as f64);
    Ok(TestResult {
        statistic: t,
        df: vec![df],
        p: t_p(t, df, tails),
    })
}

/// Paired t-test on the differences dᵢ = aᵢ − bᵢ: t = d̄ / (s_d / √n), ν = n − 1.
pub fn paired_t_test(a: &[f64], b: &[f64], tails: Tails) -> Result<TestResult, StatsError> {
    let test = "paired t-test";
    if a.len() != b.len() {
        return Err(StatsError::Unpaired(a.len(), b.len()));
    }
    if a.len() < 2 {
        return Err(StatsError::TooFew {
            test,
            needed: 2,
            found: a.len(),
        });
    }
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let sd = variance(&d).expect("n ≥ 2").sqrt();
    if sd == 0.0 {
        return Err(StatsError::ZeroVariance { test });
    }
    let n = d.len() as f64;
    let t = mean(&d) / (sd / n.sqrt());
    Ok(TestResult {
        statistic: t,
        df: vec![n - 1.0],
        p: t_p(t, n - 1.0, tails),
    })
}

/// One-way ANOVA: F = (SS_between / (k − 1)) / (SS_within / (N − k)), p = P(F_{k−1, N−k} > F).
pub fn one_way_anova(groups: &[&[f64]]) -> Result<TestResult, StatsError> {
    let test = "ANOVA";
    let k = groups.len();
    if k < 2 {
        return Err(StatsError::TooFewGroups(k));
    }
    if let Some(g) = groups.iter().find(|g| g.is_empty()) {
        return Err(StatsError::TooFew {
            test,
            needed: 1,
            found: g.len(),
        });
    }
    let n: usize = groups.iter().map(|g| g.len()).sum();
    if n <= k {
        return Err(StatsError::TooFew {
            test,
            needed: 2,
            found: 1,
        });
    }
    let grand = groups.iter().flat_map(|g| g.iter()).sum::<f64>() / n as f64;
    let ss_between: f64 = groups
        .iter()
        .map(|g| g.len() as f64 * (mean(g) - grand).powi(2))
        .sum();
    let ss_within: f64 = groups
        .iter()
        .map(|g| {
            let m = mean(g);
            g.iter().map(|x| (x - m).powi(2)).sum::<f64>()
        })
        .sum();
    if ss_within == 0.0 {
        return Err(StatsError::ZeroVariance { test });
    }
    let (df1, df2) = ((k - 1) as f64, (n - k) as f64);
    let f = (ss_between / df1) / (ss_within / df2);
    let dist = FisherSnedecor::new(df1, df2).expect("positive degrees of freedom");
    Ok(TestResult {
        statistic: f,
        df: vec![df1, df2],
        p: dist.sf(f),
    })
}

/// Evaluates c₀ + c₁x + c₂x² + … .
fn poly(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * x + ci)
}

/// The Shapiro–Wilk W test of normality for 3 ≤ n ≤ 5000, with Royston's (1992, 1995, AS R94)
/// approximations of the coefficients and of the p-value:
///
/// W = (Σ aᵢ x₍ᵢ₎)² / Σ (xᵢ − x̄)², where mᵢ = Φ⁻¹((i − 3/8)/(n + 1/4)), u = 1/√n,
/// aₙ = mₙ/√(Σm²) + 0.221157u − 0.147981u² − 2.071190u³ + 4.434685u⁴ − 2.706056u⁵,
/// aₙ₋₁ likewise with (0.042981, −0.293762, −1.752461, 5.682633, −3.582633) for n > 5, the
/// inner aᵢ = mᵢ/√φ with φ normalising Σa² to 1, and a₁ = −aₙ, a₂ = −aₙ₋₁. The p-value is the
/// upper tail of a normal approximation of ln(1 − W) (n ≥ 12) or of −ln(γ − ln(1 − W)) with
/// γ = −2.273 + 0.459n (4 ≤ n ≤ 11); for n = 3 it is exact: p = (6/π)(asin √W − asin √¾).
pub fn shapiro_wilk(xs: &[f64]) -> Result<TestResult, StatsError> {
    let test = "Shapiro-Wilk test";
    let n = xs.len();
    if n < 3 {
        return Err(StatsError::TooFew {
            test,
            needed: 3,
            found: n,
        });
    }
    let mut x = xs.to_vec();
    x.sort_by(f64::total_cmp);
    let range = x[n - 1] - x[0];
    if range == 0.0 {
        return Err(StatsError::ZeroVariance { test });
    }
    let nf = n as f64;
    let normal = Normal::new(0.0, 1.0).expect("standard normal");
    let mut a = vec![0.0; n];
    if n == 3 {
        a[0] = -std::f64::consts::FRAC_1_SQRT_2;
        a[2] = std::f64::consts::FRAC_1_SQRT_2;
    } else {
        let m: Vec<f64> = (1..=n)
            .map(|i| normal.inverse_cdf((i as f64 - 0.375) / (nf + 0.25)))
            .collect();
        let ssq: f64 = m.iter().map(|v| v * v).sum();
        let u = 1.0 / nf.sqrt();
        let an = m[n - 1] / ssq.sqrt()
            + poly(
                &[0.0, 0.221157, -0.147981, -2.071190, 4.434685, -2.706056],
                u,
            );
        if n > 5 {
            let an1 = m[n - 2] / ssq.sqrt()
                + poly(
                    &[0.0, 0.042981, -0.293762, -1.752461, 5.682633, -3.582633],
                    u,
                );
            let phi = (ssq - 2.0 * m[n - 1].powi(2) - 2.0 * m[n - 2].powi(2))
                / (1.0 - 2.0 * an.powi(2) - 2.0 * an1.powi(2));
            for i in 2..n - 2 {
                a[i] = m[i] / phi.sqrt();
            }
            a[n - 2] = an1;
            a[1] = -an1;
        } else {
            let phi = (ssq - 2.0 * m[n - 1].powi(2)) / (1.0 - 2.0 * an.powi(2));
            for i in 1..n - 1 {
                a[i] = m[i] / phi.sqrt();
            }
        }
        a[n - 1] = an;
        a[0] = -an;
    }
    let xm = mean(&x);
    let ss: f64 = x.iter().map(|v| (v - xm).powi(2)).sum();
    let num: f64 = a.iter().zip(&x).map(|(ai, xi)| ai * xi).sum();
    let w = (num * num / ss).min(1.0);
    let p = if n == 3 {
        let p = 6.0 / std::f64::consts::PI * (w.sqrt().asin() - 0.75f64.sqrt().asin());
        p.max(0.0)
    } else {
        let y = (1.0 - w).ln();
        let z = if n <= 11 {
            let gamma = poly(&[-2.273, 0.459], nf);
            if y >= gamma {
                // W so small that the approximation's log is undefined: p is essentially 0.
                f64::INFINITY
            } else {
                let y = -(gamma - y).ln();
                let m = poly(&[0.5440, -0.39978, 0.025054, -6.714e-4], nf);
                let s = poly(&[1.3822, -0.77857, 0.062767, -0.0020322], nf).exp();
                (y - m) / s
            }
        } else {
            let ln_n = nf.ln();
            let m = poly(&[-1.5861, -0.31082, -0.083751, 0.0038915], ln_n);
            let s = poly(&[-0.4803, -0.082676, 0.0030302], ln_n).exp();
            (y - m) / s
        };
        normal.sf(z)
    };
    Ok(TestResult {
        statistic: w,
        df: Vec::new(),
        p,
    })
}

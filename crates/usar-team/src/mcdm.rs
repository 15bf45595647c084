//! Multi-criteria decision making with the Choquet integral (paper 002 §3.2, eq. 1; Basilico and
//! Amigoni 2011).
//!
//! Utilities uⱼ(p, r) of candidate p for robot r under criterion j are first normalised to
//! [0, 1] by a linear relative normalisation over the pairs being compared. With the criteria
//! sorted so that u₍₁₎ ≤ … ≤ u₍ₙ₎ and u₍₀₎ = 0,
//!
//! ```text
//! u(p, r) = Σⱼ (u₍ⱼ₎(p, r) − u₍ⱼ₋₁₎(p, r)) · μ(A₍ⱼ₎),   A₍ⱼ₎ = { i ∈ N | u₍ⱼ₎ ≤ uᵢ ≤ u₍ₙ₎ }   (1)
//! ```
//!
//! where μ is a normalised fuzzy measure on the criteria N: μ(∅) = 0, μ(N) = 1, monotone. The
//! paper gives μ for some subsets (Table 1); the others are the sum of their singletons' weights,
//! raised where needed to stay monotone and capped at 1. Measures are configuration, not code.

use serde::{Deserialize, Serialize};

/// A fuzzy measure as written in a configuration: the criteria and the weights of some subsets.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeasureSpec {
    /// The criteria N, in a fixed order (at most 16).
    pub criteria: Vec<String>,
    /// Subset (criteria names) → weight. Every singleton must be given.
    pub weights: Vec<(Vec<String>, f64)>,
}

/// A complete fuzzy measure: μ of every subset of N, indexed by bitmask.
#[derive(Clone, Debug, PartialEq)]
pub struct FuzzyMeasure {
    pub criteria: Vec<String>,
    mu: Vec<f64>,
}

/// Why a fuzzy measure was refused; each names the subset and the value.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeasureError {
    #[error("a fuzzy measure needs 1 to 16 criteria, found {0}")]
    Criteria(usize),
    #[error("weight of {{{subset}}}: unknown criterion `{criterion}`, expected one of {expected}")]
    UnknownCriterion {
        subset: String,
        criterion: String,
        expected: String,
    },
    #[error("weight of {{{subset}}}: found {found}, expected a number in [0, 1]")]
    Weight { subset: String, found: f64 },
    #[error("the weight of criterion `{0}` alone is missing")]
    MissingSingleton(String),
    #[error(
        "μ({subset}) = {found} is below μ of one of its subsets ({below}); a fuzzy measure is monotone"
    )]
    NotMonotone {
        subset: String,
        found: f64,
        below: f64,
    },
    #[error("μ(N) must be 1, found {0}")]
    Whole(f64),
}

impl FuzzyMeasure {
    /// Completes `spec` (unlisted subsets: sum of singletons, made monotone, capped at 1;
    /// μ(N) = 1) and checks it. Errors name the subset and the value.
    pub fn new(spec: &MeasureSpec) -> Result<Self, MeasureError> {
        let n = spec.criteria.len();
        if n == 0 || n > 16 {
            return Err(MeasureError::Criteria(n));
        }
        let full = (1usize << n) - 1;
        let mut given: Vec<Option<f64>> = vec![None; full + 1];
        for (subset, w) in &spec.weights {
            let mut mask = 0usize;
            for c in subset {
                let i = spec.criteria.iter().position(|x| x == c).ok_or_else(|| {
                    MeasureError::UnknownCriterion {
                        subset: subset.join(", "),
                        criterion: c.clone(),
                        expected: spec.criteria.join(", "),
                    }
                })?;
                mask |= 1 << i;
            }
            if !(w.is_finite() && (0.0..=1.0).contains(w)) {
                return Err(MeasureError::Weight {
                    subset: subset.join(", "),
                    found: *w,
                });
            }
            given[mask] = Some(*w);
        }
        for (i, c) in spec.criteria.iter().enumerate() {
            if given[1 << i].is_none() {
                return Err(MeasureError::MissingSingleton(c.clone()));
            }
        }
        let name = |mask: usize| {
            let names: Vec<&str> = (0..n)
                .filter(|i| mask & (1 << i) != 0)
                .map(|i| spec.criteria[i].as_str())
                .collect();
            format!("{{{}}}", names.join(", "))
        };
        let mut mu = vec![0.0; full + 1];
        // Increasing number of members: every proper subset is done before its supersets.
        let mut order: Vec<usize> = (1..=full).collect();
        order.sort_by_key(|m| (m.count_ones(), *m));
        for mask in order {
            let below = (0..n)
                .filter(|i| mask & (1 << i) != 0 && mask != 1 << i)
                .map(|i| mu[mask & !(1 << i)])
                .fold(0.0, f64::max);
            mu[mask] = if mask == full {
                1.0
            } else if let Some(w) = given[mask] {
                if w < below {
                    return Err(MeasureError::NotMonotone {
                        subset: name(mask),
                        found: w,
                        below,
                    });
                }
                w
            } else {
                let sum: f64 = (0..n)
                    .filter(|i| mask & (1 << i) != 0)
                    .map(|i| given[1 << i].expect("singletons given"))
                    .sum();
                sum.max(below).min(1.0)
            };
        }
        if let Some(w) = given[full]
            && (w - 1.0).abs() > 1e-12
        {
            return Err(MeasureError::Whole(w));
        }
        Ok(Self {
            criteria: spec.criteria.clone(),
            mu,
        })
    }

    /// μ of the subset given by `mask` (bit i = criterion i).
    pub fn mu(&self, mask: usize) -> f64 {
        self.mu[mask]
    }

    /// The Choquet integral (eq. 1) of normalised utilities `u` (one per criterion, in [0, 1]).
    pub fn choquet(&self, u: &[f64]) -> f64 {
        debug_assert_eq!(u.len(), self.criteria.len());
        let mut order: Vec<usize> = (0..u.len()).collect();
        order.sort_by(|&a, &b| u[a].total_cmp(&u[b]).then(a.cmp(&b)));
        let mut remaining = (1usize << u.len()) - 1; // A₍₁₎ = N
        let mut previous = 0.0;
        let mut total = 0.0;
        for &j in &order {
            total += (u[j] - previous) * self.mu[remaining];
            previous = u[j];
            remaining &= !(1 << j);
        }
        total
    }
}

/// Whether larger raw values of a criterion are better (benefit) or worse (cost).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Sense {
    Benefit,
    Cost,
}

/// Linear relative normalisation of one criterion over the pairs compared: (x − min)/(max − min)
/// for a benefit, (max − x)/(max − min) for a cost; every value is 1 when all are equal (the
/// criterion does not discriminate). Missing values (`None`, e.g. unreachable) stay `None`.
pub fn normalize(values: &[Option<f64>], sense: Sense) -> Vec<Option<f64>> {
    let present = values.iter().flatten();
    let (lo, hi) = present.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
        (lo.min(v), hi.max(v))
    });
    values
        .iter()
        .map(|v| {
            v.map(|x| {
                if hi <= lo {
                    1.0
                } else {
                    match sense {
                        Sense::Benefit => (x - lo) / (hi - lo),
                        Sense::Cost => (hi - x) / (hi - lo),
                    }
                }
            })
        })
        .collect()
}

/// Table 1 (left) of paper 002: S-MCDM over N = {A, d, b, S, ND}.
pub fn s_mcdm_table_1() -> MeasureSpec {
    let w = |names: &[&str], v: f64| (names.iter().map(|s| s.to_string()).collect(), v);
    MeasureSpec {
        criteria: ["A", "d", "b", "S", "ND"].map(String::from).to_vec(),
        weights: vec![
            w(&["A"], 0.09),
            w(&["d"], 0.09),
            w(&["b"], 0.02),
            w(&["S"], 0.5),
            w(&["ND"], 0.3),
            w(&["A", "d"], 0.3),
            w(&["d", "b"], 0.09),
            w(&["d", "S"], 0.8),
            w(&["b", "S"], 0.6),
            w(&["A", "d", "b"], 0.3),
            w(&["A", "d", "S"], 0.8),
            w(&["A", "b", "S"], 0.65),
            w(&["A", "b"], 0.15),
            w(&["d", "b", "S"], 0.8),
            w(&["A", "S"], 0.65),
            w(&["A", "d", "b", "S"], 0.8),
        ],
    }
}

/// Table 1 (right) of paper 002: D-MCDM over N = {A, d, b}.
pub fn d_mcdm_table_1() -> MeasureSpec {
    let w = |names: &[&str], v: f64| (names.iter().map(|s| s.to_string()).collect(), v);
    MeasureSpec {
        criteria: ["A", "d", "b"].map(String::from).to_vec(),
        weights: vec![
            w(&["A"], 0.4),
            w(&["d"], 0.4),
            w(&["b"], 0.2),
            w(&["A", "d"], 0.95),
            w(&["A", "b"], 0.7),
            w(&["d", "b"], 0.4),
        ],
    }
}

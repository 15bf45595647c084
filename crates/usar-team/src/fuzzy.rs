//! Mamdani fuzzy inference (Mamdani and Assilian 1975), as paper 002 §3.3 uses for the ideal
//! team size: inputs fuzzified by membership functions, each rule fires with the minimum of its
//! antecedents' memberships (AND), clips its consequent set (implication = min), the clipped
//! sets are joined by maximum, and the result is the centroid of that aggregate.

use serde::{Deserialize, Serialize};

/// A membership function on the real line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum Membership {
    /// 0 at `a`, 1 at `b`, 0 at `c`.
    Triangle { a: f64, b: f64, c: f64 },
    /// 0 at `a`, 1 from `b` to `c`, 0 at `d`; `a = b` (or `c = d`) makes a shoulder, and
    /// infinite ends are allowed.
    Trapezoid { a: f64, b: f64, c: f64, d: f64 },
}

impl Membership {
    pub fn degree(&self, x: f64) -> f64 {
        let rise = |a: f64, b: f64| {
            if x >= b {
                1.0
            } else if x <= a {
                0.0
            } else {
                (x - a) / (b - a)
            }
        };
        let fall = |c: f64, d: f64| {
            if x <= c {
                1.0
            } else if x >= d {
                0.0
            } else {
                (d - x) / (d - c)
            }
        };
        match *self {
            Membership::Triangle { a, b, c } => rise(a, b).min(fall(b, c)),
            Membership::Trapezoid { a, b, c, d } => rise(a, b).min(fall(c, d)),
        }
    }
}

/// A linguistic variable: named terms with their membership functions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Variable {
    pub name: String,
    pub terms: Vec<(String, Membership)>,
}

impl Variable {
    pub fn term(&self, name: &str) -> Option<usize> {
        self.terms.iter().position(|(n, _)| n == name)
    }
}

/// "if input₀ is term and input₁ is term … then output is term" (term indices).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rule {
    pub antecedents: Vec<usize>,
    pub consequent: usize,
}

/// A Mamdani system: inputs, one output on [lo, hi], rules.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Mamdani {
    pub inputs: Vec<Variable>,
    pub output: Variable,
    /// The output universe sampled for the centroid.
    pub output_range: (f64, f64),
    pub rules: Vec<Rule>,
}

/// Samples of the output universe for the centroid.
const CENTROID_SAMPLES: usize = 401;

impl Mamdani {
    /// Firing strength of every rule for crisp `inputs`.
    pub fn strengths(&self, inputs: &[f64]) -> Vec<f64> {
        let degrees: Vec<Vec<f64>> = self
            .inputs
            .iter()
            .zip(inputs)
            .map(|(v, &x)| v.terms.iter().map(|(_, m)| m.degree(x)).collect())
            .collect();
        self.rules
            .iter()
            .map(|r| {
                r.antecedents
                    .iter()
                    .enumerate()
                    .map(|(i, &t)| degrees[i][t])
                    .fold(1.0, f64::min)
            })
            .collect()
    }

    /// The centroid of the aggregated output, or `None` when no rule fires.
    ///
    /// The aggregate max over rules of min(strength, consequent(y)) equals the max over output
    /// terms of min(the strongest rule concluding that term, term(y)), which is how it is
    /// computed: one clip level per output term instead of one per rule.
    pub fn infer(&self, inputs: &[f64]) -> Option<f64> {
        let strengths = self.strengths(inputs);
        let mut clip = vec![0.0f64; self.output.terms.len()];
        for (r, &s) in self.rules.iter().zip(&strengths) {
            clip[r.consequent] = clip[r.consequent].max(s);
        }
        let (lo, hi) = self.output_range;
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..CENTROID_SAMPLES {
            let y = lo + (hi - lo) * k as f64 / (CENTROID_SAMPLES - 1) as f64;
            let mu = self
                .output
                .terms
                .iter()
                .zip(&clip)
                .filter(|&(_, &c)| c > 0.0)
                .map(|((_, m), &c)| c.min(m.degree(y)))
                .fold(0.0, f64::max);
            num += mu * y;
            den += mu;
        }
        (den > 0.0).then(|| num / den)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn membership_shapes() {
        let t = Membership::Triangle {
            a: 0.0,
            b: 1.0,
            c: 3.0,
        };
        assert_eq!(
            [t.degree(-1.0), t.degree(0.5), t.degree(1.0), t.degree(2.0)],
            [0.0, 0.5, 1.0, 0.5]
        );
        let shoulder = Membership::Trapezoid {
            a: f64::NEG_INFINITY,
            b: 0.0,
            c: 1.0,
            d: 2.0,
        };
        assert_eq!(
            [
                shoulder.degree(-5.0),
                shoulder.degree(1.5),
                shoulder.degree(2.0)
            ],
            [1.0, 0.5, 0.0]
        );
    }

    #[test]
    fn a_single_firing_rule_gives_its_consequents_centroid() {
        let low = Membership::Triangle {
            a: 0.0,
            b: 1.0,
            c: 2.0,
        };
        let high = Membership::Triangle {
            a: 2.0,
            b: 3.0,
            c: 4.0,
        };
        let m = Mamdani {
            inputs: vec![Variable {
                name: "x".into(),
                terms: vec![("lo".into(), low), ("hi".into(), high)],
            }],
            output: Variable {
                name: "y".into(),
                terms: vec![("lo".into(), low), ("hi".into(), high)],
            },
            output_range: (0.0, 4.0),
            rules: vec![
                Rule {
                    antecedents: vec![0],
                    consequent: 0,
                },
                Rule {
                    antecedents: vec![1],
                    consequent: 1,
                },
            ],
        };
        assert!((m.infer(&[1.0]).unwrap() - 1.0).abs() < 1e-9);
        assert!((m.infer(&[3.0]).unwrap() - 3.0).abs() < 1e-9);
        assert!(m.infer(&[10.0]).is_none());
    }
}

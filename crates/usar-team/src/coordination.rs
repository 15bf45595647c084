//! Allocating candidate locations to robots from their bids u(p, r) (paper 002 §3.3).
//!
//! - **SR** (single robot per task, Zlot et al. 2002): greedy, one robot per candidate — MRv1
//!   with i(p) = 1 for every p.
//! - **MRv1** (Algorithm 3): repeatedly allocate the best pair (p*, r*); eliminate r*, and
//!   eliminate p* once it has i(p*) robots.
//! - **MRv2**: like MRv1, but p* is never eliminated; after each allocation its bids are
//!   multiplied by a discount of the number k of robots it already has (Fig. 3): linear from 1
//!   (k = 0) down to [`DiscountParams::at_ideal`] at k = i(p*), then exponential,
//!   `at_ideal · exp(−rate · (k − i(p*)))`. Fig. 3 is missing from the text; the defaults (0.5,
//!   rate 1.5) keep one more robot than i(p) possible when nothing else is left while making it
//!   lose to any candidate worth a third as much.
//!
//! Ties go to the lower robot index, then the lower candidate index.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Coordination {
    Sr,
    Mrv1,
    Mrv2,
}

impl Coordination {
    pub const ALL: [Coordination; 3] = [Coordination::Sr, Coordination::Mrv1, Coordination::Mrv2];

    pub fn as_str(self) -> &'static str {
        match self {
            Coordination::Sr => "sr",
            Coordination::Mrv1 => "mrv1",
            Coordination::Mrv2 => "mrv2",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.as_str() == name)
    }
}

/// MRv2's discount curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DiscountParams {
    /// Discount when a candidate has exactly i(p) robots.
    pub at_ideal: f64,
    /// Exponential rate beyond i(p), per extra robot.
    pub rate: f64,
}

impl Default for DiscountParams {
    fn default() -> Self {
        Self {
            at_ideal: 0.5,
            rate: 1.5,
        }
    }
}

impl DiscountParams {
    /// The discount for a candidate with `k` robots allocated and ideal team size `ideal`.
    pub fn factor(&self, k: usize, ideal: usize) -> f64 {
        let ideal = ideal.max(1) as f64;
        let k = k as f64;
        if k <= ideal {
            1.0 - (1.0 - self.at_ideal) * k / ideal
        } else {
            self.at_ideal * (-self.rate * (k - ideal)).exp()
        }
    }
}

/// Allocates candidates to robots. `bids[r][p]` is u(p, r) (`None`: r cannot reach p),
/// `ideal[p]` is i(p). Returns each robot's candidate, `None` when nothing is left for it.
pub fn allocate(
    bids: &[Vec<Option<f64>>],
    ideal: &[usize],
    method: Coordination,
    discount: DiscountParams,
) -> Vec<Option<usize>> {
    allocate_among(bids, ideal, &vec![0; ideal.len()], method, discount)
}

/// Like [`allocate`], when `already[p]` robots that are not bidding (they keep their targets)
/// are on candidate p: they count towards i(p) (SR, MRv1) and MRv2's discount.
pub fn allocate_among(
    bids: &[Vec<Option<f64>>],
    ideal: &[usize],
    already: &[usize],
    method: Coordination,
    discount: DiscountParams,
) -> Vec<Option<usize>> {
    let robots = bids.len();
    let cands = ideal.len();
    let mut u: Vec<Vec<Option<f64>>> = bids.to_vec();
    let mut out = vec![None; robots];
    let mut robot_free = vec![true; robots];
    let mut count = already.to_vec();
    let limit = |p: usize| match method {
        Coordination::Sr => Some(1),
        Coordination::Mrv1 => Some(ideal[p].max(1)),
        Coordination::Mrv2 => None,
    };
    let mut cand_open: Vec<bool> = (0..cands)
        .map(|p| limit(p).is_none_or(|l| count[p] < l))
        .collect();
    if method == Coordination::Mrv2 {
        for (p, &k) in count.iter().enumerate() {
            let f = discount.factor(k, ideal[p]);
            for row in u.iter_mut() {
                if let Some(v) = row[p].as_mut() {
                    *v *= f;
                }
            }
        }
    }
    loop {
        let mut best: Option<(f64, usize, usize)> = None;
        for (r, row) in u.iter().enumerate().filter(|(r, _)| robot_free[*r]) {
            for (p, v) in row.iter().enumerate() {
                if let Some(v) = *v
                    && cand_open[p]
                    && best.is_none_or(|(b, _, _)| v > b)
                {
                    best = Some((v, r, p));
                }
            }
        }
        let Some((_, r, p)) = best else {
            return out;
        };
        out[r] = Some(p);
        robot_free[r] = false;
        count[p] += 1;
        match limit(p) {
            Some(l) if count[p] >= l => cand_open[p] = false,
            Some(_) => {}
            None => {
                let before = discount.factor(count[p] - 1, ideal[p]);
                let now = discount.factor(count[p], ideal[p]);
                for row in u.iter_mut() {
                    if let Some(v) = row[p].as_mut() {
                        // Bids were discounted by `before`; apply the new factor instead.
                        *v = if before > 0.0 { *v / before * now } else { 0.0 };
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sr_gives_one_robot_per_candidate_and_mrv1_up_to_i_p() {
        // Candidate 0 is everyone's favourite, i(0) = 2.
        let bids = vec![
            vec![Some(0.9), Some(0.5)],
            vec![Some(0.8), Some(0.4)],
            vec![Some(0.7), Some(0.3)],
        ];
        let d = DiscountParams::default();
        assert_eq!(
            allocate(&bids, &[2, 1], Coordination::Sr, d),
            vec![Some(0), Some(1), None]
        );
        assert_eq!(
            allocate(&bids, &[2, 1], Coordination::Mrv1, d),
            vec![Some(0), Some(0), Some(1)]
        );
        // MRv2: after two robots, candidate 0 is worth 0.7 · 0.5 = 0.35 to robot 2, candidate 1
        // 0.3 — a third robot still goes to 0.
        assert_eq!(
            allocate(&bids, &[2, 1], Coordination::Mrv2, d),
            vec![Some(0), Some(0), Some(0)]
        );
        let bids = vec![
            vec![Some(0.9), Some(0.5)],
            vec![Some(0.8), Some(0.4)],
            vec![Some(0.7), Some(0.6)],
        ];
        // Robot 0 takes 0; robot 2 then prefers 1 (0.6 over 0.35); candidate 1, now discounted
        // to 0.2 for robot 1, loses to candidate 0 (0.4).
        assert_eq!(
            allocate(&bids, &[1, 1], Coordination::Mrv2, d),
            vec![Some(0), Some(0), Some(1)]
        );
    }

    #[test]
    fn discount_is_linear_to_i_p_then_exponential() {
        let d = DiscountParams::default();
        assert_eq!(d.factor(0, 3), 1.0);
        assert!((d.factor(3, 3) - 0.5).abs() < 1e-12);
        assert!((d.factor(1, 3) - (1.0 - 0.5 / 3.0)).abs() < 1e-12);
        assert!((d.factor(4, 3) - 0.5 * (-1.5f64).exp()).abs() < 1e-12);
        for k in 0..8 {
            assert!(d.factor(k + 1, 3) < d.factor(k, 3));
        }
    }

    #[test]
    fn unreachable_candidates_are_never_given() {
        let bids = vec![vec![None, None], vec![Some(0.1), None]];
        assert_eq!(
            allocate(
                &bids,
                &[1, 1],
                Coordination::Mrv1,
                DiscountParams::default()
            ),
            vec![None, Some(0)]
        );
    }
}

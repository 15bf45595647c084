//! The team mission's tuning: the thresholds and periods of robot driving, recovery and
//! allocation that the papers do not give. Each was chosen on development seeds and is kept in
//! the configuration, so a campaign can vary it (`TeamConfig::tuning`; a field left out of a
//! file keeps its default).

use serde::{Deserialize, Serialize};

/// See the module documentation; the defaults are the values every figure so far was made with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Tuning {
    /// A robot is stuck when, while it had a target, it moved less than [`Tuning::stuck_distance_m`] and
    /// turned less than [`Tuning::stuck_turn_rad`] in [`Tuning::stuck_window_s`]. Turning counts as progress: a
    /// robot at paper 002's pace (0.36 rad/s) needs almost 9 s to turn round in place towards a
    /// target behind it.
    pub stuck_distance_m: f64,
    pub stuck_turn_rad: f64,
    /// Turning counts as progress for one full turn at most while the robot stays put: one that
    /// spins on the spot is stuck too.
    pub max_turn_in_place_rad: f64,
    pub stuck_window_s: f64,
    /// A candidate a robot got stuck on is not given to it again for this long.
    pub blacklist_s: f64,
    /// A candidate a robot reached is not given to it again for this long.
    pub reached_blacklist_s: f64,
    /// Commitment: at a periodic reassignment, a candidate within this distance (cells) of the
    /// robot's current target costs it [`Tuning::commitment_factor`] × its path cost, so that two frontiers
    /// at similar distances do not make the robot turn back and forth every few seconds.
    pub commitment_cells: i32,
    pub commitment_factor: f64,
    /// Margin added to half the robot's width for squeezing through narrow places, metres.
    pub tight_margin_m: f64,
    /// The mission counts as explored once no robot has had a reachable candidate for this long
    /// (a doorway closed for a moment by a noisy return must not end it).
    pub explored_after_s: f64,
    /// With auctions, a candidate some robot reached is offered to nobody within this many map cells
    /// for this long: a frontier that did not resolve on arrival lies where the laser cannot see
    /// (behind furniture), and would draw robot after robot.
    pub visited_cells: i32,
    pub visited_blacklist_s: f64,
    /// With auctions, once a robot has reached its target and scanned there, the frontier cells still
    /// left within this distance of it are taken out of the candidates for good
    /// ([`usar_map::FrontierTracker::retire_near`]): a 20 m laser that stood this near them could
    /// not see past them. Without it, frontier cells along walls that the 0.2 m map cells straddle
    /// (free on the near half, the wall's far side never seen) form long clusters that draw robot
    /// after robot to the same corridor for the whole mission; the paper's mapping is error-free
    /// (§3.1) and has no such frontiers.
    pub unobservable_radius_m: f64,
    /// A robot keeping its target occupies the candidate within this many map cells of it (with one
    /// candidate per room, that candidate's room), and a robot allocated a candidate this near its
    /// target (or its target's room) keeps its path.
    pub kept_target_cells: i32,
    /// A target that needed this many recoveries is given up (blacklisted) like a stuck one.
    pub max_recoveries: u32,
    /// When no candidate is reachable from where a robot stands (the map, refined since it drove
    /// in, no longer connects its pocket), it retraces this much of its own trajectory and plans
    /// again: it was there, so the way back is passable.
    pub retrace_m: f64,
    /// Right of way: a robot stops (it may still turn) while a robot with a lower id is closer than
    /// this, centre to centre, within ±60° of its heading.
    pub yield_distance_m: f64,
    pub yield_half_angle_rad: f64,
}

impl Default for Tuning {
    fn default() -> Self {
        Self {
            stuck_distance_m: 0.2,
            stuck_turn_rad: 0.35,
            max_turn_in_place_rad: std::f64::consts::TAU,
            stuck_window_s: 4.0,
            blacklist_s: 30.0,
            reached_blacklist_s: 20.0,
            commitment_cells: 10,
            commitment_factor: 0.5,
            tight_margin_m: 0.05,
            explored_after_s: 10.0,
            visited_cells: 3,
            visited_blacklist_s: 60.0,
            unobservable_radius_m: 2.0,
            kept_target_cells: 5,
            max_recoveries: 3,
            retrace_m: 3.0,
            yield_distance_m: 1.2,
            yield_half_angle_rad: std::f64::consts::FRAC_PI_3,
        }
    }
}

impl Tuning {
    /// Every field with its default value, by name: the campaign factors of the team runners.
    pub fn fields() -> Vec<(String, serde_json::Value)> {
        let value = serde_json::to_value(Self::default()).expect("the tuning serialises");
        value
            .as_object()
            .map(|m| m.iter().map(|(k, v)| (k.clone(), v.clone())).collect())
            .unwrap_or_default()
    }

    /// This tuning with each field that `value_of` names set to its value (the others kept);
    /// an error names a field whose type cannot hold the value (a count given −1 or 2.5).
    pub fn with(self, value_of: impl Fn(&str) -> Option<f64>) -> Result<Self, String> {
        let mut value = serde_json::to_value(self).expect("the tuning serialises");
        if let Some(map) = value.as_object_mut() {
            for (name, field) in map.iter_mut() {
                if let Some(x) = value_of(name) {
                    *field = if field.is_f64() {
                        serde_json::json!(x)
                    } else if x.fract() == 0.0 && x.abs() < 1e15 {
                        serde_json::json!(x as i64)
                    } else {
                        return Err(format!("{name}: found {x}, expected a whole number"));
                    };
                }
            }
        }
        serde_json::from_value(value).map_err(|e| format!("tuning: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_round_trip_and_a_value_reaches_its_field() {
        let fields = Tuning::fields();
        assert_eq!(fields.len(), 18);
        assert_eq!(Tuning::default().with(|_| None), Ok(Tuning::default()));
        let t = Tuning::default()
            .with(|name| match name {
                "blacklist_s" => Some(45.0),
                "kept_target_cells" => Some(7.0),
                _ => None,
            })
            .unwrap();
        assert_eq!((t.blacklist_s, t.kept_target_cells), (45.0, 7));
        assert!(
            Tuning::default()
                .with(|n| (n == "max_recoveries").then_some(-1.0))
                .is_err()
        );
        assert!(
            Tuning::default()
                .with(|n| (n == "visited_cells").then_some(2.5))
                .is_err()
        );
    }
}

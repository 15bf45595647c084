//! Free-space nodes (paper 004 §III-A-1, Fig. 3): where L_l > C₁ or L_r > C₁ in the grey
//! strip the robot is in an open area; one node marks its entrance, another its exit.

use usar_map::localization::SideClearance;
use usar_world::Point2;

/// Whether the strip around the robot shows free space on either side (L_l > C₁ or
/// L_r > C₁).
pub fn is_free_space(strip: SideClearance, clearance_m: f64) -> bool {
    strip.left_m > clearance_m || strip.right_m > clearance_m
}

/// Sides closer than this count as a tie, broken towards the right wall (the paper's robot
/// "ran along the right wall").
const SIDE_TIE_M: f64 = 0.5;

/// §IV-B: for L_l > L_r follow the right wall, for L_l < L_r the left one.
pub fn follow_right_wall(strip: SideClearance) -> bool {
    strip.left_m >= strip.right_m - SIDE_TIE_M
}

/// Watches for the exit: both sides beside the robot closer than C₁ for a distance driven.
#[derive(Clone, Debug, Default)]
pub struct ExitTracker {
    run_m: f64,
    start: Option<Point2>,
}

impl ExitTracker {
    /// Adds a step of `driven_m` at `position` with `beside` the clearance beside the robot;
    /// returns where the exit began once both sides have stayed closed for `confirm_m`.
    pub fn update(
        &mut self,
        beside: SideClearance,
        clearance_m: f64,
        driven_m: f64,
        position: Point2,
        confirm_m: f64,
    ) -> Option<Point2> {
        if beside.left_m < clearance_m && beside.right_m < clearance_m {
            let start = *self.start.get_or_insert(position);
            self.run_m += driven_m;
            (self.run_m >= confirm_m).then_some(start)
        } else {
            self.run_m = 0.0;
            self.start = None;
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wide_side_is_free_space_and_the_nearer_wall_is_followed() {
        let hall = SideClearance {
            left_m: 6.0,
            right_m: 1.0,
        };
        assert!(is_free_space(hall, 4.0));
        assert!(follow_right_wall(hall));
        let passage = SideClearance {
            left_m: 0.8,
            right_m: 0.8,
        };
        assert!(!is_free_space(passage, 4.0));
        assert!(!follow_right_wall(SideClearance {
            left_m: 1.0,
            right_m: 6.0
        }));
    }

    #[test]
    fn the_exit_needs_both_sides_closed_for_the_confirmation_distance() {
        let mut t = ExitTracker::default();
        let closed = SideClearance {
            left_m: 0.8,
            right_m: 0.8,
        };
        let open = SideClearance {
            left_m: 6.0,
            right_m: 0.8,
        };
        assert_eq!(t.update(closed, 4.0, 0.5, Point2::new(0.0, 0.0), 1.0), None);
        assert_eq!(t.update(open, 4.0, 0.5, Point2::new(0.5, 0.0), 1.0), None);
        assert_eq!(t.update(closed, 4.0, 0.5, Point2::new(1.0, 0.0), 1.0), None);
        assert_eq!(
            t.update(closed, 4.0, 0.5, Point2::new(1.5, 0.0), 1.0),
            Some(Point2::new(1.0, 0.0))
        );
    }
}

//! Autonomous locomotion (paper 004 §IV): target approach (eqs. 1–3), wall following, the
//! dead-end turn, branch selection and the central run (eq. 4), and the choice between them
//! (Fig. 8). Each behaviour turns what the robot perceives, in its own frame (x forward,
//! y left), into a velocity command. One addition for cluttered real floors: the clear-lane
//! heading ([`free_heading`]) that steers the target approach round furniture while the robot
//! drives back along a searched link.

use serde::{Deserialize, Serialize};
use usar_map::localization::{ScanView, SideClearance};
use usar_sim::Velocity;
use usar_world::Point2;

/// The run modes of Fig. 8, plus driving back along known links.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunMode {
    /// Eq. 4: along the middle of a passage.
    CentralRun,
    /// In free space, along the nearer wall.
    WallFollowing,
    /// L_l + L_r < C₂: on-the-spot turn.
    DeadEndRun,
    /// Towards a circumcentre, then onto an un-searched link.
    BranchSelection,
    /// Across a slope or stairs: central run with the view beside the robot only.
    ObstacleCrossing,
    /// Along searched links to a node that still has un-searched ones.
    Returning,
}

impl RunMode {
    pub fn as_str(self) -> &'static str {
        match self {
            RunMode::CentralRun => "central_run",
            RunMode::WallFollowing => "wall_following",
            RunMode::DeadEndRun => "dead_end_run",
            RunMode::BranchSelection => "branch_selection",
            RunMode::ObstacleCrossing => "obstacle_crossing",
            RunMode::Returning => "returning",
        }
    }
}

/// Gains of the target approach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gains {
    /// V_c, m/s.
    pub speed_mps: f64,
    /// k_w, 1/s.
    pub turn_gain: f64,
    /// Targets further off the heading than this are turned to on the spot.
    pub turn_in_place_rad: f64,
}

/// Slowest on-the-spot turn, rad/s (k_w·α vanishes as α does).
const MIN_SPOT_TURN_RADPS: f64 = 0.4;

/// Target approach, eqs. 1–3: v = V_c, ω = k_w·atan(S / L) for a target at (L, S) in the
/// robot frame. A target more than `turn_in_place_rad` off the heading is first turned to
/// on the spot (v = 0), as a tracked robot does, so that it never drives away from it.
pub fn target_approach(target: Point2, gains: Gains) -> Velocity {
    let alpha = target.y.atan2(target.x);
    if alpha.abs() > gains.turn_in_place_rad {
        let w = (gains.turn_gain * alpha).abs().max(MIN_SPOT_TURN_RADPS);
        return Velocity {
            linear_mps: 0.0,
            angular_radps: w.copysign(alpha),
        };
    }
    Velocity {
        linear_mps: gains.speed_mps,
        angular_radps: gains.turn_gain * alpha,
    }
}

/// Widest clearance used in the central run: beyond it a side opening would pull the robot.
const CENTRAL_RUN_CAP_M: f64 = 2.0;

/// Central run, eq. 4: the target approach towards (L, S) with S = (L_l − L_r) / 2.
pub fn central_run(clearance: SideClearance, look_ahead_m: f64, gains: Gains) -> Velocity {
    let (l, r) = (
        clearance.left_m.min(CENTRAL_RUN_CAP_M),
        clearance.right_m.min(CENTRAL_RUN_CAP_M),
    );
    target_approach(Point2::new(look_ahead_m, (l - r) / 2.0), gains)
}

/// Dead-end run: turn on the spot (counter-clockwise) until L_l + L_r > C₂ again.
pub fn dead_end_turn(gains: Gains) -> Velocity {
    Velocity {
        linear_mps: 0.0,
        angular_radps: (gains.turn_gain * std::f64::consts::FRAC_PI_2).max(MIN_SPOT_TURN_RADPS),
    }
}

/// Half width of the side sector in which the followed wall is looked for.
const SIDE_SECTOR_HALF_RAD: f64 = 30.0 * std::f64::consts::PI / 180.0;

/// Distance to the followed wall: the nearest point within 30° of the robot's right (or
/// left) side. Narrow enough that a doorway the robot passes opens the sector (it turns
/// in), wide enough that a wall ending behind the robot still guides it round the corner.
pub fn side_distance(scan: &ScanView, right_side: bool) -> f64 {
    let side = std::f64::consts::FRAC_PI_2;
    scan.points
        .iter()
        .filter(|p| {
            let a = p.y.atan2(p.x);
            let a = if right_side { -a } else { a };
            (a - side).abs() <= SIDE_SECTOR_HALF_RAD
        })
        .map(|p| p.x.hypot(p.y))
        .fold(scan.max_range_m, f64::min)
}

/// Wall following (§IV-B): keeps `distance_m` from the wall on the right (or left) side; a
/// wall ahead closer than that distance is turned away from on the spot.
pub fn wall_following(
    scan: &ScanView,
    right_side: bool,
    distance_m: f64,
    look_ahead_m: f64,
    half_width_m: f64,
    gains: Gains,
) -> Velocity {
    let front = scan.front_clearance(half_width_m + 0.1);
    if front < distance_m {
        let w = (gains.turn_gain * std::f64::consts::FRAC_PI_4).max(MIN_SPOT_TURN_RADPS);
        return Velocity {
            linear_mps: 0.0,
            angular_radps: if right_side { w } else { -w },
        };
    }
    let side = side_distance(scan, right_side);
    let error = (side - distance_m).clamp(-look_ahead_m, look_ahead_m);
    let s = if right_side { -error } else { error };
    target_approach(Point2::new(look_ahead_m, s), gains)
}

/// Step between the headings tried by [`free_heading`].
const FREE_HEADING_STEP_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// How far the lane of half width `half_width_m` along `heading_rad` (robot frame) is open:
/// the smallest p·u over the laser points `p` with |p × u| < `half_width_m` and p·u > 0, or
/// the laser's maximum range.
pub fn lane_length(scan: &ScanView, heading_rad: f64, half_width_m: f64) -> f64 {
    lane_open_m(
        &scan.points,
        Point2::default(),
        heading_rad,
        half_width_m,
        scan.max_range_m,
    )
}

/// How far a lane of half width `half_width_m` runs free from `centre` along `direction_rad`
/// (world frame): the smallest distance along it of the `points` within the half width
/// ahead of the centre, or `max_m`.
pub fn lane_open_m(
    points: &[Point2],
    centre: Point2,
    direction_rad: f64,
    half_width_m: f64,
    max_m: f64,
) -> f64 {
    let (s, c) = direction_rad.sin_cos();
    points
        .iter()
        .map(|p| (p.x - centre.x, p.y - centre.y))
        .filter(|(dx, dy)| (dx * s - dy * c).abs() < half_width_m)
        .map(|(dx, dy)| dx * c + dy * s)
        .filter(|&along| along > 0.0)
        .fold(max_m, f64::min)
}

/// Obstacle avoidance on a return route — an addition to §IV, whose behaviours all start from
/// an un-searched link: a robot driving back along a searched link aims at points of the path
/// it drove, but its pose estimate has drifted since, so on a cluttered floor the straight
/// line to the next point can run into a chair or a desk leg the link's path passed beside.
///
/// Of the headings within `max_deviation_rad` of `goal_rad` (robot frame), every
/// [`FREE_HEADING_STEP_RAD`], the one nearest the goal whose lane is clear: no laser point
/// `p` with 0 < p·u < `reach_m` and |p × u| < `half_width_m` (u the heading's unit vector) —
/// the vector-field-histogram idea reduced to one lane per heading. Between two headings
/// equally far from the goal, the one whose lane is open further wins (then the left one).
/// `None` when every lane is blocked.
pub fn free_heading(
    scan: &ScanView,
    goal_rad: f64,
    half_width_m: f64,
    reach_m: f64,
    max_deviation_rad: f64,
) -> Option<f64> {
    let lane_open = |a: f64| lane_length(scan, a, half_width_m);
    let steps = (max_deviation_rad / FREE_HEADING_STEP_RAD).floor() as i32;
    for k in 0..=steps {
        let candidates = if k == 0 {
            [Some(goal_rad), None]
        } else {
            let d = f64::from(k) * FREE_HEADING_STEP_RAD;
            [Some(goal_rad - d), Some(goal_rad + d)]
        };
        let best = candidates
            .into_iter()
            .flatten()
            .map(|a| (lane_open(a), a))
            .filter(|(open, _)| *open >= reach_m)
            .max_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((_, a)) = best {
            return Some(a);
        }
    }
    None
}

/// What Fig. 8 chooses from, during exploration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeInputs {
    /// The robot is crossing a 3-D obstacle.
    pub crossing_obstacle: bool,
    /// The robot is inside a free space (between its entrance and exit nodes).
    pub in_free_space: bool,
    /// A divergence candidate (circumcentre) is being approached.
    pub has_candidate: bool,
    /// L_l, L_r in the grey area ahead (Fig. 9).
    pub clearance: SideClearance,
    /// C₂, the robot width.
    pub robot_width_m: f64,
}

/// The run mode of Fig. 8: obstacle crossing first (the laser's view ahead is not of walls
/// then), a Delaunay triangle next (branch selection), then free space (wall following),
/// then the dead-end test L_l + L_r < C₂, the central run otherwise.
pub fn select_run_mode(inputs: &ModeInputs) -> RunMode {
    if inputs.crossing_obstacle {
        RunMode::ObstacleCrossing
    } else if inputs.has_candidate {
        RunMode::BranchSelection
    } else if inputs.in_free_space {
        RunMode::WallFollowing
    } else if inputs.clearance.width_m() < inputs.robot_width_m {
        RunMode::DeadEndRun
    } else {
        RunMode::CentralRun
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GAINS: Gains = Gains {
        speed_mps: 0.4,
        turn_gain: 1.5,
        turn_in_place_rad: 0.785,
    };

    #[test]
    fn target_approach_follows_eq_3() {
        let v = target_approach(Point2::new(1.0, 0.5), GAINS);
        assert_eq!(v.linear_mps, 0.4);
        assert!((v.angular_radps - 1.5 * 0.5f64.atan()).abs() < 1e-12);
        let behind = target_approach(Point2::new(-1.0, -0.1), GAINS);
        assert_eq!(behind.linear_mps, 0.0);
        assert!(behind.angular_radps < 0.0);
    }

    #[test]
    fn central_run_steers_to_the_middle_of_the_passage() {
        let off_left = SideClearance {
            left_m: 0.4,
            right_m: 1.2,
        };
        let v = central_run(off_left, 1.0, GAINS);
        // S = (0.4 − 1.2) / 2 = −0.4: turn right.
        assert!((v.angular_radps - 1.5 * (-0.4f64).atan()).abs() < 1e-12);
    }

    #[test]
    fn free_heading_steers_round_an_obstacle_on_the_way() {
        // A post 0.1 m wide 0.8 m straight ahead, the goal straight ahead beyond it.
        let mut points = Vec::new();
        for i in 0..5 {
            points.push(Point2::new(0.8, -0.05 + 0.025 * f64::from(i)));
        }
        let scan = ScanView {
            points,
            max_range_m: 20.0,
            ..ScanView::default()
        };
        assert_eq!(free_heading(&scan, 0.0, 0.25, 0.5, 1.5), Some(0.0));
        let a = free_heading(&scan, 0.0, 0.25, 1.2, 1.5).unwrap();
        assert!(a.abs() > 0.2 && a.abs() < 0.6, "{a}");
        // Walled in on every side within reach: no heading.
        let ring: Vec<Point2> = (0..72)
            .map(|i| {
                let t = f64::from(i) * 5f64.to_radians();
                Point2::new(0.6 * t.cos(), 0.6 * t.sin())
            })
            .collect();
        let closed = ScanView {
            points: ring,
            max_range_m: 20.0,
            ..ScanView::default()
        };
        assert_eq!(free_heading(&closed, 0.0, 0.25, 1.0, 3.2), None);
    }

    #[test]
    fn fig_8_prefers_obstacles_then_triangles_then_free_space_then_dead_ends() {
        let mut inputs = ModeInputs {
            crossing_obstacle: false,
            in_free_space: false,
            has_candidate: false,
            clearance: SideClearance {
                left_m: 0.1,
                right_m: 0.1,
            },
            robot_width_m: 0.45,
        };
        assert_eq!(select_run_mode(&inputs), RunMode::DeadEndRun);
        inputs.in_free_space = true;
        assert_eq!(select_run_mode(&inputs), RunMode::WallFollowing);
        inputs.has_candidate = true;
        assert_eq!(select_run_mode(&inputs), RunMode::BranchSelection);
        inputs.crossing_obstacle = true;
        assert_eq!(select_run_mode(&inputs), RunMode::ObstacleCrossing);
        inputs = ModeInputs {
            clearance: SideClearance {
                left_m: 0.8,
                right_m: 0.8,
            },
            ..ModeInputs {
                crossing_obstacle: false,
                in_free_space: false,
                has_candidate: false,
                ..inputs
            }
        };
        assert_eq!(select_run_mode(&inputs), RunMode::CentralRun);
    }
}

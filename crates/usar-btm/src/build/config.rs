//! Every constant of BTM generation (paper 004 §III–IV) that the paper leaves open, with the
//! default chosen here and why.

use super::BuildError;
use serde::{Deserialize, Serialize};

/// Parameters of [`crate::build::build_btm`]. Lengths in metres, angles in radians, speeds in
/// m/s. Defaults suit the paper-004 course (passages 1.0–2.2 m wide, a hall wider than 8 m)
/// and robots 0.4–0.5 m wide with the simulator's default sensors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BuildConfig {
    // --- Divergence nodes (§III-A-1, Fig. 2) ---
    /// D1: near edge of the band Ω₁ = {(x, y) | D1 < x < D2} ahead of the robot whose laser
    /// points are triangulated. 0.3 m: just beyond the front of a 0.6 m long robot.
    pub band_near_m: f64,
    /// D2: far edge of the band, also its lateral half width. 4 m: the spacing of 1° laser
    /// points along a passage wall 0.8 m to the side stays below a robot width (0.45 m) up to
    /// about 4.5 m ahead, so every triangle inside a plain passage has a short side.
    pub band_far_m: f64,
    /// How far past 90° a triangle's largest angle may be before it counts as obtuse. The
    /// triangle inscribed in a dead end is right-angled; laser noise tilts it either way.
    pub obtuse_tolerance_rad: f64,
    /// Gaps (triangle sides, openings between link points) count as passages when wider than
    /// the robot by this margin. The paper takes every gap wider than the robot (0, the
    /// default); on a cluttered real floor a margin (0.35 m in `configs/btm-real-floor.toml`)
    /// keeps the robot to corridors and doorways instead of the slots between desks.
    pub passage_margin_m: f64,
    /// A gap becomes an un-searched link only when a lane as wide as the robot plus
    /// [`LINK_LANE_MARGIN_M`](crate::build::divergence::LINK_LANE_MARGIN_M) runs free from
    /// the node through it for at least this far. The paper takes every gap (0, the
    /// default); on a cluttered real floor (3 m in `configs/btm-real-floor.toml`) the gaps
    /// between chairs and desk legs, behind which the next obstacle stands within a few
    /// metres, are not links: the robot keeps to corridors and doorways, where it can drive
    /// without touching anything. When set, a circumcentre is also approached only when the
    /// same lane runs free from the robot to it.
    pub link_min_open_m: f64,
    /// Search circle for links (Fig. 2 f): circumradius of the triangle plus this margin.
    pub search_margin_m: f64,
    /// Candidates closer than this to the node the robot is leaving are that node again.
    pub node_exclusion_m: f64,
    /// A divergence found within this distance of a known node is that node (loop closure).
    pub merge_radius_m: f64,

    // --- Free-space nodes (§III-A-1, Fig. 3) ---
    /// C₁: a side is free space when its clearance L_l or L_r exceeds this. The paper uses the
    /// laser's maximum range; the simulator's laser reaches 20 m, so 4 m (the course's search
    /// radius: its hall is wider than twice this) is used instead.
    pub free_space_clearance_m: f64,
    /// Half length (along x, centred on the robot) of the grey strip of Fig. 3 in which the
    /// minimum lateral distances are taken for the entrance test. 1 m: a strip 2 m long is
    /// longer than any passage is wide, so a side passage at a junction never looks free.
    pub free_space_strip_half_m: f64,
    /// The exit is declared after both sides beside the robot have stayed closer than C₁ for
    /// this distance driven (hall corners met head-on are shorter than this).
    pub free_space_exit_confirm_m: f64,

    // --- Obstacle nodes (§III-A-2, Figs. 4–5) ---
    /// Height (L − l₁)·cos θ above which the tilted laser reports a 3-D obstacle.
    pub obstacle_detect_height_m: f64,
    /// A tilted-laser return is a wall, not floor, when the horizontal laser is blocked within
    /// this distance of it in the same direction.
    pub obstacle_wall_margin_m: f64,
    /// V_max as a standard deviation: a piece whose residual about its least-squares line is
    /// larger is stairs, otherwise a slope. 2 cm lies between a ramp on a 0.1 m grid
    /// (≈ 1 cm) and stairs of 0.1 m rises (≈ 3 cm).
    pub stairs_min_residual_sd_m: f64,
    /// Body inclination below which the robot stands level.
    pub level_attitude_rad: f64,
    /// The crossing of an obstacle ends after this distance driven on level floor with level
    /// floor ahead. (Obstacles are observed only while the robot stands level: a node is made
    /// from each such observation when the robot starts to climb.)
    pub level_confirm_m: f64,
    /// Profile length that must be seen before passability is judged.
    pub judge_profile_m: f64,
    /// Clearance kept between an impassable obstacle and the robot's turning circle.
    pub obstacle_stop_clearance_m: f64,

    // --- Locomotion (§IV) ---
    /// V_c of eq. 1.
    pub approach_speed_mps: f64,
    /// k_w of eqs. 2–3, 1/s.
    pub turn_gain: f64,
    /// L of eq. 3 for the central run and wall following: the look-ahead distance.
    pub look_ahead_m: f64,
    /// Targets more than this off the heading are turned to on the spot first.
    pub turn_in_place_rad: f64,
    /// C₃: radius around a circumcentre within which the robot has arrived.
    pub arrival_radius_m: f64,
    /// C₄: distance from the node of the target set on the chosen link.
    pub branch_target_m: f64,
    /// Far edge of the grey area of Fig. 9 (from the robot centre) for L_l, L_r in the central
    /// run and the dead-end test.
    pub run_strip_m: f64,
    /// Distance kept from the wall in wall following.
    pub wall_distance_m: f64,
    /// Speed on obstacles, as a fraction of V_c.
    pub obstacle_speed_factor: f64,

    // --- Localisation ---
    /// Correct odometry by matching each scan against a key scan (point-to-line ICP).
    pub scan_matching: bool,
    /// A new key scan is taken after this distance ...
    pub keyframe_distance_m: f64,
    /// ... or this turn (π: a 360° scan overlaps its key scan whatever the turn, and every
    /// new key scan adds its own small error).
    pub keyframe_angle_rad: f64,
    /// Match against the robot's own map of all the scans it took before
    /// ([`usar_map::localization::ScanMap`]) instead of the last key scan. Off by default: on the
    /// generated course, whose slopes and stairs the horizontal laser sees as walls that move
    /// as the robot pitches, the map does worse (measured, seeds 1–5: largest position error
    /// 0.3–1.2 m and 89 collisions on seed 3, against 0.1–0.3 m and none with key scans); on
    /// a real floor (`configs/btm-real-floor.toml`) the frame the map keeps holds node
    /// coordinates together (Willow Garage, seed 1, that preset: largest position error
    /// 0.94 m with key scans, 0.34 m with the map).
    pub scan_map: bool,

    // --- Run ---
    /// Simulated time after which the build stops unfinished.
    pub max_time_s: f64,
    /// Simulation step.
    pub dt_s: f64,
}

impl Default for BuildConfig {
    fn default() -> Self {
        Self {
            band_near_m: 0.3,
            band_far_m: 4.0,
            obtuse_tolerance_rad: 8f64.to_radians(),
            passage_margin_m: 0.0,
            link_min_open_m: 0.0,
            search_margin_m: 0.5,
            node_exclusion_m: 1.5,
            merge_radius_m: 1.5,
            free_space_clearance_m: 4.0,
            free_space_strip_half_m: 1.0,
            free_space_exit_confirm_m: 1.0,
            obstacle_detect_height_m: 0.04,
            obstacle_wall_margin_m: 0.15,
            stairs_min_residual_sd_m: 0.02,
            level_attitude_rad: 3f64.to_radians(),
            level_confirm_m: 0.6,
            judge_profile_m: 0.25,
            obstacle_stop_clearance_m: 0.15,
            approach_speed_mps: 0.4,
            turn_gain: 1.5,
            look_ahead_m: 1.0,
            turn_in_place_rad: 45f64.to_radians(),
            arrival_radius_m: 0.2,
            branch_target_m: 1.0,
            run_strip_m: 0.8,
            wall_distance_m: 0.7,
            obstacle_speed_factor: 0.6,
            scan_matching: true,
            keyframe_distance_m: 1.0,
            keyframe_angle_rad: std::f64::consts::PI,
            scan_map: false,
            max_time_s: 3600.0,
            dt_s: 0.1,
        }
    }
}

impl BuildConfig {
    /// Checks the values; the error ([`BuildError::Config`]) names the field, the value found
    /// and what was expected.
    pub fn validate(&self) -> Result<(), BuildError> {
        let bad = |field: &str, found: String| BuildError::Config {
            field: field.into(),
            found,
        };
        let positive = [
            ("band_far_m", self.band_far_m),
            ("search_margin_m", self.search_margin_m),
            ("free_space_clearance_m", self.free_space_clearance_m),
            ("free_space_strip_half_m", self.free_space_strip_half_m),
            ("obstacle_detect_height_m", self.obstacle_detect_height_m),
            ("stairs_min_residual_sd_m", self.stairs_min_residual_sd_m),
            ("approach_speed_mps", self.approach_speed_mps),
            ("turn_gain", self.turn_gain),
            ("look_ahead_m", self.look_ahead_m),
            ("arrival_radius_m", self.arrival_radius_m),
            ("branch_target_m", self.branch_target_m),
            ("run_strip_m", self.run_strip_m),
            ("wall_distance_m", self.wall_distance_m),
            ("obstacle_speed_factor", self.obstacle_speed_factor),
            ("keyframe_distance_m", self.keyframe_distance_m),
            ("keyframe_angle_rad", self.keyframe_angle_rad),
            ("max_time_s", self.max_time_s),
            ("dt_s", self.dt_s),
        ];
        for (field, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(field, format!("{v}, expected a positive number")));
            }
        }
        let non_negative = [
            ("band_near_m", self.band_near_m),
            ("passage_margin_m", self.passage_margin_m),
            ("link_min_open_m", self.link_min_open_m),
            ("obtuse_tolerance_rad", self.obtuse_tolerance_rad),
            ("node_exclusion_m", self.node_exclusion_m),
            ("merge_radius_m", self.merge_radius_m),
            ("free_space_exit_confirm_m", self.free_space_exit_confirm_m),
            ("obstacle_wall_margin_m", self.obstacle_wall_margin_m),
            ("level_attitude_rad", self.level_attitude_rad),
            ("level_confirm_m", self.level_confirm_m),
            ("judge_profile_m", self.judge_profile_m),
            ("obstacle_stop_clearance_m", self.obstacle_stop_clearance_m),
            ("turn_in_place_rad", self.turn_in_place_rad),
        ];
        for (field, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(bad(field, format!("{v}, expected a number ≥ 0")));
            }
        }
        if self.band_near_m >= self.band_far_m {
            return Err(bad(
                "band_near_m",
                format!(
                    "{}, expected less than band_far_m = {}",
                    self.band_near_m, self.band_far_m
                ),
            ));
        }
        Ok(())
    }
}

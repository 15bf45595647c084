//! Obstacle crossing (§III-A-2): observing an obstacle from level floor with the tilted laser,
//! judging whether the robot can climb it, and making its obstacle node.

use super::*;

/// Reverse driven after meeting an impassable obstacle, metres.
const BACKOFF_M: f64 = 0.3;
/// Floor returns kept from before an obstacle is seen, metres driven.
pub(super) const RECENT_FLOOR_M: f64 = 0.3;
/// Less obstacle than this seen from level floor makes no node, metres.
const OBSTACLE_MIN_LENGTH_M: f64 = 0.1;

/// Whether the horizontal laser has a return where a raised tilted-laser return `hit` lies:
/// within one beam of its bearing and no further than its distance plus `margin_m`.
fn seen_by_horizontal_laser(view: &ScanView, hit: &FloorHit, margin_m: f64) -> bool {
    if hit.height_m <= 0.0 {
        return false;
    }
    let bearing = hit.lateral_m.atan2(hit.forward_m);
    let range = hit.forward_m.hypot(hit.lateral_m);
    view.min_range_near(bearing, 1.5 * view.angle_increment_rad) <= range + margin_m
}

/// The obstacle shape of paper 004's node table.
fn obstacle_subtype(stairs: bool) -> &'static str {
    if stairs {
        subtype::STAIRS
    } else {
        subtype::SLOPE
    }
}

/// An obstacle node's values: the step height of stairs or the inclination of a slope, and the
/// largest body inclination measured.
fn set_obstacle_values(
    n: &mut crate::model::Node,
    stairs: bool,
    step_m: Option<f64>,
    inclination_rad: f64,
    max_robot_inclination_rad: f64,
) {
    if stairs {
        n.step_height_m = step_m;
    } else {
        n.slope_inclination_rad = Some(inclination_rad);
    }
    n.max_robot_inclination_rad = Some(max_robot_inclination_rad);
}

pub(super) struct Crossing {
    start_driven_m: f64,
    /// The current observation, taken from level floor (x from `start_driven_m`).
    profile: ObstacleProfile,
    /// Whether the robot stands level and records `profile`.
    observing: bool,
    /// Along-path position of the first return that showed the current obstacle.
    detect_along_m: f64,
    judged: bool,
    level_run_m: f64,
    contact_steps: u32,
    /// The last obstacle node made in this crossing and the largest inclination since.
    last_node: Option<u32>,
    max_inclination_rad: f64,
    /// Body inclinations while on the obstacle since the last node.
    on_obstacle_rad: Vec<f64>,
    /// The judgement found the obstacle impassable: (inclination, step).
    impassable: Option<(f64, Option<f64>)>,
}

impl Explorer<'_> {
    /// The obstacle ahead on the robot's track, if the tilted laser sees one that is not a
    /// wall: the height and distance of its return.
    ///
    /// A raised return that the horizontal laser also sees at the same place (same bearing,
    /// within `obstacle_wall_margin_m` of its range) is the side of a wall or of furniture
    /// standing from the floor past the horizontal scan plane, not a slope or a stair: it is
    /// left out before the median of the track is taken. (Checking only straight ahead let a
    /// chair leg off the axis but under the track read as stairs on a flat floor.)
    fn obstacle_ahead(&self) -> Option<FloorHit> {
        let half = self.spec.width_m / 2.0;
        let view = &self.view;
        let margin = self.cfg.obstacle_wall_margin_m;
        // Off-track hits are left out before the (costlier) wall check.
        let floor = self
            .hits
            .iter()
            .filter(|h| h.lateral_m.abs() <= half && !seen_by_horizontal_laser(view, h, margin))
            .copied();
        let s = track_sample(floor, half)?;
        if s.height_m.abs() <= self.cfg.obstacle_detect_height_m {
            return None;
        }
        if s.height_m > 0.0 {
            let ahead = self.view.min_range_near(0.0, 3f64.to_radians());
            if ahead <= s.forward_m + self.cfg.obstacle_wall_margin_m {
                return None;
            }
        }
        Some(s)
    }

    /// Starts a crossing when a level robot sees an obstacle ahead.
    pub(super) fn detect_obstacle(&self) -> Option<Crossing> {
        if self.inclination_rad >= self.cfg.level_attitude_rad {
            return None;
        }
        let s = self.obstacle_ahead()?;
        let mut c = Crossing {
            start_driven_m: self.driven_m,
            profile: ObstacleProfile::default(),
            observing: true,
            detect_along_m: s.forward_m,
            judged: false,
            level_run_m: 0.0,
            contact_steps: 0,
            last_node: None,
            max_inclination_rad: 0.0,
            on_obstacle_rad: Vec::new(),
            impassable: None,
        };
        for &(driven, forward, height) in &self.recent_floor {
            c.profile.push(driven - c.start_driven_m + forward, height);
        }
        Some(c)
    }

    /// Adds the tilted laser's returns on the robot's track to the observation: heights above
    /// the level floor the robot stands on, (L − l₁)·cos θ for the central beam.
    fn record_profile(&self, c: &mut Crossing) {
        let half = self.spec.width_m / 2.0;
        let along = self.driven_m - c.start_driven_m;
        for h in self.hits.iter().filter(|h| h.lateral_m.abs() <= half) {
            c.profile.push(along + h.forward_m, h.height_m);
        }
    }

    /// Obstacle crossing: observe the obstacle from level floor, judge whether the robot
    /// can climb it, make its node when the robot starts to climb (the observation ends),
    /// observe again from every level stretch on it, and finish on level floor with level
    /// floor ahead.
    pub(super) fn cross(
        &mut self,
        mut ex: Exploration,
        mut c: Crossing,
    ) -> Result<Velocity, BuildError> {
        self.mode = RunMode::ObstacleCrossing;
        let level = self.inclination_rad < self.cfg.level_attitude_rad;
        let robot_along = self.driven_m - c.start_driven_m;
        if self.contact {
            c.contact_steps += 1;
        } else {
            c.contact_steps = 0;
        }
        if self.inclination_rad > c.max_inclination_rad {
            c.max_inclination_rad = self.inclination_rad;
            if let Some(node) = c.last_node {
                self.map.update_node(node, |n| {
                    n.max_robot_inclination_rad = Some(c.max_inclination_rad)
                })?;
            }
        }
        let mut hold = false;
        if c.observing {
            if level && self.driven_m > c.start_driven_m + 1e-9 {
                self.record_profile(&mut c);
            }
            let stop_at = c.detect_along_m
                - (self.spec.circumscribed_radius_m() + self.cfg.obstacle_stop_clearance_m);
            let at_limit = robot_along >= stop_at || c.contact_steps > 3 || !level;
            if !c.judged {
                let judge = if at_limit {
                    0.0
                } else {
                    self.cfg.judge_profile_m
                };
                match c.profile.passability(
                    c.detect_along_m - 0.01,
                    judge,
                    self.spec.max_inclination_rad,
                    self.spec.max_step_m,
                ) {
                    Passability::Impassable {
                        inclination_rad,
                        step_m,
                    } => {
                        c.judged = true;
                        c.impassable = Some((inclination_rad, step_m));
                    }
                    Passability::Passable => c.judged = true,
                    Passability::Undecided => hold = at_limit,
                }
            }
            if let Some((inclination_rad, step_m)) = c.impassable {
                // Observe on up to where the robot must stop, then record what it saw.
                if at_limit {
                    return self.impassable(ex, &c, inclination_rad, step_m);
                }
            } else if !level {
                // The robot climbs onto what it observed: that is an obstacle node.
                self.close_observation(&mut ex, &mut c)?;
            }
        } else if level {
            self.finish_slope(&mut c)?;
            if let Some(s) = self.obstacle_ahead() {
                // Level on the obstacle (its top) with more of it ahead: observe again.
                c.profile = ObstacleProfile::default();
                c.start_driven_m = self.driven_m;
                c.detect_along_m = s.forward_m;
                c.observing = true;
                c.judged = false;
                c.level_run_m = 0.0;
                self.record_profile(&mut c);
            } else {
                c.level_run_m += self.step_m;
            }
        } else {
            c.on_obstacle_rad.push(self.inclination_rad);
            c.level_run_m = 0.0;
        }
        if c.contact_steps > 2 * STUCK_STEPS {
            let piece = c.profile.piece(
                self.cfg.obstacle_detect_height_m,
                self.cfg.stairs_min_residual_sd_m,
                0.0,
            );
            let inclination = piece.map_or(0.0, |p| p.inclination_rad);
            let step = piece.and_then(|p| p.step_height_m);
            return self.impassable(ex, &c, inclination, step);
        }
        if !c.observing && c.level_run_m >= self.cfg.level_confirm_m {
            self.finish_slope(&mut c)?;
            ex.phase = Phase::Running;
            self.state = State::Explore(ex);
            return Ok(Velocity::default());
        }
        let h = self.spec.length_m / 2.0;
        let beside = self.view.side_clearance(-h, 0.6 * h);
        let mut gains = self.gains();
        gains.speed_mps *= self.cfg.obstacle_speed_factor;
        let mut v = central_run(beside, self.cfg.look_ahead_m, gains);
        if hold {
            v.linear_mps = 0.0;
        }
        ex.phase = Phase::Crossing(c);
        self.state = State::Explore(ex);
        Ok(v)
    }

    fn impassable(
        &mut self,
        ex: Exploration,
        c: &Crossing,
        inclination_rad: f64,
        step_m: Option<f64>,
    ) -> Result<Velocity, BuildError> {
        let name = self.spec.name.clone();
        if let (Some(node), false) = (c.last_node, c.observing) {
            // Stuck on the obstacle it has begun to climb: that node is where it cannot pass;
            // the link beyond it was never driven.
            let max_inclination = c.max_inclination_rad.max(self.inclination_rad);
            self.map.update_node(node, |n| {
                n.max_robot_inclination_rad = Some(max_inclination);
                n.extra.insert(IMPASSABLE_FOR.into(), name.into());
            })?;
            self.map.remove_unsearched(ex.link)?;
            self.node = node;
            self.state = State::Backoff {
                until_driven_m: self.driven_m + BACKOFF_M,
            };
            self.mode = RunMode::DeadEndRun;
            return Ok(Velocity::default());
        }
        let pose = self.pose();
        let robot_along = self.driven_m - c.start_driven_m;
        let ahead = (c.detect_along_m - robot_along).max(0.0);
        let at = pose.to_world(Point2::new(ahead, 0.0));
        // The shape by the paper's variance test; the values as the judgement found them
        // (a riser higher than the robot climbs, or the inclination).
        let piece = c.profile.piece(
            self.cfg.obstacle_detect_height_m,
            self.cfg.stairs_min_residual_sd_m,
            0.0,
        );
        let piece = piece.filter(|p| p.end_m - p.start_m >= OBSTACLE_MIN_LENGTH_M);
        let stairs = step_m.is_some() || piece.is_some_and(|p| p.shape == ObstacleShape::Stairs);
        let step_m = piece.and_then(|p| p.step_height_m).or(step_m);
        let max_inclination = c.max_inclination_rad.max(self.inclination_rad);
        let node = self
            .map
            .add_node(at, kind::OBSTACLE, Some(obstacle_subtype(stairs)), |n| {
                set_obstacle_values(n, stairs, step_m, inclination_rad, max_inclination);
                n.extra.insert(IMPASSABLE_FOR.into(), name.into());
            })?;
        let from = self.node_position(ex.from);
        self.map
            .close_link(ex.link, node, ex.rec.measures(from, at))?;
        self.node = node;
        self.state = State::Backoff {
            until_driven_m: self.driven_m + BACKOFF_M,
        };
        self.mode = RunMode::DeadEndRun;
        Ok(Velocity::default())
    }

    /// The robot is level again after a slope: its inclination becomes the median body
    /// inclination while it stood on it (within 75 % of the largest), which the paper saves
    /// ("it passed over the slope and the maximum inclination angle is saved"); the tilted
    /// laser's estimate stays in `extra`.
    fn finish_slope(&mut self, c: &mut Crossing) -> Result<(), BuildError> {
        let samples = std::mem::take(&mut c.on_obstacle_rad);
        let Some(node) = c.last_node else {
            return Ok(());
        };
        let max = samples.iter().copied().fold(0.0, f64::max);
        let mut on: Vec<f64> = samples.into_iter().filter(|&v| v >= 0.75 * max).collect();
        if on.is_empty() {
            return Ok(());
        }
        on.sort_by(f64::total_cmp);
        let median = on[on.len() / 2];
        self.map.update_node(node, |n| {
            if n.subtype.as_deref() == Some(subtype::SLOPE) {
                if let Some(profile) = n.slope_inclination_rad {
                    n.extra
                        .insert("profile_inclination_rad".into(), profile.into());
                }
                n.slope_inclination_rad = Some(median);
            }
        })?;
        Ok(())
    }

    /// The robot has begun to climb what it observed: an obstacle node at the obstacle's
    /// start ends the link driven so far, and a new link leaves it.
    fn close_observation(
        &mut self,
        ex: &mut Exploration,
        c: &mut Crossing,
    ) -> Result<(), BuildError> {
        c.observing = false;
        let Some(piece) = c.profile.piece(
            self.cfg.obstacle_detect_height_m,
            self.cfg.stairs_min_residual_sd_m,
            OBSTACLE_MIN_LENGTH_M,
        ) else {
            return Ok(());
        };
        let pose = self.pose();
        let robot_along = self.driven_m - c.start_driven_m;
        let at = pose.to_world(Point2::new(piece.start_m - robot_along, 0.0));
        let stairs = piece.shape == ObstacleShape::Stairs;
        let inclination = self.inclination_rad;
        let node = self
            .map
            .add_node(at, kind::OBSTACLE, Some(obstacle_subtype(stairs)), |n| {
                set_obstacle_values(
                    n,
                    stairs,
                    piece.step_height_m,
                    piece.inclination_rad,
                    inclination,
                );
                n.extra.insert("uphill".into(), piece.rising.into());
                n.extra
                    .insert("profile_residual_sd_m".into(), piece.residual_sd_m.into());
            })?;
        let before = ex.rec.split_before(self.driven_m);
        let from = self.node_position(ex.from);
        self.map
            .close_link(ex.link, node, before.measures(from, at))?;
        ex.link = self.map.add_unsearched(node, pose.theta)?;
        ex.from = node;
        c.last_node = Some(node);
        c.max_inclination_rad = inclination;
        Ok(())
    }
}

//! Driving back along searched links to the nearest node with an un-searched one (the
//! depth-first order of §III), with the additions a cluttered real floor needs: obstacle
//! avoidance on the way ([`free_heading`]) and, when the robot stalls on its way, planning
//! again from the node nearest to it before a goal is given up.

use super::*;

/// Obstacle avoidance on a return route ([`free_heading`]): the lane checked reaches to the
/// route point or this far, whichever is nearer, but at least [`AVOID_MIN_REACH_M`] ...
const AVOID_REACH_M: f64 = 1.0;
const AVOID_MIN_REACH_M: f64 = 0.5;
/// ... is wider than the robot by this on each side ...
const AVOID_SIDE_CLEARANCE_M: f64 = 0.05;
/// ... and may leave the direction of the route point by up to this.
const AVOID_MAX_DEVIATION_RAD: f64 = 100.0 * PI / 180.0;

/// Times a robot stuck on its way back plans again from the node nearest to it before it
/// gives the goal's un-searched links up.
const RETURN_REPLANS: u32 = 2;

/// Route stretch searched for the point nearest the robot after a detour, metres.
const RESUME_WINDOW_M: f64 = 2.0;

/// Clearance kept around the robot's turning circle: with anything nearer, a robot whose
/// route point lies behind it backs towards it instead of turning on the spot (a narrow
/// passage between furniture is left the way it was entered).
const TURN_CLEARANCE_M: f64 = 0.05;
/// Reverse speed as a fraction of the approach speed, and the gap kept behind, metres.
const REVERSE_SPEED_FACTOR: f64 = 0.5;
const REVERSE_STOP_M: f64 = 0.05;

pub(super) struct Route {
    pub(super) waypoints: Vec<Point2>,
    pub(super) index: usize,
    pub(super) goal: u32,
    /// The detour heading (world frame) being followed round an obstacle on the way.
    pub(super) detour_rad: Option<f64>,
}

impl Explorer<'_> {
    pub(super) fn plan_return(&mut self, node: u32) -> Result<(), BuildError> {
        let Some((links, goal)) = route_to_unsearched(&self.map.btm, node) else {
            return self.finish();
        };
        if links.is_empty() {
            let back = self.pose().theta + PI;
            return self.continue_from(goal, back);
        }
        let mut waypoints = Vec::new();
        let mut at = node;
        for l in links {
            if let Some(path) = self.map.path_from(l, at) {
                waypoints.extend(path);
            }
            at = match self.map.link(l) {
                Some(link) if link.start == at => link.end.unwrap_or(at),
                Some(link) => link.start,
                None => at,
            };
        }
        waypoints.push(self.node_position(goal));
        self.state = State::Return(Route {
            waypoints,
            index: 0,
            goal,
            detour_rad: None,
        });
        Ok(())
    }

    /// After repeated stalls: the link being explored, or every un-searched link of the node
    /// the robot could not drive back to, is marked [`BLOCKED_FOR`] this robot (it stays
    /// un-searched) and exploration goes on from the last node.
    ///
    /// A robot that could not drive back to a node first drives to the node nearest to it
    /// and plans again from there ([`Explorer::replan_from_nearest`]), up to
    /// [`RETURN_REPLANS`] times before it reaches any node: the place it is stuck at lies on
    /// its way, and says nothing about the un-searched links at the goal.
    pub(super) fn give_up(&mut self, target: Target) -> Result<(), BuildError> {
        if let Target::Node(_) = target
            && self.replans < RETURN_REPLANS
        {
            self.replans += 1;
            return self.replan_from_nearest();
        }
        let blocked: Vec<u32> = match target {
            Target::Link(link) => vec![link],
            Target::Node(node) => open_links(&self.map.btm, node).map(|l| l.id).collect(),
            Target::Backoff => Vec::new(),
        };
        let name = serde_json::Value::from(self.spec.name.clone());
        for link in blocked {
            self.map.set_link_extra(link, BLOCKED_FOR, name.clone())?;
        }
        // Back the way it came: along what it drove of the link it gave up, then on.
        let mut back: Vec<Point2> = match &self.state {
            State::Explore(ex) => ex.rec.samples.iter().rev().map(|s| s.position).collect(),
            _ => Vec::new(),
        };
        self.plan_return(self.node)?;
        if let State::Return(route) = &mut self.state {
            back.append(&mut route.waypoints);
            route.waypoints = back;
        }
        Ok(())
    }

    /// Drives to the node nearest the robot's estimated position (one it may drive through),
    /// then on by the shortest chain of searched links to a node with an un-searched link.
    fn replan_from_nearest(&mut self) -> Result<(), BuildError> {
        let here = self.pose().position();
        let nearest = self
            .map
            .btm
            .nodes
            .iter()
            .filter(|n| !n.extra.contains_key(IMPASSABLE_FOR))
            .map(|n| (Point2::new(n.x_m, n.y_m).distance(here), n.id))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let Some((_, node)) = nearest else {
            return self.plan_return(self.node);
        };
        let at = self.node_position(node);
        self.node = node;
        self.plan_return(node)?;
        match &mut self.state {
            State::Return(route) => route.waypoints.insert(0, at),
            State::Explore(_) => {
                self.state = State::Return(Route {
                    waypoints: vec![at],
                    index: 0,
                    goal: node,
                    detour_rad: None,
                });
            }
            _ => {}
        }
        Ok(())
    }

    pub(super) fn follow_route(&mut self, mut route: Route) -> Result<Velocity, BuildError> {
        self.mode = RunMode::Returning;
        let pose = self.pose();
        let here = pose.position();
        let last = route.waypoints.len() - 1;
        Self::advance_route(&mut route, here);
        let goal = route.waypoints[last];
        if route.index == last && here.distance(goal) < self.cfg.arrival_radius_m + 0.15 {
            // The direction back along the route from the goal.
            let back = route
                .waypoints
                .iter()
                .rev()
                .find(|p| p.distance(goal) >= ENTRY_LOOKBACK_M)
                .map_or(pose.theta + PI, |p| goal.bearing_to(*p));
            self.continue_from(route.goal, back)?;
            return Ok(Velocity::default());
        }
        let mut gains = self.gains();
        let target = pose.to_body(route.waypoints[route.index]);
        let behind = target.x < 0.0 && target.y.abs() < -target.x;
        let v = if behind && !self.turn_is_clear() {
            route.detour_rad = None;
            self.reverse_approach(target, gains)
        } else if self.inclination_rad > self.cfg.level_attitude_rad {
            // On a slope or stairs the horizontal laser sees the obstacle's own floor.
            gains.speed_mps *= self.cfg.obstacle_speed_factor;
            target_approach(target, gains)
        } else {
            let world_heading = |a: f64| normalize_angle(a + pose.theta);
            let (v, detour) = self.avoiding_approach(
                target,
                route.detour_rad.map(|h| normalize_angle(h - pose.theta)),
                gains,
            );
            route.detour_rad = detour.map(world_heading);
            v
        };
        self.state = State::Return(route);
        Ok(v)
    }

    /// Whether the robot can turn on the spot: no laser point within its circumscribed
    /// radius plus [`TURN_CLEARANCE_M`].
    fn turn_is_clear(&self) -> bool {
        let r = self.spec.circumscribed_radius_m() + TURN_CLEARANCE_M;
        self.view.points.iter().all(|p| p.x.hypot(p.y) > r)
    }

    /// Target approach driving backwards: the rear turns towards `target` (robot frame,
    /// behind the robot) as the front does in [`target_approach`], ω = k_w·(α − π); it stops
    /// short of anything close behind.
    fn reverse_approach(&self, target: Point2, gains: Gains) -> Velocity {
        let alpha = normalize_angle(target.y.atan2(target.x) - PI);
        let half = self.spec.width_m / 2.0;
        let blocked = self.view.points.iter().any(|p| {
            p.x < 0.0 && p.y.abs() <= half && -p.x < self.spec.length_m / 2.0 + REVERSE_STOP_M
        });
        Velocity {
            linear_mps: if blocked {
                0.0
            } else {
                -gains.speed_mps * REVERSE_SPEED_FACTOR
            },
            angular_radps: gains.turn_gain * alpha,
        }
    }

    /// Target approach towards `target` (robot frame) when its lane is clear; otherwise along
    /// the detour heading `detour` (robot frame) kept from earlier steps while its lane stays
    /// clear (so that the robot does not dither between lanes as its view turns), or the clear
    /// lane nearest to the target ([`free_heading`]); on the spot towards the more open side
    /// when no lane is clear. Returns the command and the detour heading now followed.
    fn avoiding_approach(
        &self,
        target: Point2,
        detour: Option<f64>,
        gains: Gains,
    ) -> (Velocity, Option<f64>) {
        let goal = target.y.atan2(target.x);
        let reach = target
            .x
            .hypot(target.y)
            .clamp(AVOID_MIN_REACH_M, AVOID_REACH_M);
        let half = self.spec.width_m / 2.0 + AVOID_SIDE_CLEARANCE_M;
        if lane_length(&self.view, goal, half) >= reach {
            return (target_approach(target, gains), None);
        }
        let heading = detour
            .filter(|&h| lane_length(&self.view, h, half) >= AVOID_MIN_REACH_M)
            .or_else(|| free_heading(&self.view, goal, half, reach, AVOID_MAX_DEVIATION_RAD));
        let v = match heading {
            Some(a) => target_approach(Point2::new(a.cos(), a.sin()), gains),
            None => {
                let open = self.view.side_clearance(-self.spec.length_m / 2.0, reach);
                let turn = dead_end_turn(gains);
                if open.right_m > open.left_m {
                    Velocity {
                        angular_radps: -turn.angular_radps,
                        ..turn
                    }
                } else {
                    turn
                }
            }
        };
        (v, heading)
    }

    /// The route point aimed at: the first one further than [`PATH_LOOK_AHEAD_M`]; during a
    /// detour, searched from the route point nearest the robot among the next
    /// [`RESUME_WINDOW_M`] of the route (the detour may have passed some).
    fn advance_route(route: &mut Route, here: Point2) {
        let last = route.waypoints.len() - 1;
        if route.detour_rad.is_some() {
            let mut best = (here.distance(route.waypoints[route.index]), route.index);
            let mut along = 0.0;
            for i in route.index + 1..=last {
                along += route.waypoints[i - 1].distance(route.waypoints[i]);
                if along > RESUME_WINDOW_M {
                    break;
                }
                let d = here.distance(route.waypoints[i]);
                if d < best.0 {
                    best = (d, i);
                }
            }
            route.index = best.1;
        }
        while route.index < last && here.distance(route.waypoints[route.index]) < PATH_LOOK_AHEAD_M
        {
            route.index += 1;
        }
    }
}

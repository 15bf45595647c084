//! The exploring robot: senses, localises, chooses a run mode (Fig. 8) and makes nodes and
//! links as it drives (§III), depth first over un-searched links.

mod crossing;
mod free_space_walk;
mod route;
mod stall;

use self::crossing::{Crossing, RECENT_FLOOR_M};
use self::free_space_walk::FreeSpaceWalk;
use self::route::Route;
use self::stall::{Remedy, StallWatch, Target};
use super::divergence::{
    LINK_LANE_MARGIN_M, divergence_subtype, divergence_triangles, open_directions,
};
use super::free_space::{ExitTracker, follow_right_wall, is_free_space};
use super::links::{LinkMeasures, LinkRecorder, LinkSample, MapWriter};
use super::obstacle::{
    FloorHit, ObstacleProfile, ObstacleShape, Passability, floor_hits, track_sample,
};
use super::planner::{open_links, route_to_unsearched};
use super::{BLOCKED_FOR, BuildConfig, BuildError, IMPASSABLE_FOR, StopReason};
use crate::locomotion::{
    Gains, ModeInputs, RunMode, central_run, dead_end_turn, free_heading, lane_length, lane_open_m,
    select_run_mode, side_distance, target_approach, wall_following,
};
use crate::model::{Btm, kind, subtype};
use crate::store::BtmStore;
use std::f64::consts::{PI, TAU};
use usar_map::localization::{Localizer, ScanView, SideClearance};
use usar_sim::host::{Controller, FleetIo};
use usar_sim::sensors::{Attitude, LaserScan, Odometry, TiltedScan};
use usar_sim::{RobotSpec, Velocity};
use usar_world::{Point2, Pose2, normalize_angle};

/// Two open directions closer than this to opposite are a plain passage, not a corner.
const STRAIGHT_TOLERANCE_RAD: f64 = 35.0 * PI / 180.0;
/// An open direction within this of the way the robot came is the link it arrived by.
const ENTRY_MATCH_RAD: f64 = 60.0 * PI / 180.0;
/// A candidate circumcentre moves to a new triangle's only within this distance.
const CANDIDATE_TRACK_M: f64 = 1.0;
/// Distance back along the path used for the direction of the link arrived by.
const ENTRY_LOOKBACK_M: f64 = 1.0;
/// Look-ahead along a known link's path when driving back.
const PATH_LOOK_AHEAD_M: f64 = 0.6;
/// Speed of the robot's reverse moves, m/s.
const BACKOFF_SPEED_MPS: f64 = 0.2;
/// Steps in contact after which the robot backs up a little (a scraped corner).
const STUCK_STEPS: u32 = 15;
const RECOVERY_STEPS: u32 = 5;
/// A dead end is confirmed this much inside the tilted laser's reach, metres.
/// [`Explorer::safe`]: the turn of a robot lining up with a passage, and how far off its
/// axis the wall that stopped it must be for that.
const MIN_ALIGN_TURN_RADPS: f64 = 0.3;
const ALIGN_OFF_AXIS_M: f64 = 0.05;
const DEAD_END_MARGIN_M: f64 = 0.1;
/// Time an approach may take before the robot settles for where it got, seconds.
const APPROACH_PATIENCE_S: f64 = 20.0;

enum State {
    Explore(Exploration),
    Return(Route),
    Backoff { until_driven_m: f64 },
    Done,
}

struct Exploration {
    /// The un-searched link being driven and the node it leaves.
    link: u32,
    from: u32,
    rec: LinkRecorder,
    phase: Phase,
}

enum Phase {
    Departing {
        target: Point2,
    },
    Running,
    Approaching {
        centre: Point2,
        radius_m: f64,
        since_s: f64,
    },
    /// At a dead end's circumcentre: on towards the end wall until the tilted laser has seen
    /// all the floor before it (a rising floor seen by the horizontal laser looks like a
    /// dead end from afar).
    ConfirmingDeadEnd {
        centre: Point2,
        radius_m: f64,
    },
    Crossing(Crossing),
    FreeSpace {
        entrance: u32,
        right_wall: bool,
        /// Driving straight on until a wall is met (then it is followed).
        seeking: bool,
        /// Times the robot came back past the entrance, and whether it is away from it now.
        passes: u32,
        away: bool,
        exit: ExitTracker,
        entered_driven_m: f64,
    },
}

/// What a step of the explorer comes to.
enum Step {
    Drive(Velocity),
    Stop(StopReason),
}

/// What the explorer records at each step, in its own estimate (the truth beside it is the
/// evaluation's, see [`super::build_btm_observed`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimatedSample {
    pub time_s: f64,
    pub estimated: Pose2,
    pub mode: RunMode,
    pub contact: bool,
}

/// The BTM-building robot as a controller on the host: it reads its laser, tilted laser,
/// attitude, odometry and bumper through a [`FleetIo`] and never sees the scene.
pub struct Explorer<'a> {
    cfg: &'a BuildConfig,
    spec: RobotSpec,
    /// The clock and the bumper at the last reading.
    now: f64,
    contact: bool,
    started: bool,
    /// Why the exploration ended, or what went wrong, once it has (until taken).
    finished: Option<Result<StopReason, BuildError>>,
    /// The exploration has ended: it commands nothing more.
    done: bool,
    loc: Localizer,
    map: MapWriter<'a>,
    /// The latest readings (their buffers reused from step to step).
    readings: CrawlerReadings,
    view: ScanView,
    hits: Vec<FloorHit>,
    state: State,
    trajectory: Vec<EstimatedSample>,
    driven_m: f64,
    step_m: f64,
    last_odometry_m: f64,
    inclination_rad: f64,
    node: u32,
    mode: RunMode,
    contact_steps: u32,
    /// Commands played before the next decision (recovery after contact, stall escapes).
    manoeuvre: std::collections::VecDeque<Velocity>,
    stall: StallWatch,
    /// Routes planned again from the nearest node since a node was last reached.
    replans: u32,
    /// Circumcentres that turned out to be plain passage.
    ignored: Vec<Point2>,
    /// Tilted-laser returns on the track over the last stretch driven (distance driven,
    /// forward distance, height), so that an observation starts with the level floor before
    /// the obstacle.
    recent_floor: std::collections::VecDeque<(f64, f64, f64)>,
}

impl<'a> Explorer<'a> {
    /// An explorer for a robot of `spec` that starts at `start` (the map's frame).
    pub fn new(
        spec: RobotSpec,
        cfg: &'a BuildConfig,
        start: Pose2,
        store: Option<&'a BtmStore>,
    ) -> Self {
        Self {
            cfg,
            spec,
            now: 0.0,
            contact: false,
            started: false,
            finished: None,
            done: false,
            loc: {
                // Odometry starts at the start pose.
                let loc = Localizer::new(
                    start,
                    start,
                    cfg.scan_matching,
                    cfg.keyframe_distance_m,
                    cfg.keyframe_angle_rad,
                );
                if cfg.scan_map { loc.with_map() } else { loc }
            },
            map: MapWriter::new(store),
            readings: CrawlerReadings::new(start),
            view: ScanView::default(),
            hits: Vec::new(),
            state: State::Done,
            trajectory: Vec::new(),
            driven_m: 0.0,
            step_m: 0.0,
            last_odometry_m: 0.0,
            inclination_rad: 0.0,
            node: 0,
            mode: RunMode::CentralRun,
            contact_steps: 0,
            manoeuvre: std::collections::VecDeque::new(),
            stall: StallWatch::new(start, 0.0, cfg.dt_s),
            replans: 0,
            ignored: Vec::new(),
            recent_floor: std::collections::VecDeque::new(),
        }
    }

    /// Where it believed it was at each step, with its run mode and bumper.
    pub fn trajectory(&self) -> &[EstimatedSample] {
        &self.trajectory
    }

    /// Its position estimate now.
    pub fn estimated_pose(&self) -> Pose2 {
        self.loc.pose()
    }

    /// Its last horizontal scan, in its frame.
    pub fn last_scan(&self) -> &ScanView {
        &self.view
    }

    /// The map so far.
    pub fn btm(&self) -> &Btm {
        &self.map.btm
    }

    pub fn into_btm(self) -> Btm {
        self.map.btm
    }

    /// Scans matched and rejected by the localizer.
    pub fn scan_matches(&self) -> (u64, u64) {
        (self.loc.matched, self.loc.rejected)
    }

    /// Why the exploration ended (explored, out of time) or what went wrong, once it has.
    pub fn take_finished(&mut self) -> Option<Result<StopReason, BuildError>> {
        self.finished.take()
    }

    /// One control step on `readings`, whatever produced them (the shared simulator, another
    /// simulator, a real robot): the velocity to drive, or `None` once the map is finished —
    /// then [`Explorer::take_finished`] says why (explored, out of time) or what went wrong.
    pub fn next_command(&mut self, readings: &CrawlerReadings) -> Option<Velocity> {
        if self.done {
            return None;
        }
        let result = self.control(readings);
        self.done = !matches!(result, Ok(Step::Drive(_)));
        match result {
            Ok(Step::Drive(command)) => Some(command),
            Ok(Step::Stop(stop)) => {
                self.finished = Some(Ok(stop));
                None
            }
            Err(e) => {
                self.finished = Some(Err(e));
                None
            }
        }
    }

    /// One step: sense, and unless the map is done or time is up, decide the command.
    fn control(&mut self, readings: &CrawlerReadings) -> Result<Step, BuildError> {
        self.sense(readings);
        if !std::mem::replace(&mut self.started, true) {
            self.start()?;
        }
        if matches!(self.state, State::Done) {
            return Ok(Step::Stop(StopReason::Explored));
        }
        if self.now >= self.cfg.max_time_s {
            return Ok(Step::Stop(StopReason::TimeLimit));
        }
        self.decide().map(Step::Drive)
    }

    // ----- sensing -------------------------------------------------------------------------

    fn crossing(&self) -> bool {
        matches!(
            &self.state,
            State::Explore(Exploration {
                phase: Phase::Crossing(_),
                ..
            })
        )
    }

    fn sense(&mut self, r: &CrawlerReadings) {
        self.now = r.time_s;
        self.contact = r.contact;
        self.view = ScanView::from_scan(&r.laser);
        self.hits = floor_hits(&self.spec.tilted_laser, &r.tilted);
        self.inclination_rad = r.attitude.inclination_rad();
        let half = self.spec.width_m / 2.0;
        let driven = self.driven_m;
        self.recent_floor.extend(
            self.hits
                .iter()
                .filter(|h| h.lateral_m.abs() <= half)
                .map(|h| (driven, h.forward_m, h.height_m)),
        );
        while self
            .recent_floor
            .front()
            .is_some_and(|r| r.0 < driven - RECENT_FLOOR_M)
        {
            self.recent_floor.pop_front();
        }
        let odometry = &r.odometry;
        self.step_m = odometry.distance_m - self.last_odometry_m;
        self.last_odometry_m = odometry.distance_m;
        self.driven_m += self.step_m;
        self.loc.predict(odometry.estimate);
        let on_obstacle = self.crossing() || self.inclination_rad >= self.cfg.level_attitude_rad;
        self.loc.correct(&self.view, on_obstacle);
        if self.contact {
            self.contact_steps += 1;
        } else {
            self.contact_steps = 0;
        }
        self.trajectory.push(EstimatedSample {
            time_s: self.now,
            estimated: self.loc.pose(),
            mode: self.mode,
            contact: self.contact,
        });
    }

    fn pose(&self) -> Pose2 {
        self.loc.pose()
    }

    fn world_points(&self) -> Vec<Point2> {
        let pose = self.pose();
        self.view.points.iter().map(|&p| pose.to_world(p)).collect()
    }

    fn gains(&self) -> Gains {
        Gains {
            speed_mps: self.cfg.approach_speed_mps.min(self.spec.max_linear_mps),
            turn_gain: self.cfg.turn_gain,
            turn_in_place_rad: self.cfg.turn_in_place_rad,
        }
    }

    /// L_l, L_r beside the robot (the length of its body).
    fn beside(&self) -> SideClearance {
        let h = self.spec.length_m / 2.0;
        self.view.side_clearance(-h, h)
    }

    fn sample(&self) -> LinkSample {
        LinkSample {
            driven_m: self.driven_m,
            position: self.pose().position(),
            width_m: self.beside().width_m().min(self.view.max_range_m),
            inclination_rad: self.inclination_rad,
        }
    }

    fn node_position(&self, id: u32) -> Point2 {
        self.map.node_position(id).unwrap_or_default()
    }

    // ----- start, branch choice, return ----------------------------------------------------

    fn start(&mut self) -> Result<(), BuildError> {
        let pose = self.pose();
        let here = pose.position();
        let start = self
            .map
            .add_node(here, kind::TERMINAL, Some(subtype::START), |_| {})?;
        self.node = start;
        let width = self.passage_width_m();
        let cfg = self.cfg;
        let triangles = divergence_triangles(
            &self.view.points,
            -cfg.band_far_m,
            cfg.band_far_m,
            width,
            cfg.obtuse_tolerance_rad,
        );
        let world = self.world_points();
        let back = pose.theta + PI;
        if let Some(t) = triangles
            .iter()
            .find(|t| t.circumcentre.distance(Point2::default()) < CANDIDATE_TRACK_M)
        {
            let centre = pose.to_world(t.circumcentre);
            let dirs = open_directions(
                &world,
                centre,
                t.circumradius_m + cfg.search_margin_m,
                width,
            );
            if let Some(sub) = divergence_subtype(&dirs, STRAIGHT_TOLERANCE_RAD) {
                let node = self
                    .map
                    .add_node(centre, kind::DIVERGENCE, Some(sub), |_| {})?;
                let link = self.map.add_unsearched(start, here.bearing_to(centre))?;
                let measures = LinkMeasures {
                    length_m: here.distance(centre),
                    min_width_m: Some(self.beside().width_m()),
                    max_inclination_rad: Some(self.inclination_rad),
                    path: vec![here, centre],
                };
                self.map.close_link(link, node, measures)?;
                for d in dirs {
                    if self.link_is_open(&world, centre, d) {
                        self.map.add_unsearched(node, d)?;
                    }
                }
                self.node = node;
                return self.continue_from(node, back);
            }
        }
        let mut dirs = open_directions(&world, here, cfg.band_far_m / 2.0, width);
        dirs.retain(|&d| self.link_is_open(&world, here, d));
        if dirs.is_empty() {
            dirs.push(pose.theta.rem_euclid(TAU));
        }
        for d in dirs {
            self.map.add_unsearched(start, d)?;
        }
        self.continue_from(start, back)
    }

    /// At `node`, arrived from direction `entry_rad` (pointing from the node back along the
    /// link arrived by): takes the first un-searched link counter-clockwise from it, or
    /// drives back towards the nearest node that has one.
    fn continue_from(&mut self, node: u32, entry_rad: f64) -> Result<(), BuildError> {
        self.node = node;
        self.replans = 0;
        let next = open_links(&self.map.btm, node)
            .map(|l| {
                let mut turn = (l.direction_rad - entry_rad).rem_euclid(TAU);
                if turn < 1e-6 {
                    turn = TAU;
                }
                (turn, l.id, l.direction_rad)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        match next {
            Some((_, link, direction)) => {
                let target = self
                    .node_position(node)
                    .offset(direction, self.cfg.branch_target_m);
                self.state = State::Explore(Exploration {
                    link,
                    from: node,
                    rec: LinkRecorder::default(),
                    phase: Phase::Departing { target },
                });
                Ok(())
            }
            None => self.plan_return(node),
        }
    }

    fn finish(&mut self) -> Result<(), BuildError> {
        let here = self.pose().position();
        let from = self.node_position(self.node);
        let end = self
            .map
            .add_node(here, kind::TERMINAL, Some(subtype::END), |_| {})?;
        let link = self.map.add_unsearched(self.node, from.bearing_to(here))?;
        let measures = LinkMeasures {
            length_m: from.distance(here),
            min_width_m: Some(self.beside().width_m()),
            max_inclination_rad: Some(self.inclination_rad),
            path: vec![from, here],
        };
        self.map.close_link(link, end, measures)?;
        self.node = end;
        self.state = State::Done;
        Ok(())
    }

    // ----- the control step ----------------------------------------------------------------

    fn decide(&mut self) -> Result<Velocity, BuildError> {
        if let Some(v) = self.manoeuvre.pop_front() {
            return Ok(v);
        }
        if self.contact_steps >= STUCK_STEPS && !self.crossing() {
            self.contact_steps = 0;
            let back = Velocity {
                linear_mps: -BACKOFF_SPEED_MPS,
                angular_radps: 0.0,
            };
            self.manoeuvre.extend([back; RECOVERY_STEPS as usize]);
            return Ok(self.manoeuvre.pop_front().unwrap_or_default());
        }
        let target = match &self.state {
            State::Explore(ex) => Some(Target::Link(ex.link)),
            State::Return(route) => Some(Target::Node(route.goal)),
            State::Backoff { .. } => Some(Target::Backoff),
            State::Done => None,
        };
        match self.stall.check(self.pose(), self.now, target) {
            Some(Remedy::Escape(commands)) => {
                self.manoeuvre.extend(commands);
                return Ok(self.manoeuvre.pop_front().unwrap_or_default());
            }
            Some(Remedy::GiveUp(target)) => {
                self.give_up(target)?;
                return Ok(Velocity::default());
            }
            None => {}
        }
        let state = std::mem::replace(&mut self.state, State::Done);
        let command = match state {
            State::Done => Velocity::default(),
            State::Backoff { until_driven_m } => {
                if self.driven_m >= until_driven_m {
                    self.plan_return(self.node)?;
                    Velocity::default()
                } else {
                    self.state = State::Backoff { until_driven_m };
                    Velocity {
                        linear_mps: -BACKOFF_SPEED_MPS,
                        angular_radps: 0.0,
                    }
                }
            }
            State::Return(route) => self.follow_route(route)?,
            State::Explore(ex) => self.explore(ex)?,
        };
        Ok(self.safe(command))
    }

    /// Stops forward motion just short of a wall ahead (not on obstacles, whose rising floor
    /// the horizontal laser sees as a wall). A robot stopped by a wall to one side of its axis
    /// (it entered a narrow passage at an angle) and not told to turn turns away from it, so
    /// that it lines up with the passage instead of standing still.
    fn safe(&self, mut v: Velocity) -> Velocity {
        if v.linear_mps <= 0.0
            || self.crossing()
            || self.inclination_rad >= self.cfg.level_attitude_rad
        {
            return v;
        }
        let Some(p) = self.view.nearest_ahead(self.spec.width_m / 2.0) else {
            return v;
        };
        if p.x < self.spec.length_m / 2.0 + 0.05 {
            v.linear_mps = 0.0;
            if v.angular_radps.abs() < MIN_ALIGN_TURN_RADPS && p.y.abs() > ALIGN_OFF_AXIS_M {
                v.angular_radps = -MIN_ALIGN_TURN_RADPS.copysign(p.y);
            }
        }
        v
    }

    fn explore(&mut self, mut ex: Exploration) -> Result<Velocity, BuildError> {
        ex.rec.push(self.sample());
        let phase = std::mem::replace(&mut ex.phase, Phase::Running);
        match phase {
            Phase::Departing { target } => {
                if let Some(c) = self.detect_obstacle() {
                    return self.cross(ex, c);
                }
                let pose = self.pose();
                let from = self.node_position(ex.from);
                if pose.position().distance(target) < 0.3
                    || pose.position().distance(from) > self.cfg.branch_target_m
                {
                    return self.run_passage(ex);
                }
                self.mode = RunMode::BranchSelection;
                ex.phase = Phase::Departing { target };
                let v = target_approach(pose.to_body(target), self.gains());
                self.state = State::Explore(ex);
                Ok(v)
            }
            Phase::Running => self.run_passage(ex),
            Phase::Approaching {
                centre,
                radius_m,
                since_s,
            } => self.approach(ex, centre, radius_m, since_s),
            Phase::ConfirmingDeadEnd { centre, radius_m } => {
                self.confirm_dead_end(ex, centre, radius_m)
            }
            Phase::Crossing(c) => self.cross(ex, c),
            Phase::FreeSpace {
                entrance,
                right_wall,
                seeking,
                passes,
                away,
                exit,
                entered_driven_m,
            } => {
                let walk = FreeSpaceWalk {
                    entrance,
                    right_wall,
                    seeking,
                    passes,
                    away,
                    entered_driven_m,
                };
                self.free_space(ex, walk, exit)
            }
        }
    }

    /// Whether the gap in `direction_rad` from `centre` is a link: a lane a little wider than
    /// the robot runs free through it for [`BuildConfig::link_min_open_m`] (always, when that
    /// is 0 as in the paper).
    fn link_is_open(&self, world: &[Point2], centre: Point2, direction_rad: f64) -> bool {
        let need = self.cfg.link_min_open_m;
        need <= 0.0
            || lane_open_m(
                world,
                centre,
                direction_rad,
                self.spec.width_m / 2.0 + LINK_LANE_MARGIN_M,
                need,
            ) >= need
    }

    /// The narrowest gap taken for a passage: the robot's width plus the configured margin.
    fn passage_width_m(&self) -> f64 {
        self.spec.width_m + self.cfg.passage_margin_m
    }

    fn candidate(&self, from: Point2) -> Option<(Point2, f64)> {
        let pose = self.pose();
        let cfg = self.cfg;
        divergence_triangles(
            &self.view.points,
            cfg.band_near_m,
            cfg.band_far_m,
            self.passage_width_m(),
            cfg.obtuse_tolerance_rad,
        )
        .into_iter()
        .find_map(|t| {
            let c = t.circumcentre;
            let world = pose.to_world(c);
            let distance = c.distance(Point2::default());
            let bearing = c.y.atan2(c.x);
            let visible = self.view.min_range_near(bearing, 1f64.to_radians()) >= distance - 0.3;
            // On a real floor: only a circumcentre the robot can drive straight to without
            // brushing anything (not the middle of a table between its legs).
            let reachable = cfg.link_min_open_m <= 0.0
                || lane_length(
                    &self.view,
                    bearing,
                    self.spec.width_m / 2.0 + LINK_LANE_MARGIN_M,
                ) >= distance;
            let known = world.distance(from) < cfg.node_exclusion_m
                || self
                    .ignored
                    .iter()
                    .any(|p| p.distance(world) < CANDIDATE_TRACK_M);
            (visible && reachable && !known).then_some((world, t.circumradius_m))
        })
    }

    fn run_passage(&mut self, mut ex: Exploration) -> Result<Velocity, BuildError> {
        if let Some(c) = self.detect_obstacle() {
            return self.cross(ex, c);
        }
        let cfg = self.cfg;
        let strip = self
            .view
            .side_clearance(-cfg.free_space_strip_half_m, cfg.free_space_strip_half_m);
        if is_free_space(strip, cfg.free_space_clearance_m) {
            return self.enter_free_space(ex);
        }
        let from = self.node_position(ex.from);
        let candidate = self.candidate(from);
        let clearance = self.view.side_clearance(0.0, cfg.run_strip_m);
        let mode = select_run_mode(&ModeInputs {
            crossing_obstacle: false,
            in_free_space: false,
            has_candidate: candidate.is_some(),
            clearance,
            robot_width_m: self.spec.width_m,
        });
        self.mode = mode;
        match (mode, candidate) {
            (RunMode::BranchSelection, Some((centre, radius_m))) => {
                let since_s = self.now;
                self.approach(ex, centre, radius_m, since_s)
            }
            (RunMode::DeadEndRun, _) => {
                // A dead end no triangle showed: classify where the robot stands.
                let here = self.pose().position();
                let ahead = self
                    .pose()
                    .to_world(Point2::new(cfg.run_strip_m / 2.0, 0.0));
                if self.arrive(&mut ex, ahead, self.spec.width_m)? {
                    return Ok(Velocity::default());
                }
                self.ignored.push(here);
                self.state = State::Explore(ex);
                Ok(dead_end_turn(self.gains()))
            }
            _ => {
                let v = central_run(clearance, cfg.look_ahead_m, self.gains());
                self.state = State::Explore(ex);
                Ok(v)
            }
        }
    }

    fn approach(
        &mut self,
        mut ex: Exploration,
        mut centre: Point2,
        mut radius_m: f64,
        since_s: f64,
    ) -> Result<Velocity, BuildError> {
        if let Some(c) = self.detect_obstacle() {
            return self.cross(ex, c);
        }
        self.mode = RunMode::BranchSelection;
        let from = self.node_position(ex.from);
        if let Some((c, r)) = self.candidate(from)
            && c.distance(centre) < CANDIDATE_TRACK_M
        {
            centre = c;
            radius_m = r;
        }
        let pose = self.pose();
        let distance = pose.position().distance(centre);
        let patience_over = self.now - since_s > APPROACH_PATIENCE_S;
        if distance < self.cfg.arrival_radius_m || (patience_over && distance < 2.0 * radius_m) {
            if self.is_dead_end(centre, radius_m) && !self.floor_seen_to_front_wall() {
                ex.phase = Phase::ConfirmingDeadEnd { centre, radius_m };
                self.state = State::Explore(ex);
                return Ok(Velocity::default());
            }
            if self.arrive(&mut ex, centre, radius_m)? {
                return Ok(Velocity::default());
            }
            self.state = State::Explore(ex);
            return Ok(Velocity::default());
        }
        let body = pose.to_body(centre);
        if (body.x < -0.5 && distance > CANDIDATE_TRACK_M) || patience_over {
            // Lost it: back to the passage.
            self.ignored.push(centre);
            self.state = State::Explore(ex);
            return Ok(Velocity::default());
        }
        ex.phase = Phase::Approaching {
            centre,
            radius_m,
            since_s,
        };
        let v = target_approach(body, self.gains());
        self.state = State::Explore(ex);
        Ok(v)
    }

    fn is_dead_end(&self, centre: Point2, radius_m: f64) -> bool {
        let dirs = open_directions(
            &self.world_points(),
            centre,
            radius_m + self.cfg.search_margin_m,
            self.passage_width_m(),
        );
        divergence_subtype(&dirs, STRAIGHT_TOLERANCE_RAD) == Some(subtype::DEAD_END)
    }

    /// Whether the wall ahead is within the tilted laser's reach on level floor, so that any
    /// obstacle before it would have been seen.
    fn floor_seen_to_front_wall(&self) -> bool {
        let t = &self.spec.tilted_laser;
        let reach = t.flat_floor_range_m() * t.tilt_from_vertical_rad.sin();
        self.view.front_clearance(self.spec.width_m / 2.0) <= reach - DEAD_END_MARGIN_M
    }

    fn confirm_dead_end(
        &mut self,
        mut ex: Exploration,
        centre: Point2,
        radius_m: f64,
    ) -> Result<Velocity, BuildError> {
        if let Some(c) = self.detect_obstacle() {
            return self.cross(ex, c);
        }
        self.mode = RunMode::BranchSelection;
        if self.floor_seen_to_front_wall() || self.contact_steps > 0 {
            if !self.arrive(&mut ex, centre, radius_m)? {
                self.state = State::Explore(ex);
            }
            return Ok(Velocity::default());
        }
        let clearance = self.view.side_clearance(0.0, self.cfg.run_strip_m);
        let mut gains = self.gains();
        gains.speed_mps *= self.cfg.obstacle_speed_factor;
        let v = central_run(clearance, self.cfg.look_ahead_m, gains);
        ex.phase = Phase::ConfirmingDeadEnd { centre, radius_m };
        self.state = State::Explore(ex);
        Ok(v)
    }

    /// At a circumcentre: classifies it by its open directions and makes (or closes a loop
    /// onto) a divergence node. Returns whether a node was reached; if not, the exploration
    /// goes on in `ex` (a plain passage).
    fn arrive(
        &mut self,
        ex: &mut Exploration,
        centre: Point2,
        radius_m: f64,
    ) -> Result<bool, BuildError> {
        let width = self.passage_width_m();
        let world = self.world_points();
        let dirs = open_directions(&world, centre, radius_m + self.cfg.search_margin_m, width);
        let Some(sub) = divergence_subtype(&dirs, STRAIGHT_TOLERANCE_RAD) else {
            self.ignored.push(centre);
            ex.phase = Phase::Running;
            return Ok(false);
        };
        let back_point = ex
            .rec
            .position_at(self.driven_m - ENTRY_LOOKBACK_M)
            .unwrap_or_else(|| self.node_position(ex.from));
        let from = self.node_position(ex.from);
        let known = self
            .map
            .btm
            .nodes
            .iter()
            .filter(|n| n.id != ex.from && n.kind == kind::DIVERGENCE)
            .map(|n| (Point2::new(n.x_m, n.y_m).distance(centre), n.id))
            .filter(|(d, _)| *d < self.cfg.merge_radius_m)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, node)) = known {
            let at = self.node_position(node);
            let back = at.bearing_to(back_point);
            self.map
                .close_link(ex.link, node, ex.rec.measures(from, at))?;
            let stub = open_links(&self.map.btm, node)
                .map(|l| (normalize_angle(l.direction_rad - back).abs(), l.id))
                .filter(|(d, _)| *d < ENTRY_MATCH_RAD)
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((_, stub)) = stub {
                self.map.remove_unsearched(stub)?;
            }
            self.continue_from(node, back)?;
            return Ok(true);
        }
        let back = centre.bearing_to(back_point);
        let entry = dirs
            .iter()
            .enumerate()
            .map(|(i, d)| (normalize_angle(d - back).abs(), i))
            .filter(|(d, _)| *d < ENTRY_MATCH_RAD)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, i)| i);
        let node = self
            .map
            .add_node(centre, kind::DIVERGENCE, Some(sub), |_| {})?;
        self.map
            .close_link(ex.link, node, ex.rec.measures(from, centre))?;
        for (i, d) in dirs.iter().enumerate() {
            if Some(i) != entry && self.link_is_open(&world, centre, *d) {
                self.map.add_unsearched(node, *d)?;
            }
        }
        self.continue_from(node, back)?;
        Ok(true)
    }
}

/// What the crawler's sensors give the builder at one control step.
#[derive(Clone, Debug)]
pub struct CrawlerReadings {
    pub time_s: f64,
    /// The bumper: its last motion was stopped by something.
    pub contact: bool,
    /// The horizontal 2-D laser.
    pub laser: LaserScan,
    /// The laser tilted down at the floor ahead.
    pub tilted: TiltedScan,
    pub attitude: Attitude,
    /// Dead reckoning from the tracks (its estimate starts at the start pose).
    pub odometry: Odometry,
}

impl CrawlerReadings {
    /// Empty readings of a robot at `start`.
    pub fn new(start: Pose2) -> Self {
        Self {
            time_s: 0.0,
            contact: false,
            laser: LaserScan::default(),
            tilted: TiltedScan::default(),
            attitude: Attitude::default(),
            odometry: Odometry::new(start),
        }
    }

    /// The fleet's first robot's readings now, into these buffers.
    pub fn read(&mut self, io: &mut FleetIo<'_>) {
        self.time_s = io.time_s();
        self.contact = io.contact(0);
        io.laser(0, &mut self.laser);
        self.tilted = io.tilted_laser(0);
        self.attitude = io.attitude(0);
        self.odometry = io.odometry(0);
    }
}

/// On the host: the readings of the fleet's first robot in, its command out.
impl Controller for Explorer<'_> {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        if self.done {
            return;
        }
        let mut readings =
            std::mem::replace(&mut self.readings, CrawlerReadings::new(Pose2::default()));
        readings.read(io);
        if let Some(command) = self.next_command(&readings) {
            io.command(0, command);
        }
        self.readings = readings;
    }
}

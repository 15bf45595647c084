//! The team as a controller on the host: each step it reads its robots' sensors through a
//! [`FleetIo`] — laser scans every scan period, the thermal camera every thermal period, the
//! bumper and the motion achieved every step — merges their maps at the base station, runs the
//! allocation, and sets every robot's velocity. It never sees the scene: the semantic labels
//! of paper 002 come from the semantic map it is built with (the named semantic oracle, or its
//! own segmentation), and the robots' poses
//! through the localization oracle when the host has it on.

use super::*;
use crate::config::{Localization, Semantics};
use usar_map::localization::{Localizer, ScanView};
use usar_map::segmentation::SegmentationParams;
use usar_sim::host::{Controller, FleetIo};

/// Key scans of the localizer (the BTM builder's defaults; with a map to match against they
/// only pace its bookkeeping).
const KEYFRAME_DISTANCE_M: f64 = 1.0;
const KEYFRAME_ANGLE_RAD: f64 = std::f64::consts::PI;

pub(super) struct Agent {
    /// Where the controller believes the robot is, refreshed at every step.
    pub(super) pose: Pose2,
    /// Whether the robot still answers.
    pub(super) alive: bool,
    pub(super) map: OccupancyGrid,
    pub(super) scan: LaserScan,
    pub(super) follower: PathFollower,
    pub(super) target: Option<Cell>,
    /// Pose and time of the last progress check.
    pub(super) progress_mark: (Pose2, f64),
    /// Turning at the checks since the robot last moved [`Tuning::stuck_distance_m`], radians.
    pub(super) turned_in_place_rad: f64,
    pub(super) blacklist: Vec<(Cell, f64)>,
    pub(super) trajectory: Vec<Point2>,
    /// Path costs from the robot, reused between assignments (nearest-frontier strategy).
    pub(super) field: DistanceField,
    /// Recovery after bumps: the manoeuvre under way and the motions it may retrace.
    pub(super) recovery: Recovery,
    /// Recoveries since the current target was assigned.
    pub(super) recoveries: u32,
    /// Retracing its own trajectory out of a pocket the map no longer connects.
    pub(super) escaping: bool,
    /// Whether it may retrace when no candidate is reachable: once after each target, so that
    /// a robot with nothing left to do goes idle instead of pacing back and forth.
    pub(super) may_retrace: bool,
    /// Where it took its last scan.
    pub(super) last_scan: Option<Pose2>,
    /// Whether its link to the base station worked at the last exchange.
    pub(super) linked: bool,
    /// With a limited radio: the base station's copy of this robot's map as last received.
    pub(super) uploaded: Option<OccupancyGrid>,
    /// Without the localization oracle: odometry corrected by matching each scan against the
    /// robot's own map.
    localizer: Option<Localizer>,
}

impl Agent {
    /// A new target and the path to it: recoveries counted afresh, no escape under way, and
    /// one retrace allowed again when the robot later has nothing to do.
    pub(super) fn head_for(&mut self, target: Cell, waypoints: Vec<Point2>) {
        self.follower = PathFollower::new(waypoints);
        self.target = Some(target);
        self.recoveries = 0;
        self.escaping = false;
        self.may_retrace = true;
    }
}

/// A warm region with a human signature one of the team's robots saw: the team reports it, the
/// evaluator tells which victim (if any) it was.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VictimReport {
    pub reading: usar_sim::sensors::DetectionId,
    /// The team's robot that saw it.
    pub robot: usize,
    pub time_s: f64,
    /// Where the robot places it (its pose as it believes it, the reading's bearing and range),
    /// and the warm region's size.
    pub at: Point2,
    pub size_m2: f64,
}

/// A target the team gave a robot at an auction: the evaluator counts assignments per true
/// room label from them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Assignment {
    pub target: Cell,
}

/// Paper 002's team (or the nearest-frontier baseline) driving its fleet.
pub struct TeamController {
    pub(super) config: TeamConfig,
    pub(super) agents: Vec<Agent>,
    pub(super) base: BaseStation,
    /// The team's semantic map (paper 002 §4): rooms, labels, doors and visibility, from the
    /// semantic oracle or segmented from the team's own map.
    pub(super) semantic: SemanticMap,
    pub(super) measures: Measures,
    pub(super) sizer: TeamSizer,
    pub(super) planner: GridAStar,
    /// The current bidder's distance field on the bid grid: one buffer for every bidder, so
    /// that an auction keeps one field's memory in cache rather than one per robot.
    pub(super) bid_field: DistanceField,
    /// Per navigable grid: how many robot discs cover each cell during a nearest-frontier
    /// round (all zero between rounds; see `discs.rs`).
    pub(super) disc_cover: [Vec<u16>; 2],
    /// b(p, r) of the current bidder's paths, memoised along its distance field.
    pub(super) travel_times: TravelTimes,
    pub(super) strategy_rng: Pcg64Mcg,
    /// Auction assignments since the evaluator last took them.
    pub(super) assignments: Vec<Assignment>,
    /// Candidates a robot reached (auctions): not offered to anyone for a while.
    pub(super) visited: Vec<(Cell, f64)>,
    pub(super) allocations: Vec<crate::outcome::Allocation>,
    /// Per room: the last i(p) inferred, with the perceived label and known fraction it was
    /// inferred from.
    pub(super) team_sizes: Vec<Option<(Option<RoomLabel>, f64, usize)>>,
    /// Where and when robots reached their targets, waiting for a scan there to be merged.
    pub(super) arrivals: Vec<(Point2, f64)>,
    /// The clock at this step, and the length of a step.
    pub(super) now: f64,
    dt_s: f64,
    /// Steps seen (0 before the first).
    step: u64,
    /// Robots whose recovery ended at the last step: they need a target.
    pub(super) replan: Vec<usize>,
    pub(super) idle_since: Option<f64>,
    pub(super) explored: bool,
    /// Merges done so far (the evaluator follows the merged map's changes by it).
    merges: u64,
    /// With segmented semantics: the merge the rooms were last segmented after.
    segmented_after: Option<u64>,
    reports: Vec<VictimReport>,
}

impl TeamController {
    /// A team on `scene` for robots starting at `starts`: its configuration checked, its maps
    /// on the configured grid, its semantic knowledge from the source the configuration names
    /// (the scene's room layer only through the semantic oracle).
    pub fn on_scene(
        scene: &Scene,
        config: TeamConfig,
        starts: &[Pose2],
        seed: u64,
    ) -> Result<Self, MissionError> {
        let measures = config.check(scene.geometry().resolution_m)?;
        if starts.len() != config.robots {
            return Err(super::check::invalid(
                "start poses",
                starts.len(),
                format!("one per robot of the team, {}", config.robots),
            ));
        }
        let geometry = map_geometry(scene, config.map_resolution_m);
        let label_rng = Pcg64Mcg::seed_from_u64(derive_seed(seed, SEMANTIC_STREAM));
        let x = &config.exploration;
        let semantic = match config.semantics {
            // The named semantic oracle: the scene's room layer.
            Semantics::Oracle => {
                SemanticMap::new(scene, &geometry, &x.hypothesis, x.label_errors, label_rng)
            }
            Semantics::Segmented => {
                SemanticMap::segmented(&geometry, &x.hypothesis, x.label_errors, label_rng)
            }
        };
        Ok(Self::new(
            config, starts, geometry, semantic, measures, seed,
        ))
    }

    /// A team for robots starting at `starts`, its maps on `geometry`, its semantic map
    /// `semantic`, its random choices drawn from streams of `seed`.
    fn new(
        config: TeamConfig,
        starts: &[Pose2],
        geometry: GridGeometry,
        semantic: SemanticMap,
        measures: Measures,
        seed: u64,
    ) -> Self {
        let params = OccupancyParams::default();
        let dt_s = config.sim.dt_s;
        let agents = starts
            .iter()
            .map(|&pose| Agent {
                pose,
                alive: true,
                map: OccupancyGrid::new(geometry, params),
                scan: LaserScan::default(),
                follower: PathFollower::default(),
                target: None,
                progress_mark: (pose, 0.0),
                turned_in_place_rad: 0.0,
                blacklist: Vec::new(),
                trajectory: vec![pose.position()],
                field: DistanceField::new(),
                recovery: Recovery::for_robot(&config.robot),
                recoveries: 0,
                escaping: false,
                may_retrace: true,
                last_scan: None,
                linked: true,
                uploaded: (config.radio != crate::config::Radio::default())
                    .then(|| OccupancyGrid::new(geometry, params)),
                localizer: (config.localization == Localization::Estimated).then(|| {
                    // Paper 002 §3.1: "a new acquired scan is aligned with the current map
                    // (using odometry as initial guess)". The robot knows where it started.
                    Localizer::new(pose, pose, true, KEYFRAME_DISTANCE_M, KEYFRAME_ANGLE_RAD)
                        .with_map()
                }),
            })
            .collect();
        // Occupied cells stand for walls whose faces are half a cell nearer than their centres.
        let half_cell = geometry.resolution_m / 2.0;
        let tight = config.robot.width_m / 2.0 + config.tuning.tight_margin_m + half_cell;
        let base = BaseStation::new(
            geometry,
            params,
            config.robot.circumscribed_radius_m() + half_cell,
            tight,
            config.exploration.bid_grid_factor,
        );
        let team_sizes = vec![None; semantic.rooms().len()];
        Self {
            sizer: TeamSizer::new(config.exploration.max_robots_per_candidate),
            config,
            agents,
            base,
            semantic,
            measures,
            planner: GridAStar::new(),
            bid_field: DistanceField::new(),
            disc_cover: Default::default(),
            travel_times: TravelTimes::new(),
            strategy_rng: Pcg64Mcg::seed_from_u64(derive_seed(seed, STRATEGY_STREAM)),
            assignments: Vec::new(),
            visited: Vec::new(),
            allocations: Vec::new(),
            team_sizes,
            arrivals: Vec::new(),
            now: 0.0,
            dt_s,
            step: 0,
            replan: Vec::new(),
            idle_since: None,
            explored: false,
            merges: 0,
            segmented_after: None,
            reports: Vec::new(),
        }
    }

    pub fn base_station(&self) -> &BaseStation {
        &self.base
    }

    /// Keeps the team's planners off the segment `a`–`b` widened by `radius_m` (a slope or
    /// stairs its robots cannot take, reported by another robot).
    pub fn keep_out(&mut self, a: Point2, b: Point2, radius_m: f64) {
        self.base.keep_out(a, b, radius_m);
    }

    /// Where robot `robot` believes it is (its true pose under the localization oracle).
    pub fn pose(&self, robot: usize) -> Option<Pose2> {
        self.agents.get(robot).map(|a| a.pose)
    }

    /// The last scan robot `robot` took (in its own frame, stamped with the pose it believed),
    /// if it has taken one.
    pub fn last_scan(&self, robot: usize) -> Option<&LaserScan> {
        let a = self.agents.get(robot)?;
        a.last_scan.map(|_| &a.scan)
    }

    /// Robot `robot`'s goal: the end of the path it follows.
    pub fn robot_goal(&self, robot: usize) -> Option<Point2> {
        self.agents.get(robot).and_then(|a| a.follower.goal())
    }

    /// Whether robot `robot` is backing out of a contact (a recovery manoeuvre).
    pub fn is_recovering(&self, robot: usize) -> bool {
        self.agents
            .get(robot)
            .is_some_and(|a| a.recovery.is_active())
    }

    /// Replaces the relevance hypothesis of the auctions (paper 002 §4.1) while the team runs
    /// (an operator changing it at the console); the evaluation's relevant area keeps the
    /// hypothesis the mission started with.
    pub fn set_hypothesis(&mut self, hypothesis: crate::criteria::Hypothesis) {
        self.config.exploration.hypothesis = hypothesis;
    }

    /// The semantic map the team bids with (the oracle's or its own segmentation).
    pub fn semantic_map(&self) -> &SemanticMap {
        &self.semantic
    }

    /// Each robot's trajectory (its believed position once per simulated second).
    pub fn trajectories(&self) -> Vec<&[Point2]> {
        self.agents
            .iter()
            .map(|a| a.trajectory.as_slice())
            .collect()
    }

    /// Whether the team believes the floor explored: nobody has had anything to do for
    /// [`Tuning::explored_after_s`].
    pub fn explored(&self) -> bool {
        self.explored
    }

    /// How many times the base station has merged the robots' maps.
    pub fn merges(&self) -> u64 {
        self.merges
    }

    /// With segmented semantics, segments the merged map again when it changed since the
    /// last time (the i(p) inferred per room start afresh with the new rooms).
    pub(super) fn refresh_semantics(&mut self) {
        if self.config.semantics != Semantics::Segmented
            || self.segmented_after == Some(self.merges)
        {
            return;
        }
        self.segmented_after = Some(self.merges);
        self.semantic.resegment(
            &self.base.merged,
            &self.config.exploration.hypothesis,
            &SegmentationParams::default(),
        );
        self.team_sizes = vec![None; self.semantic.rooms().len()];
    }

    /// The auction assignments since the last call.
    pub fn take_assignments(&mut self) -> Vec<Assignment> {
        std::mem::take(&mut self.assignments)
    }

    /// The victim reports since the last call.
    pub fn take_reports(&mut self) -> Vec<VictimReport> {
        std::mem::take(&mut self.reports)
    }

    fn every(&self, period_s: f64) -> bool {
        every(period_s, self.dt_s, self.step)
    }

    /// Reads where every robot is and whether it answers: the true pose under the localization
    /// oracle.
    fn refresh(&mut self, io: &FleetIo<'_>) {
        self.now = io.time_s();
        self.dt_s = io.dt_s();
        for (k, a) in self.agents.iter_mut().enumerate() {
            let alive = io.alive(k);
            if a.alive && !alive {
                // It failed: nothing more is asked of it.
                a.target = None;
                a.follower = PathFollower::default();
                a.escaping = false;
                a.recovery.stop();
            }
            a.alive = alive;
            // Without the oracle the localizer carries the estimate between scans: odometry's
            // motion since the last step on top of the last corrected pose.
            a.pose = match (io.true_pose(k), &mut a.localizer) {
                (Some(truth), _) => truth,
                (None, Some(loc)) => {
                    loc.predict(io.odometry(k).estimate);
                    loc.pose()
                }
                (None, None) => io.odometry(k).estimate,
            };
        }
    }

    fn scan_all(&mut self, io: &mut FleetIo<'_>) {
        let (min_move, min_turn) = (self.config.rescan_distance_m, self.config.rescan_turn_rad);
        for (k, a) in self.agents.iter_mut().enumerate() {
            if !a.alive {
                continue;
            }
            if let Some(last) = a.last_scan
                && last.position().distance(a.pose.position()) < min_move
                && normalize_angle(last.theta - a.pose.theta).abs() < min_turn
            {
                continue;
            }
            a.last_scan = Some(a.pose);
            io.laser(k, &mut a.scan);
            if let Some(loc) = &mut a.localizer {
                // Team robots drive on level floors: no scan is taken on an obstacle.
                loc.correct(&ScanView::from_scan(&a.scan), false);
                a.pose = loc.pose();
                a.scan.pose = a.pose;
            }
            a.map.integrate_scan(&a.scan);
        }
    }

    /// Merges what reached the base station. With a limited radio the base station merges the
    /// copies it last received (a merge recomputes a tile from every map given, so an unheard
    /// robot's copy stands in for it).
    pub(super) fn merge(&mut self, io: &mut FleetIo<'_>) {
        for (k, a) in self.agents.iter_mut().enumerate() {
            let link = io.link_to_base(k);
            a.linked = a.alive && link;
        }
        let mut scratch = Vec::new();
        for a in &mut self.agents {
            if let (true, Some(copy)) = (a.linked, a.uploaded.as_mut()) {
                copy.merge_from(&mut [&mut a.map]);
                copy.drain_changed(&mut scratch);
                scratch.clear();
            }
            // Nothing reads a robot's own class-change log: emptied here, it stays small
            // instead of growing with every scan of the mission.
            a.map.drain_changed(&mut scratch);
            scratch.clear();
        }
        let mut maps: Vec<&mut OccupancyGrid> = self
            .agents
            .iter_mut()
            .map(|a| a.uploaded.as_mut().unwrap_or(&mut a.map))
            .collect();
        self.base.merge(&mut maps);
        self.semantic
            .update_from(&self.base.merged, self.base.last_changes());
        self.merges += 1;
        // Arrivals whose scan on the spot is in the merged map now.
        let settled = self.now - self.config.timing.scan_period_s;
        let g = *self.base.merged.geometry();
        let radius = (self.config.tuning.unobservable_radius_m / g.resolution_m).round() as i32;
        for &(p, _) in self.arrivals.iter().filter(|&&(_, t)| t <= settled) {
            self.base.frontiers.retire_near(g.world_to_cell(p), radius);
        }
        self.arrivals.retain(|&(_, t)| t > settled);
    }

    fn read_thermal(&mut self, io: &mut FleetIo<'_>) {
        for (k, a) in self.agents.iter().enumerate() {
            if !a.alive {
                continue;
            }
            for d in io.thermal(k) {
                if d.human_signature {
                    self.reports.push(VictimReport {
                        reading: d.id,
                        robot: k,
                        time_s: self.now,
                        at: a
                            .pose
                            .position()
                            .offset(a.pose.theta + d.bearing_rad, d.range_m),
                        size_m2: d.size_m2,
                    });
                }
            }
        }
    }

    /// The first step: every robot scans, the maps are merged, the first targets assigned.
    fn start(&mut self, io: &mut FleetIo<'_>) {
        self.scan_all(io);
        self.merge(io);
        self.read_thermal(io);
        let everyone: Vec<usize> = (0..self.agents.len()).collect();
        // Nothing assigned yet ends the mission only by the idle rule: the robots' first
        // targets may have no path on the map (the coarser bid grid joins more), and the next
        // auction offers them others.
        self.assign(&everyone);
    }

    /// What the last step brought: scans, heat, a merge and new targets when due.
    fn sense_and_plan(&mut self, io: &mut FleetIo<'_>) {
        let dt_s = io.dt_s();
        for (k, a) in self.agents.iter_mut().enumerate() {
            a.recovery.record(io.achieved(k), dt_s);
        }
        if self.every(self.config.timing.scan_period_s) {
            self.scan_all(io);
        }
        if self.every(self.config.timing.thermal_period_s) {
            self.read_thermal(io);
        }
        let merged_now = self.every(self.config.timing.merge_period_s);
        if merged_now {
            self.merge(io);
        }
        if self.every(1.0) {
            for a in &mut self.agents {
                a.trajectory.push(a.pose.position());
            }
        }
        let mut who = self.needing_targets(merged_now);
        if self.every(self.config.timing.assignment_period_s) {
            who = (0..self.agents.len()).collect();
        }
        if !who.is_empty() {
            self.assign(&who);
        }
        self.check_explored();
    }

    /// The last merge of a mission that ends.
    pub(super) fn finish(&mut self, io: &mut FleetIo<'_>) {
        self.refresh(io);
        self.merge(io);
    }
}

impl Controller for TeamController {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        self.refresh(io);
        if self.step == 0 {
            self.start(io);
        } else {
            self.sense_and_plan(io);
        }
        self.step += 1;
        self.drive(io);
    }
}

/// The last merge as a controller step (no commands).
pub(super) struct Finishing<'a>(pub(super) &'a mut TeamController);

impl Controller for Finishing<'_> {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        self.0.finish(io);
    }
}

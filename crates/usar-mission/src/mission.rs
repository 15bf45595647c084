//! A mission on its host: set up (the file's values checked, the scene given room for every
//! robot, the team and the crawler placed with their own oracles), stepped (every controller
//! decides, the evaluation follows, the world moves) and summed up.

use crate::board::VictimBoard;
use crate::controllers::{SharingCrawler, TeamWithBtm};
use crate::live::{LiveMission, MissionHook, Operator, Unwatched};
use crate::outcome::{CrawlerFigures, MissionOutcome, MissionSample, TeamFigures};
use crate::rescuer::Rescuer;
use crate::{CrawlerPart, MissionConfig, MissionError};
use std::sync::Arc;
use usar_btm::build::{BuildConfig, BuildError, Explorer, count_nodes};
use usar_btm::plan::RobotLimits;
use usar_btm::store::BtmStore;
use usar_map::segmentation::SegmentationParams;
use usar_rescue::controller::Question;
use usar_rescue::desk::OperatorDesk;
use usar_rescue::operator::{SimulatedOperator, VictimDecision};
use usar_sim::host::{FleetId, Host, Oracles, RadioSpec};
use usar_sim::{RobotSpec, SimConfig};
use usar_team::setup::TeamSetup;
use usar_team::{Radio, TeamConfig, TeamController, TeamEvaluation};
use usar_world::cellview::{CellView, CellViewParams};
use usar_world::{Point2, Scene};

/// How often the mission's coverage and relevant area are sampled, seconds.
const SAMPLE_PERIOD_S: f64 = 10.0;

fn bad(field: &str, message: impl Into<String>) -> MissionError {
    MissionError::Config {
        field: field.into(),
        message: message.into(),
    }
}

/// The crawler on the host, and the largest error of its position estimate so far.
pub(crate) struct Crawler<'a> {
    pub(crate) fleet: FleetId,
    pub(crate) controller: SharingCrawler<'a>,
    pub(crate) max_error_m: f64,
}

/// A mission being run.
pub(crate) struct Mission<'a> {
    pub(crate) scene: Arc<Scene>,
    pub(crate) seed: u64,
    pub(crate) steps: u64,
    pub(crate) sample_every: u64,
    pub(crate) host: Host,
    pub(crate) team_fleet: FleetId,
    pub(crate) team: TeamWithBtm,
    pub(crate) eval: TeamEvaluation,
    pub(crate) crawler: Option<Crawler<'a>>,
    pub(crate) rescuer: Option<Rescuer>,
    /// The one operator, and the base station's board of the team's victim reports.
    pub(crate) desk: OperatorDesk,
    pub(crate) board: VictimBoard,
    pub(crate) series: Vec<MissionSample>,
}

/// The team's configuration from the mission file's `[team]` names.
fn team_config(config: &MissionConfig) -> Result<TeamConfig, MissionError> {
    if !(config.minutes.is_finite() && config.minutes > 0.0 && config.minutes <= 24.0 * 60.0) {
        return Err(bad(
            "minutes",
            format!("found {}, expected (0, 1440]", config.minutes),
        ));
    }
    let t = &config.team;
    if t.robots == 0 {
        return Err(bad("team.robots", "found 0, expected at least 1"));
    }
    let setup = TeamSetup {
        robots: t.robots,
        robot: &t.robot,
        strategy: &t.strategy,
        coordination: &t.coordination,
        hypothesis: &t.hypothesis,
        minutes: config.minutes,
        label_errors: &t.label_errors,
        candidates: &t.candidates,
        semantics: &t.semantics,
        localization: &t.localization,
        stop_at_relevant: None,
        merge_period_s: 2.5,
        radio: Radio::default(),
        failures: Vec::new(),
    };
    let mut team = setup.config()?;
    team.sim.robots_in_lasers = config.robots_in_lasers;
    Ok(team)
}

/// The crawler's robot and builder parameters (its step the mission's, its time limit at least
/// the mission's), when the mission has one.
fn crawler_part(
    part: &CrawlerPart,
    minutes: f64,
    dt_s: f64,
) -> Result<Option<(RobotSpec, BuildConfig, f64)>, MissionError> {
    if !part.enabled {
        return Ok(None);
    }
    if !(part.share_period_s.is_finite() && part.share_period_s > 0.0) {
        return Err(bad(
            "crawler.share_period_s",
            format!("found {}, expected a positive number", part.share_period_s),
        ));
    }
    let mut build = part.build.clone();
    build.dt_s = dt_s;
    build.max_time_s = build.max_time_s.max(minutes * 60.0);
    build.validate().map_err(|e| match e {
        BuildError::Config { field, found } => bad(&format!("crawler.build.{field}"), found),
        other => other.into(),
    })?;
    Ok(Some((
        RobotSpec::load(&part.robot)?,
        build,
        part.share_period_s,
    )))
}

/// The largest rescuer zone side, cells (a 200 × 200-cell zone is 180 m across).
pub const MAX_ZONE_CELLS: u32 = 200;

impl MissionConfig {
    /// Checks every value the mission reads before anything is set up or trained (the scene
    /// is not read here): names, ranges, the robot presets or files.
    pub fn check(&self) -> Result<(), MissionError> {
        let team = team_config(self)?;
        crawler_part(&self.crawler, self.minutes, team.sim.dt_s)?;
        let r = &self.rescuer;
        if !r.enabled {
            return Ok(());
        }
        let rescuer = |field: &str, message: String| crate::rescuer::bad(field, message);
        RobotSpec::load(&r.robot)?;
        crate::rescuer::oracles(r)?;
        crate::rescuer::weights(r)?;
        if r.policy.is_empty() {
            usar_rescue::training::check_trials(r.train_trials)
                .map_err(|e| rescuer("train_trials", e.problem()))?;
        }
        if !(1..=MAX_ZONE_CELLS).contains(&r.zone_cells) {
            return Err(rescuer(
                "zone_cells",
                format!("found {}, expected 1 to {MAX_ZONE_CELLS}", r.zone_cells),
            ));
        }
        if r.max_primitives == 0 {
            return Err(rescuer(
                "max_primitives",
                "found 0, expected at least 1".into(),
            ));
        }
        crate::zone::ZoneAt::of(r)?;
        crate::zone::PutDown::of(r)?;
        Ok(())
    }
}

impl<'a> Mission<'a> {
    /// Sets `config` up on `scene` with the team's configuration `team_config`; the crawler
    /// (robot, builder parameters, share period — kept by the caller, as the crawler borrows
    /// them) writes its map to `store` when given.
    pub(crate) fn new(
        scene: Arc<Scene>,
        config: &MissionConfig,
        team_config: TeamConfig,
        seed: u64,
        crawler: Option<&'a (RobotSpec, BuildConfig, f64)>,
        store: Option<&'a BtmStore>,
        operator: Operator,
    ) -> Result<Self, MissionError> {
        // Room for every robot: a room layer for the team's evaluation, start poses for all,
        // spaced for the widest.
        let rescuer_part = config.rescuer.enabled.then_some(&config.rescuer);
        let robots = team_config.robots
            + usize::from(crawler.is_some())
            + usize::from(rescuer_part.is_some());
        let rescuer_spec = rescuer_part
            .map(|r| RobotSpec::load(&r.robot))
            .transpose()?;
        let widest = crawler
            .map_or(0.0, |(spec, _, _)| spec.circumscribed_radius_m())
            .max(team_config.robot.circumscribed_radius_m())
            .max(
                rescuer_spec
                    .as_ref()
                    .map_or(0.0, RobotSpec::circumscribed_radius_m),
            );
        let mut scene = (*scene).clone();
        usar_team::scene_prep::prepare_scene(
            &mut scene,
            robots,
            widest + 0.1,
            &SegmentationParams::default(),
        );
        if scene.start_poses.len() < robots {
            return Err(MissionError::NotEnoughRoom {
                available: scene.start_poses.len(),
                requested: robots,
            });
        }
        // The rescuer's zone (with its rubble, laid now: the world every robot meets).
        let rescuer_k = team_config.robots + usize::from(crawler.is_some());
        let placed = match (rescuer_part, &rescuer_spec) {
            (Some(part), Some(spec)) => {
                let view = CellView::from_scene(&scene, &CellViewParams::default());
                let start = scene.start_poses[rescuer_k];
                Some(crate::zone::place(
                    &mut scene, &view, part, spec, start, seed,
                )?)
            }
            _ => None,
        };
        let scene = Arc::new(scene);
        let starts = scene.start_poses[..team_config.robots].to_vec();
        let base = starts[0].position();
        let team = TeamController::on_scene(&scene, team_config.clone(), &starts, seed)?;
        let sim = SimConfig {
            robots_in_lasers: config.robots_in_lasers,
            ..team_config.sim.clone()
        };
        let mut host =
            Host::new(scene.clone(), sim, seed, Oracles::default()).with_radio(RadioSpec {
                range_m: None,
                drop_probability: 0.0,
                base: Some(base),
            });
        let team_robots: Vec<_> = starts
            .iter()
            .map(|&p| (team_config.robot.clone(), p))
            .collect();
        let team_fleet = host.add_fleet_with(&team_robots, team_config.oracles())?;
        // The team's controller runs the base station.
        host.set_base_owner(team_fleet);
        let spec = &team_config.robot;
        let team = TeamWithBtm::new(
            team,
            RobotLimits::of(spec),
            spec.circumscribed_radius_m(),
            config.crawler.keep_out_narrow,
        );
        let crawler = match crawler {
            Some((spec, build, share_period_s)) => {
                let start = scene.start_poses[team_config.robots];
                // The crawler assumes nothing: no oracle.
                let fleet = host.add_fleet_with(&[(spec.clone(), start)], Oracles::default())?;
                let explorer = Explorer::new(spec.clone(), build, start, store);
                Some(Crawler {
                    fleet,
                    controller: SharingCrawler::new(explorer, *share_period_s),
                    max_error_m: 0.0,
                })
            }
            None => None,
        };
        // The camera's view of the floor, for the operator; the rescuer's zone is a part of its
        // cell grid (geometry only).
        let view = CellView::from_scene(&scene, &CellViewParams::default());
        let rescuer = match (rescuer_part, rescuer_spec, placed) {
            (Some(part), Some(spec), Some((zone, put_down))) => {
                let oracles = crate::rescuer::oracles(part)?;
                let fleet = put_down_in_zone(&mut host, &spec, &zone, put_down, oracles)?;
                let (policy, trials) = crate::rescuer::policy(part, seed)?;
                let controller = crate::rescuer::controller(part, zone, policy)?;
                Some(Rescuer::new(fleet, controller, trials))
            }
            _ => None,
        };
        let simulated = SimulatedOperator::new(config.operator.clone(), seed ^ 0x0DE5_C000);
        let dt_s = team_config.sim.dt_s;
        Ok(Self {
            rescuer,
            desk: crate::live::desk_for(operator, simulated, view),
            board: VictimBoard::default(),
            eval: TeamEvaluation::new(&scene, &team_config, base),
            steps: (config.minutes * 60.0 / dt_s).round() as u64,
            sample_every: (SAMPLE_PERIOD_S / dt_s).round().max(1.0) as u64,
            scene,
            seed,
            host,
            team_fleet,
            team,
            crawler,
            series: Vec::new(),
        })
    }

    /// Runs to the time limit or until `hook` ends it: each step every controller decides,
    /// the hand-offs are exchanged, the hook looks on, the evaluation follows (sampled every
    /// [`SAMPLE_PERIOD_S`]), then the world moves.
    pub(crate) fn run(
        &mut self,
        mut on_progress: impl FnMut(f64),
        hook: &mut dyn MissionHook,
    ) -> Result<(), MissionError> {
        for step in 0..=self.steps {
            self.host.decide(self.team_fleet, &mut self.team);
            if let Some(c) = &mut self.crawler {
                self.host.decide(c.fleet, &mut c.controller);
                if matches!(c.controller.finished, Some(Err(_)))
                    && let Some(Err(e)) = c.controller.finished.take()
                {
                    return Err(e.into());
                }
                let truth = self
                    .host
                    .evaluator()
                    .robot(self.host.fleet(c.fleet)[0])
                    .pose;
                let estimate = c.controller.explorer.estimated_pose();
                c.max_error_m = c
                    .max_error_m
                    .max(estimate.position().distance(truth.position()));
            }
            if let Some(r) = &mut self.rescuer {
                self.host.decide(r.fleet, &mut r.controller);
            }
            self.hand_offs();
            if !hook.after_decide(&mut LiveMission { mission: self }) {
                break;
            }
            self.eval.update(
                &mut self.team.team,
                &self.host.evaluator(),
                self.host.fleet(self.team_fleet),
            );
            if step % self.sample_every == 0 || step == self.steps {
                self.series.push(MissionSample {
                    time_s: self.host.time_s(),
                    coverage: self.eval.coverage(),
                    relevant_area_m2: self.eval.relevant_area_m2(),
                });
                on_progress(self.host.time_s());
            }
            if step == self.steps {
                break;
            }
            self.host.advance();
        }
        Ok(())
    }

    /// The rescuer's question and the team's new victim reports (on the board) go to the
    /// operator; the operator's answers due now reach the rescuer and the board.
    fn hand_offs(&mut self) {
        let now = self.host.time_s();
        if let Some(r) = &mut self.rescuer {
            let id = self.host.fleet(r.fleet)[0].0;
            if let Some(q) = r.controller.take_question() {
                self.desk.ask(id, now, q);
            }
            let truth = self.host.evaluator();
            r.follow(now, |reading| truth.truth_of(reading));
        }
        let reports = self.team.team.take_reports();
        let truth = self.host.evaluator();
        self.eval.record_reports(&reports, &truth);
        let team = self.host.fleet(self.team_fleet);
        for (k, q) in self.board.post(&reports) {
            self.desk.ask(team[k].0, now, q);
        }
        let rescuer_id = self.rescuer.as_ref().map(|r| self.host.fleet(r.fleet)[0].0);
        for a in self.desk.answers(now, &truth) {
            if Some(a.robot) == rescuer_id {
                if let Some(r) = &mut self.rescuer {
                    r.controller.answer(a.answer);
                }
            } else if let (
                Question::Victim { source, .. },
                usar_rescue::controller::Answer::Victim(d),
            ) = (a.question, a.answer)
            {
                self.board
                    .answer(source, d == VictimDecision::Tag, a.time_s);
            }
        }
    }

    /// What every system did, from the evaluation's side.
    pub(crate) fn outcome(self) -> MissionOutcome {
        let truth = self.host.evaluator();
        let eval = &self.eval;
        let team_robots: Vec<_> = self
            .host
            .fleet(self.team_fleet)
            .iter()
            .map(|&id| truth.robot(id))
            .collect();
        let victims = self.victim_rows(&truth);
        let base_station = self.team.team.base_station();
        let team = TeamFigures {
            robots: team_robots.len(),
            relevant_area_m2: eval.relevant_area_m2(),
            relevant_total_m2: eval.relevant_total_m2(),
            coverage: eval.coverage(),
            explored_area_m2: base_station.merged.known_area_m2(),
            victims_total: self.scene.victims.len(),
            victims_seen: eval.victims_seen().len(),
            distance_m: team_robots.iter().map(|r| r.distance_m).sum(),
            collisions: team_robots.iter().map(|r| r.collisions).sum(),
            max_pose_error_m: eval.max_pose_error_m().iter().copied().fold(0.0, f64::max),
            btm_maps_received: self.team.maps_received,
            btm_maps_unreadable: self.team.maps_unreadable,
            keep_out_zones: base_station.keep_outs().len(),
        };
        let crawler = self.crawler.as_ref().map(|c| {
            let r = truth.robot(self.host.fleet(c.fleet)[0]);
            let btm = c.controller.explorer.btm();
            CrawlerFigures {
                nodes: btm.nodes.len(),
                links: btm.links.len(),
                searched_links: btm.links.iter().filter(|l| l.searched).count(),
                unsearched_links: btm.links.iter().filter(|l| !l.searched).count(),
                nodes_by_type: count_nodes(btm),
                stop: match &c.controller.finished {
                    Some(Ok(stop)) => Some(*stop),
                    _ => None,
                },
                distance_m: r.distance_m,
                collisions: r.collisions,
                max_position_error_m: c.max_error_m,
                maps_sent: c.controller.maps_sent,
            }
        });
        MissionOutcome {
            scene: self.scene.name.clone(),
            seed: self.seed,
            time_s: truth.time_s(),
            team,
            crawler,
            rescuer: self.rescuer_figures(&truth),
            operator: self.operator_figures(truth.time_s()),
            victim_figures: self.victim_figures(&victims, &truth),
            robot_contacts: truth.robots().iter().map(|r| r.robot_contacts).sum(),
            radio: truth.radio(),
            victims,
            handoffs: self.desk.timeline.clone(),
            series: self.series.clone(),
            merged_map: base_station.merged.clone(),
            team_trajectories: self
                .team
                .team
                .trajectories()
                .into_iter()
                .map(<[Point2]>::to_vec)
                .collect(),
            btm: self
                .crawler
                .as_ref()
                .map(|c| c.controller.explorer.btm().clone()),
            crawler_trajectory: self.crawler.as_ref().map_or_else(Vec::new, |c| {
                c.controller
                    .explorer
                    .trajectory()
                    .iter()
                    .map(|s| s.estimated.position())
                    .collect()
            }),
            keep_outs: base_station.keep_outs().to_vec(),
            rescuer_zone: self.rescuer.as_ref().map(|r| *r.controller.zone()),
            rescuer_trajectory: self
                .rescuer
                .as_ref()
                .map_or_else(Vec::new, |r| r.trajectory.clone()),
        }
    }
}

/// Puts the rescuer down at `at`, or — when its body cannot stand there (a pile of the rubble
/// arena, another robot) — at the centre of the zone cell nearest to it where it can, facing the
/// same way. A zone with no such cell is the mission's error: a rescuer put down outside its
/// zone could search nothing.
fn put_down_in_zone(
    host: &mut Host,
    spec: &RobotSpec,
    zone: &usar_world::GridGeometry,
    at: usar_world::Pose2,
    oracles: Oracles,
) -> Result<FleetId, MissionError> {
    if let Ok(fleet) = host.add_fleet_with(&[(spec.clone(), at)], oracles) {
        return Ok(fleet);
    }
    let mut centres: Vec<Point2> = (0..zone.height as i32)
        .flat_map(|r| (0..zone.width as i32).map(move |c| usar_world::Cell::new(c, r)))
        .map(|c| zone.cell_center(c))
        .collect();
    centres.sort_by(|a, b| {
        a.distance(at.position())
            .total_cmp(&b.distance(at.position()))
    });
    centres
        .into_iter()
        .find_map(|p| {
            let pose = usar_world::Pose2::new(p.x, p.y, at.theta);
            host.add_fleet_with(&[(spec.clone(), pose)], oracles).ok()
        })
        .ok_or_else(|| {
            bad(
                "rescuer.zone",
                format!("no cell of the zone is free for robot {}", spec.name),
            )
        })
}

/// Runs `config` on `scene` with `seed`; the crawler's map is also written to `store` when
/// given. `on_progress` gets the simulated time now and then.
pub fn run_mission(
    scene: Arc<Scene>,
    config: &MissionConfig,
    seed: u64,
    store: Option<&BtmStore>,
    on_progress: impl FnMut(f64),
) -> Result<MissionOutcome, MissionError> {
    run_mission_live(
        scene,
        config,
        seed,
        store,
        Operator::Simulated,
        on_progress,
        &mut Unwatched,
    )
}

/// [`run_mission`] with `operator` at the desk and `hook` beside it (see [`crate::live`]); the
/// outcome when the time limit is reached or the hook ends it.
pub fn run_mission_live(
    scene: Arc<Scene>,
    config: &MissionConfig,
    seed: u64,
    store: Option<&BtmStore>,
    operator: Operator,
    on_progress: impl FnMut(f64),
    hook: &mut dyn MissionHook,
) -> Result<MissionOutcome, MissionError> {
    config.check()?;
    let team = team_config(config)?;
    let crawler = crawler_part(&config.crawler, config.minutes, team.sim.dt_s)?;
    let mut mission = Mission::new(scene, config, team, seed, crawler.as_ref(), store, operator)?;
    mission.run(on_progress, hook)?;
    Ok(mission.outcome())
}

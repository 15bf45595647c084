//! `usar-mission`: the whole mission in one world. Paper 002's wheeled explorers and paper
//! 004's crawler run as controllers on one host — one physics: they see each other in their
//! lasers and block each other. The crawler builds a Behavioral Trace Map and sends it over the
//! radio; the team's base station closes to its wheeled robots every link and node the crawler
//! measured too steep, too narrow or too high a step for them. The evaluation follows every
//! controller from outside (ground truth never reaches a controller), and [`report`] writes the
//! report folder.
//!
//! ```
//! use std::sync::Arc;
//! use usar_mission::{MissionConfig, run_mission};
//! use usar_world::generate::{SceneKind, generate};
//!
//! let scene = Arc::new(generate(SceneKind::Office, 1));
//! let config = MissionConfig { minutes: 0.5, ..MissionConfig::default() };
//! let outcome = run_mission(scene, &config, 1, None, |_| {}).unwrap();
//! assert_eq!(outcome.team.robots, 4);
//! assert!(outcome.team.explored_area_m2 > 0.0);
//! assert!(outcome.crawler.as_ref().unwrap().nodes > 0);
//! ```

pub mod config;
pub mod controllers;
pub mod report;

pub use self::config::{CrawlerPart, MissionConfig, TeamPart};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

use self::controllers::{SharingCrawler, TeamWithBtm};
use serde::Serialize;
use std::collections::BTreeMap;
use std::sync::Arc;
use usar_btm::build::{BuildError, Explorer, StopReason, count_nodes};
use usar_btm::model::Btm;
use usar_btm::plan::RobotLimits;
use usar_btm::store::BtmStore;
use usar_map::OccupancyGrid;
use usar_map::segmentation::SegmentationParams;
use usar_sim::host::{Host, Oracles, RadioSpec, RadioStats};
use usar_sim::{PlacementError, RobotSpec, SimConfig};
use usar_team::setup::TeamSetup;
use usar_team::{Localization, MissionError as TeamError, Radio, TeamController, TeamEvaluation};
use usar_world::{Point2, Scene};

/// Why a mission could not run.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// A field of the mission file holds a value outside what it accepts.
    #[error("mission field {field}: {message}")]
    Config { field: String, message: String },
    #[error("the scene has room for {available} robots, the mission has {requested}")]
    NotEnoughRoom { available: usize, requested: usize },
    #[error(transparent)]
    Team(#[from] TeamError),
    /// A `[team]` setting named something unknown or held a value out of range.
    #[error("mission field team.{0}")]
    TeamSetting(#[from] usar_team::setup::SetupError),
    #[error(transparent)]
    Placement(#[from] PlacementError),
    #[error(transparent)]
    Build(#[from] BuildError),
    #[error(transparent)]
    Robot(#[from] usar_sim::SimError),
}

impl MissionError {
    /// Whether the mission's input is at fault (a bad file or value) rather than something
    /// that failed while it ran (writing the crawler's map to its store).
    pub fn is_input(&self) -> bool {
        !matches!(self, MissionError::Build(BuildError::Store(_)))
    }
}

/// What the team did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TeamFigures {
    pub robots: usize,
    pub relevant_area_m2: f64,
    pub relevant_total_m2: f64,
    /// Known part of the reachable floor.
    pub coverage: f64,
    pub explored_area_m2: f64,
    pub victims_total: usize,
    pub victims_seen: usize,
    pub distance_m: f64,
    pub collisions: u32,
    pub max_pose_error_m: f64,
    /// BTMs the base station received (and could not read), and the keep-out zones it drew
    /// from them.
    pub btm_maps_received: u32,
    pub btm_maps_unreadable: u32,
    pub keep_out_zones: usize,
}

/// What the crawler did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CrawlerFigures {
    pub nodes: usize,
    pub links: usize,
    pub searched_links: usize,
    pub unsearched_links: usize,
    pub nodes_by_type: BTreeMap<String, usize>,
    /// Why it stopped (`None`: the mission ended first).
    pub stop: Option<StopReason>,
    pub distance_m: f64,
    pub collisions: u32,
    pub max_position_error_m: f64,
    pub maps_sent: u32,
}

/// A victim: who saw it and when.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VictimRow {
    pub id: u32,
    pub x_m: f64,
    pub y_m: f64,
    /// The team robot that first saw it, and when (`None`: missed).
    pub seen_by: Option<usize>,
    pub seen_at_s: Option<f64>,
}

/// Coverage and relevant area at one time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MissionSample {
    pub time_s: f64,
    pub coverage: f64,
    pub relevant_area_m2: f64,
}

/// The mission's result.
#[derive(Clone, Debug, Serialize)]
pub struct MissionOutcome {
    pub scene: String,
    pub seed: u64,
    pub time_s: f64,
    pub team: TeamFigures,
    pub crawler: Option<CrawlerFigures>,
    /// Collision events in which another robot stopped a robot's motion, counted per robot
    /// stopped (a head-on meeting counts twice), over all controllers.
    pub robot_contacts: u32,
    pub radio: RadioStats,
    pub victims: Vec<VictimRow>,
    pub series: Vec<MissionSample>,
    /// For pictures: the team's merged map, its robots' believed trajectories, the crawler's
    /// BTM and estimated trajectory, the keep-out segments.
    #[serde(skip)]
    pub merged_map: OccupancyGrid,
    #[serde(skip)]
    pub team_trajectories: Vec<Vec<Point2>>,
    #[serde(skip)]
    pub btm: Option<Btm>,
    #[serde(skip)]
    pub crawler_trajectory: Vec<Point2>,
    #[serde(skip)]
    pub keep_outs: Vec<(Point2, Point2, f64)>,
}

/// How often the mission's coverage and relevant area are sampled, seconds.
const SAMPLE_PERIOD_S: f64 = 10.0;

fn bad(field: &str, message: impl Into<String>) -> MissionError {
    MissionError::Config {
        field: field.into(),
        message: message.into(),
    }
}

/// Runs `config` on `scene` with `seed`; the crawler's map is also written to `store` when
/// given. `on_progress` gets the simulated time now and then.
pub fn run_mission(
    scene: Arc<Scene>,
    config: &MissionConfig,
    seed: u64,
    store: Option<&BtmStore>,
    mut on_progress: impl FnMut(f64),
) -> Result<MissionOutcome, MissionError> {
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
    let mut team_config = setup.config()?;
    team_config.sim.robots_in_lasers = config.robots_in_lasers;
    let crawler = match Some(&config.crawler).filter(|c| c.enabled) {
        Some(c) => {
            if !(c.share_period_s.is_finite() && c.share_period_s > 0.0) {
                return Err(bad(
                    "crawler.share_period_s",
                    format!("found {}, expected a positive number", c.share_period_s),
                ));
            }
            Some((RobotSpec::load(&c.robot)?, c))
        }
        None => None,
    };
    // Room for every robot: a room layer for the team's evaluation, start poses for all.
    let robots = team_config.robots + usize::from(crawler.is_some());
    let mut scene = (*scene).clone();
    let widest = crawler
        .as_ref()
        .map_or(0.0, |(spec, _)| spec.circumscribed_radius_m())
        .max(team_config.robot.circumscribed_radius_m());
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
    let scene = Arc::new(scene);
    let starts = scene.start_poses[..team_config.robots].to_vec();
    let base = starts[0].position();
    let team = TeamController::on_scene(&scene, team_config.clone(), &starts, seed)?;
    let sim = SimConfig {
        robots_in_lasers: config.robots_in_lasers,
        ..team_config.sim.clone()
    };
    let mut host = Host::new(scene.clone(), sim, seed, Oracles::default()).with_radio(RadioSpec {
        range_m: None,
        drop_probability: 0.0,
        base: Some(base),
    });
    let team_oracles = Oracles {
        localization: team_config.localization == Localization::True,
    };
    let team_robots: Vec<_> = starts
        .iter()
        .map(|&p| (team_config.robot.clone(), p))
        .collect();
    let team_fleet = host.add_fleet_with(&team_robots, team_oracles)?;
    // The team's controller runs the base station.
    host.set_base_owner(team_fleet);
    let spec = &team_config.robot;
    let mut team = TeamWithBtm::new(team, RobotLimits::of(spec), spec.circumscribed_radius_m());
    let mut eval = TeamEvaluation::new(&scene, &team_config, base);
    let build_config = crawler.as_ref().map(|(_, c)| {
        let mut b = c.build.clone();
        b.dt_s = team_config.sim.dt_s;
        b.max_time_s = b.max_time_s.max(config.minutes * 60.0);
        b
    });
    let mut crawler = match (&crawler, &build_config) {
        (Some((spec, part)), Some(build)) => {
            build
                .validate()
                .map_err(|(field, found)| bad(&format!("crawler.build.{field}"), found))?;
            let start = scene.start_poses[team_config.robots];
            // The crawler assumes nothing: no oracle.
            let fleet = host.add_fleet_with(&[(spec.clone(), start)], Oracles::default())?;
            let explorer = Explorer::new(spec.clone(), build, start, store);
            Some((fleet, SharingCrawler::new(explorer, part.share_period_s)))
        }
        _ => None,
    };
    let steps = (config.minutes * 60.0 / team_config.sim.dt_s).round() as u64;
    let sample_every = (SAMPLE_PERIOD_S / team_config.sim.dt_s).round() as u64;
    let mut series = Vec::new();
    let mut crawler_error_m: f64 = 0.0;
    for step in 0..=steps {
        host.decide(team_fleet, &mut team);
        if let Some((fleet, c)) = &mut crawler {
            host.decide(*fleet, c);
            if matches!(c.finished, Some(Err(_)))
                && let Some(Err(e)) = c.finished.take()
            {
                return Err(e.into());
            }
            let truth = host.evaluator().robot(host.fleet(*fleet)[0]).pose;
            crawler_error_m = crawler_error_m.max(
                c.explorer
                    .estimated_pose()
                    .position()
                    .distance(truth.position()),
            );
        }
        eval.update(&mut team.team, &host.evaluator(), host.fleet(team_fleet));
        if step % sample_every == 0 || step == steps {
            series.push(MissionSample {
                time_s: host.time_s(),
                coverage: eval.coverage(),
                relevant_area_m2: eval.relevant_area_m2(),
            });
            on_progress(host.time_s());
        }
        if step == steps {
            break;
        }
        host.advance();
    }
    let truth = host.evaluator();
    let team_ids = host.fleet(team_fleet);
    let team_robots_truth: Vec<_> = team_ids.iter().map(|&id| truth.robot(id)).collect();
    let victims = scene
        .victims
        .iter()
        .map(|v| {
            let seen = eval.victims_seen().iter().find(|s| s.victim_id == v.id);
            VictimRow {
                id: v.id,
                x_m: v.position.x,
                y_m: v.position.y,
                seen_by: seen.map(|s| s.robot),
                seen_at_s: seen.map(|s| s.time_s),
            }
        })
        .collect();
    let base_station = team.team.base_station();
    let team_figures = TeamFigures {
        robots: team_ids.len(),
        relevant_area_m2: eval.relevant_area_m2(),
        relevant_total_m2: eval.relevant_total_m2(),
        coverage: eval.coverage(),
        explored_area_m2: base_station.merged.known_area_m2(),
        victims_total: scene.victims.len(),
        victims_seen: eval.victims_seen().len(),
        distance_m: team_robots_truth.iter().map(|r| r.distance_m).sum(),
        collisions: team_robots_truth.iter().map(|r| r.collisions).sum(),
        max_pose_error_m: eval.max_pose_error_m().iter().copied().fold(0.0, f64::max),
        btm_maps_received: team.maps_received,
        btm_maps_unreadable: team.maps_unreadable,
        keep_out_zones: base_station.keep_outs().len(),
    };
    let (crawler_figures, btm, crawler_trajectory) = match &crawler {
        Some((fleet, c)) => {
            let r = truth.robot(host.fleet(*fleet)[0]);
            let btm = c.explorer.btm();
            let samples = c.explorer.trajectory();
            (
                Some(CrawlerFigures {
                    nodes: btm.nodes.len(),
                    links: btm.links.len(),
                    searched_links: btm.links.iter().filter(|l| l.searched).count(),
                    unsearched_links: btm.links.iter().filter(|l| !l.searched).count(),
                    nodes_by_type: count_nodes(btm),
                    stop: match &c.finished {
                        Some(Ok(stop)) => Some(*stop),
                        _ => None,
                    },
                    distance_m: r.distance_m,
                    collisions: r.collisions,
                    max_position_error_m: crawler_error_m,
                    maps_sent: c.maps_sent,
                }),
                Some(btm.clone()),
                samples.iter().map(|s| s.estimated.position()).collect(),
            )
        }
        None => (None, None, Vec::new()),
    };
    Ok(MissionOutcome {
        scene: scene.name.clone(),
        seed,
        time_s: truth.time_s(),
        team: team_figures,
        crawler: crawler_figures,
        robot_contacts: truth.robots().iter().map(|r| r.robot_contacts).sum(),
        radio: truth.radio(),
        victims,
        series,
        merged_map: base_station.merged.clone(),
        team_trajectories: team
            .team
            .trajectories()
            .into_iter()
            .map(<[Point2]>::to_vec)
            .collect(),
        btm,
        crawler_trajectory,
        keep_outs: base_station.keep_outs().to_vec(),
    })
}

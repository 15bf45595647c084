//! Runner `explore`: the baseline nearest-frontier team explorer (paper 002's Distance
//! strategy) on a scene.

use crate::{TeamConfig, TeamMission};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use usar_campaign::{Config, FactorSpec, MetricSpec, RunError, RunOutput, Runner, SeriesPoint};
use usar_world::Scene;
use usar_world::io::source::{BareImage, load_scene};

pub struct ExploreRunner {
    /// Scenes by (scene, scene_seed): generated or read once per campaign.
    scenes: Mutex<BTreeMap<(String, u64), Arc<Scene>>>,
}

impl Default for ExploreRunner {
    fn default() -> Self {
        Self::new()
    }
}

impl ExploreRunner {
    /// A runner with an empty scene cache (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self {
            scenes: Mutex::new(BTreeMap::new()),
        }
    }

    fn scene(&self, config: &Config) -> Result<Arc<Scene>, String> {
        scene_for(&self.scenes, config)
    }

    fn team_config(config: &Config) -> Result<TeamConfig, String> {
        let robot = usar_sim::RobotSpec::load(config.text("robot").unwrap_or("wheeled"))
            .map_err(|e| e.to_string())?;
        let stop = config.float("stop_at_coverage").unwrap_or(1.0);
        let stall = config.float("stall_minutes").unwrap_or(3.0);
        Ok(TeamConfig {
            robots: config.int("robots").unwrap_or(4) as usize,
            robot,
            duration_s: config.float("minutes").unwrap_or(20.0) * 60.0,
            stop_at_coverage: (stop < 1.0).then_some(stop),
            stall_after_s: (stall > 0.0).then_some(stall * 60.0),
            tuning: super::tuning_of(config)?,
            ..TeamConfig::default()
        })
    }
}

/// Scenes by (scene, scene_seed), generated or read once per campaign.
pub type SceneCache = Mutex<BTreeMap<(String, u64), Arc<Scene>>>;

/// The scene a configuration names (`scene`, `scene_seed`), from `cache` or loaded into it
/// (the `explore`, `team` and `mission` runners share it).
pub fn scene_for(cache: &SceneCache, config: &Config) -> Result<Arc<Scene>, String> {
    let name = config.text("scene").unwrap_or("office").to_string();
    let seed = config.int("scene_seed").unwrap_or(1) as u64;
    let key = (name.clone(), seed);
    if let Some(s) = cache.lock().expect("scene cache").get(&key) {
        return Ok(s.clone());
    }
    let scene = load_scene(&name, seed, &BareImage::default()).map_err(|e| e.to_string())?;
    let scene = Arc::new(scene);
    cache
        .lock()
        .expect("scene cache")
        .insert(key, scene.clone());
    Ok(scene)
}

/// The factors every team runner has: `scene`, `scene_seed`, `robots` and `robot` (defaults
/// `robots` and `robot`).
pub(crate) fn scene_and_team_factors(
    scene_help: &str,
    robots: i64,
    robot: &str,
) -> Vec<FactorSpec> {
    vec![
        FactorSpec::text("scene", &[], "office", scene_help),
        FactorSpec::int("scene_seed", (0, i64::MAX), 1, "seed of a generated scene"),
        FactorSpec::int("robots", (1, 64), robots, "team size"),
        FactorSpec::text(
            "robot",
            &[],
            robot,
            "robot model: crawler, cell-crawler, wheeled, wheeled-paper-pace or a robot TOML file",
        ),
    ]
}

/// A team of `robots` needs as many start poses in the scene.
pub(crate) fn enough_start_poses(scene: &Scene, robots: usize) -> Result<(), String> {
    if scene.start_poses.len() < robots {
        return Err(format!(
            "scene {} has {} start poses, robots = {robots}",
            scene.name,
            scene.start_poses.len()
        ));
    }
    Ok(())
}

impl Runner for ExploreRunner {
    fn name(&self) -> &str {
        "explore"
    }

    fn factors(&self) -> Vec<FactorSpec> {
        let mut factors = scene_and_team_factors(
            "a generator name (office, mall, rubble, course) or a scene/map file",
            4,
            "wheeled",
        );
        factors.extend([
            FactorSpec::float("minutes", (0.01, 1440.0), 20.0, "simulated time limit"),
            FactorSpec::float(
                "stop_at_coverage",
                (0.0, 1.0),
                1.0,
                "stop at this coverage (1: never)",
            ),
            FactorSpec::float(
                "stall_minutes",
                (0.0, 1440.0),
                3.0,
                "stop when coverage grew < 0.2 % in this long (0: never)",
            ),
        ]);
        factors.extend(super::tuning_factors());
        factors
    }

    fn metrics(&self) -> Vec<MetricSpec> {
        vec![
            MetricSpec::new(
                "coverage",
                "known fraction of the reachable area at the end",
            ),
            MetricSpec::new("victims_seen", "victims whose heat signature a robot saw"),
            MetricSpec::new("time_s", "simulated time at the end"),
            MetricSpec::new("distance_m", "distance driven by the whole team"),
            MetricSpec::new("collisions", "collisions of the whole team"),
        ]
    }

    fn series_x(&self) -> &str {
        "time (s)"
    }

    fn check(&self, config: &Config) -> Result<(), RunError> {
        let scene = self.scene(config).map_err(RunError::Input)?;
        let team = Self::team_config(config).map_err(RunError::Input)?;
        enough_start_poses(&scene, team.robots).map_err(RunError::Input)
    }

    fn run(&self, config: &Config, seed: u64) -> Result<RunOutput, RunError> {
        let scene = self.scene(config).map_err(RunError::Input)?;
        let team = Self::team_config(config).map_err(RunError::Input)?;
        // Every reason a team mission cannot start is its configuration's.
        let outcome = TeamMission::new(scene, team, seed)
            .map_err(|e| RunError::Input(e.to_string()))?
            .run(|_| {});
        let metrics = BTreeMap::from([
            ("coverage".to_string(), outcome.coverage),
            ("victims_seen".to_string(), outcome.victims_seen as f64),
            ("time_s".to_string(), outcome.time_s),
            ("distance_m".to_string(), outcome.distance_m),
            ("collisions".to_string(), f64::from(outcome.collisions)),
        ]);
        let series = outcome
            .series
            .iter()
            .map(|s| SeriesPoint {
                x: (s.time_s * 1e3).round() / 1e3,
                values: BTreeMap::from([
                    ("coverage".to_string(), s.coverage),
                    ("victims_seen".to_string(), s.victims_seen as f64),
                ]),
            })
            .collect();
        Ok(RunOutput { metrics, series })
    }
}

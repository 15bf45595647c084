//! Runner `team`: paper 002's semantically-informed exploration (one `usar team run`).

use super::explore::{enough_start_poses, scene_and_team_factors, scene_for};
use crate::paper_run::RunSummary;
use crate::scene_prep::prepare_scene;
use crate::setup::{DEFAULT_ROBOT, TeamSetup};
use crate::{Radio, TeamConfig, TeamMission};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use usar_campaign::{Config, FactorSpec, MetricSpec, RunError, RunOutput, Runner, SeriesPoint};
use usar_map::segmentation::SegmentationParams;
use usar_world::{RoomLabel, Scene};

pub struct TeamRunner {
    /// Scenes by (scene, scene_seed): generated or read once per campaign.
    scenes: Mutex<BTreeMap<(String, u64), Arc<Scene>>>,
    /// Scenes given a room layer (segmentation) and start poses, by (scene, scene_seed, robots).
    prepared: Mutex<BTreeMap<(String, u64, usize), Arc<Scene>>>,
}

/// The label names of the `assigned_*` metrics.
const LABELS: [(RoomLabel, &str); 4] = [
    (RoomLabel::Corridor, "corridor"),
    (RoomLabel::SmallRoom, "small_room"),
    (RoomLabel::MediumRoom, "medium_room"),
    (RoomLabel::BigRoom, "big_room"),
];

impl Default for TeamRunner {
    fn default() -> Self {
        Self::new()
    }
}

impl TeamRunner {
    /// A runner with empty caches (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self {
            scenes: Mutex::new(BTreeMap::new()),
            prepared: Mutex::new(BTreeMap::new()),
        }
    }

    /// The run's scene; one without a room layer is segmented, one with fewer start poses than
    /// robots gets more (`usar_team::scene_prep`), as `usar team run` does.
    fn scene(&self, config: &Config, team: &TeamConfig) -> Result<Arc<Scene>, String> {
        let base = scene_for(&self.scenes, config)?;
        if !base.rooms.is_empty() && base.start_poses.len() >= team.robots {
            return Ok(base);
        }
        let key = (
            config.text("scene").unwrap_or("office").to_string(),
            config.int("scene_seed").unwrap_or(1) as u64,
            team.robots,
        );
        let mut cache = self.prepared.lock().expect("prepared scene cache");
        if let Some(s) = cache.get(&key) {
            return Ok(s.clone());
        }
        let mut scene = (*base).clone();
        prepare_scene(
            &mut scene,
            team.robots,
            team.robot.circumscribed_radius_m() + 0.1,
            &SegmentationParams::default(),
        );
        let scene = Arc::new(scene);
        cache.insert(key, scene.clone());
        Ok(scene)
    }

    fn setup(config: &Config) -> TeamSetup<'_> {
        let range = config.float("radio_range_m").unwrap_or(0.0);
        TeamSetup {
            robots: config.int("robots").unwrap_or(6) as usize,
            robot: config.text("robot").unwrap_or(DEFAULT_ROBOT),
            strategy: config.text("strategy").unwrap_or("s-mcdm"),
            coordination: config.text("coordination").unwrap_or("sr"),
            hypothesis: config.text("hypothesis").unwrap_or("big"),
            minutes: config.float("minutes").unwrap_or(20.0),
            label_errors: config.text("label_errors").unwrap_or("perfect"),
            candidates: config.text("candidates").unwrap_or("room"),
            semantics: config.text("semantics").unwrap_or("oracle"),
            localization: config.text("localization").unwrap_or("true"),
            stop_at_relevant: config.float("stop_at_relevant").filter(|&f| f > 0.0),
            merge_period_s: config.float("merge_period_s").unwrap_or(2.5),
            radio: Radio {
                range_m: (range > 0.0).then_some(range),
                drop_probability: config.float("radio_drop").unwrap_or(0.0),
            },
            failures: Vec::new(),
        }
    }
}

impl Runner for TeamRunner {
    fn name(&self) -> &str {
        "team"
    }

    fn factors(&self) -> Vec<FactorSpec> {
        let text = |name: &str, default: &str, choices: &[&str], help: &str| {
            FactorSpec::text(name, choices, default, help)
        };
        let float = |name: &str, default: f64, max: f64, help: &str| {
            FactorSpec::float(name, (0.0, max), default, help)
        };
        let mut factors = scene_and_team_factors(
            "office or mall (generated with scene_seed), or a scene file (segmented if it has no room layer)",
            6,
            DEFAULT_ROBOT,
        );
        factors.extend([
            text(
                "strategy",
                "s-mcdm",
                &["random", "distance", "d-mcdm", "s-mcdm", "nearest"],
                "exploration strategy",
            ),
            text(
                "coordination",
                "sr",
                &["sr", "mrv1", "mrv2"],
                "coordination method",
            ),
            text(
                "hypothesis",
                "big",
                &["big", "small"],
                "victims in big or small rooms",
            ),
            text(
                "label_errors",
                "perfect",
                &[],
                "perfect, random:RATE or until-known:FRACTION (paper 002 §4.4)",
            ),
            text(
                "candidates",
                "room",
                &["room", "cluster"],
                "candidate locations: one per room, or one per frontier cluster (paper 002 §3.1)",
            ),
            text(
                "semantics",
                "oracle",
                &["oracle", "segmented"],
                "rooms and labels: the scene's (the paper's oracle) or segmented from the team's map",
            ),
            text(
                "localization",
                "true",
                &["true", "estimated"],
                "poses robots map at: true (the paper's oracle) or odometry + scan matching",
            ),
            float("minutes", 20.0, 1440.0, "simulated time limit"),
            float(
                "stop_at_relevant",
                0.0,
                1.0,
                "stop at this known fraction of the relevant area (0: run to the limit)",
            ),
            float(
                "merge_period_s",
                2.5,
                600.0,
                "map merge period at the base station",
            ),
            float(
                "radio_range_m",
                0.0,
                1e6,
                "radio range from the base station (0: unlimited)",
            ),
            float(
                "radio_drop",
                0.0,
                1.0,
                "probability that an exchange is lost",
            ),
        ]);
        factors.extend(super::tuning_factors());
        factors
    }

    fn metrics(&self) -> Vec<MetricSpec> {
        let mut m = vec![
            MetricSpec::new("relevant_area_m2", "explored relevant area at the end"),
            MetricSpec::new("total_area_m2", "explored area at the end"),
            MetricSpec::new("distance_m", "distance travelled by the whole team"),
            MetricSpec::new(
                "time_to_relevant_s",
                "when the relevant-area target (stop_at_relevant, else 0.9) was reached; the run's end if never",
            ),
            MetricSpec::new(
                "relevant_fraction",
                "explored fraction of the relevant area",
            ),
            MetricSpec::new("time_s", "simulated time at the end"),
            MetricSpec::new("collisions", "collisions of the whole team"),
        ];
        for (_, name) in LABELS {
            m.push(MetricSpec {
                name: format!("assigned_{name}"),
                help: format!("candidate locations assigned in {name}s"),
            });
        }
        m
    }

    fn series_x(&self) -> &str {
        "time (s)"
    }

    fn check(&self, config: &Config) -> Result<(), RunError> {
        let input = |e: String| RunError::Input(e);
        let mut team = Self::setup(config)
            .config()
            .map_err(|e| input(e.to_string()))?;
        team.tuning = super::tuning_of(config).map_err(input)?;
        let scene = self.scene(config, &team).map_err(input)?;
        enough_start_poses(&scene, team.robots).map_err(input)?;
        if scene.rooms.is_empty() {
            return Err(input(format!(
                "scene {} has no room layer and no free space to segment",
                scene.name
            )));
        }
        Ok(())
    }

    fn run(&self, config: &Config, seed: u64) -> Result<RunOutput, RunError> {
        let input = |e: String| RunError::Input(e);
        let setup = Self::setup(config);
        let mut team = setup.config().map_err(|e| input(e.to_string()))?;
        team.tuning = super::tuning_of(config).map_err(input)?;
        let scene = self.scene(config, &team).map_err(input)?;
        // Every reason a team mission cannot start is its configuration's.
        let outcome = TeamMission::new(scene, team, seed)
            .map_err(|e| input(e.to_string()))?
            .run(|_| {});
        let s = RunSummary::new(
            &outcome,
            setup.strategy,
            setup.coordination,
            setup.hypothesis,
            seed,
        );
        let assigned =
            |m: &BTreeMap<RoomLabel, u32>, l: RoomLabel| f64::from(m.get(&l).copied().unwrap_or(0));
        let mut metrics = BTreeMap::from([
            ("relevant_area_m2".to_string(), s.relevant_area_m2),
            ("total_area_m2".to_string(), s.total_area_m2),
            ("distance_m".to_string(), s.distance_m),
            (
                "time_to_relevant_s".to_string(),
                s.time_to_relevant_s.unwrap_or(s.time_s),
            ),
            (
                "relevant_fraction".to_string(),
                s.relevant_area_m2 / s.relevant_total_m2.max(1e-9),
            ),
            ("time_s".to_string(), s.time_s),
            ("collisions".to_string(), f64::from(s.collisions)),
        ]);
        for (l, name) in LABELS {
            metrics.insert(
                format!("assigned_{name}"),
                assigned(&s.assigned_per_label, l),
            );
        }
        let series = s
            .series
            .iter()
            .map(|p| {
                let mut values = BTreeMap::from([
                    ("relevant_area_m2".to_string(), p.relevant_area_m2),
                    ("total_area_m2".to_string(), p.total_area_m2),
                    ("distance_m".to_string(), p.distance_m),
                ]);
                for (l, name) in LABELS {
                    values.insert(
                        format!("assigned_{name}"),
                        assigned(&p.assigned_per_label, l),
                    );
                }
                SeriesPoint {
                    x: (p.time_s * 1e3).round() / 1e3,
                    values,
                }
            })
            .collect();
        Ok(RunOutput { metrics, series })
    }
}

//! Runner `mission`: the whole mission ([`crate::run_mission`]) as a campaign runs it, so that
//! its per-system figures can be swept over floors, seeds, teams and operators and reported
//! like any other campaign.

use crate::{MissionConfig, run_mission};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use usar_campaign::{Config, FactorSpec, MetricSpec, RunError, RunOutput, Runner, SeriesPoint};
use usar_team::runner::{SceneCache, scene_for};
use usar_world::Scene;

/// See the [module documentation](self).
pub struct MissionRunner {
    scenes: SceneCache,
}

impl Default for MissionRunner {
    fn default() -> Self {
        Self::new()
    }
}

impl MissionRunner {
    /// A runner with an empty scene cache (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self {
            scenes: Mutex::new(BTreeMap::new()),
        }
    }

    fn scene(&self, config: &Config) -> Result<Arc<Scene>, RunError> {
        scene_for(&self.scenes, config).map_err(RunError::Input)
    }

    /// The mission file a configuration stands for: the built-in mission with the factors'
    /// values (a factor left out keeps the built-in value).
    fn mission(config: &Config) -> MissionConfig {
        let mut m = MissionConfig::default();
        m.scene = config.text("scene").unwrap_or(&m.scene).to_string();
        m.scene_seed = config.int("scene_seed").map_or(m.scene_seed, |s| s as u64);
        m.minutes = config.float("minutes").unwrap_or(m.minutes);
        m.team.robots = config
            .int("team_robots")
            .map_or(m.team.robots, |n| n as usize);
        m.team.strategy = config
            .text("strategy")
            .unwrap_or(&m.team.strategy)
            .to_string();
        m.team.coordination = config
            .text("coordination")
            .unwrap_or(&m.team.coordination)
            .to_string();
        m.crawler.enabled = config.int("crawler").map_or(m.crawler.enabled, |v| v == 1);
        m.rescuer.enabled = config.int("rescuer").map_or(m.rescuer.enabled, |v| v == 1);
        m.rescuer.zone_cells = config
            .int("zone_cells")
            .map_or(m.rescuer.zone_cells, |v| v as u32);
        m.rescuer.put_down = config
            .text("put_down")
            .unwrap_or(&m.rescuer.put_down)
            .to_string();
        m.rescuer.train_trials = config
            .int("train_trials")
            .map_or(m.rescuer.train_trials, |v| v as u32);
        m.operator.delay_s = config
            .float("operator_delay_s")
            .unwrap_or(m.operator.delay_s);
        m
    }
}

impl Runner for MissionRunner {
    fn name(&self) -> &str {
        "mission"
    }

    fn factors(&self) -> Vec<FactorSpec> {
        vec![
            FactorSpec::text(
                "scene",
                &[],
                "office",
                "a generator name (office, mall, rubble, course) or a scene/map file",
            ),
            FactorSpec::int("scene_seed", (0, i64::MAX), 1, "seed of a generated scene"),
            FactorSpec::float("minutes", (0.01, 1440.0), 10.0, "simulated time limit"),
            FactorSpec::int("team_robots", (1, 32), 4, "paper 002's wheeled robots"),
            FactorSpec::text(
                "strategy",
                &["random", "distance", "d-mcdm", "s-mcdm", "nearest"],
                "s-mcdm",
                "the team's strategy",
            ),
            FactorSpec::text(
                "coordination",
                &["sr", "mrv1", "mrv2"],
                "mrv1",
                "the team's coordination",
            ),
            FactorSpec::int(
                "crawler",
                (0, 1),
                1,
                "1: paper 004's crawler shares its BTM",
            ),
            FactorSpec::int(
                "rescuer",
                (0, 1),
                1,
                "1: paper 000's robot searches a rubble zone",
            ),
            FactorSpec::int(
                "zone_cells",
                (2, 40),
                10,
                "side of the rescuer's zone, cells",
            ),
            FactorSpec::text(
                "put_down",
                &["arena-start", "open-turnable"],
                "arena-start",
                "where the rescuer is put down in its rubble zone",
            ),
            FactorSpec::int(
                "train_trials",
                (1, 1_000_000),
                300,
                "the rescuer's training trials",
            ),
            FactorSpec::float(
                "operator_delay_s",
                (0.0, 600.0),
                5.0,
                "the operator's mean response time",
            ),
        ]
    }

    fn metrics(&self) -> Vec<MetricSpec> {
        [
            ("relevant_area_m2", "relevant area the team explored"),
            ("coverage", "known fraction of the reachable floor"),
            ("btm_nodes", "nodes of the crawler's BTM"),
            ("btm_links", "links of the crawler's BTM"),
            ("rescuer_cells", "zone cells the rescuer visited"),
            ("rescuer_tags", "possible victims the rescuer tagged"),
            ("victims_detected", "victims some robot detected"),
            (
                "victims_confirmed",
                "victims the operator or the rescuer confirmed",
            ),
            ("victims_missed", "victims nobody detected"),
            ("false_confirmations", "confirmations of what was no victim"),
            ("handoffs_asked", "questions for the operator"),
            ("handoffs_answered", "questions the operator answered"),
            ("mean_wait_s", "mean seconds from a question to its answer"),
            ("robot_contacts", "times one robot stopped another"),
        ]
        .into_iter()
        .map(|(name, help)| MetricSpec::new(name, help))
        .collect()
    }

    fn series_x(&self) -> &str {
        "time (s)"
    }

    fn check(&self, config: &Config) -> Result<(), RunError> {
        self.scene(config).map(|_| ())
    }

    fn run(&self, config: &Config, seed: u64) -> Result<RunOutput, RunError> {
        let scene = self.scene(config)?;
        let mission = Self::mission(config);
        let out = run_mission(scene, &mission, seed, None, |_| {}).map_err(|e| {
            if e.is_input() {
                RunError::Input(e.to_string())
            } else {
                RunError::Failed(e.to_string())
            }
        })?;
        let v = &out.victim_figures;
        let (crawler, rescuer) = (out.crawler.as_ref(), out.rescuer.as_ref());
        let metrics = BTreeMap::from([
            ("relevant_area_m2".into(), out.team.relevant_area_m2),
            ("coverage".into(), out.team.coverage),
            ("btm_nodes".into(), crawler.map_or(0.0, |c| c.nodes as f64)),
            ("btm_links".into(), crawler.map_or(0.0, |c| c.links as f64)),
            (
                "rescuer_cells".into(),
                rescuer.map_or(0.0, |r| r.cells_visited as f64),
            ),
            (
                "rescuer_tags".into(),
                rescuer.map_or(0.0, |r| r.tags as f64),
            ),
            ("victims_detected".into(), v.detected as f64),
            ("victims_confirmed".into(), v.confirmed as f64),
            ("victims_missed".into(), v.missed as f64),
            ("false_confirmations".into(), v.false_confirmations as f64),
            ("handoffs_asked".into(), out.operator.asked as f64),
            ("handoffs_answered".into(), out.operator.answered as f64),
            ("mean_wait_s".into(), out.operator.mean_wait_s),
            ("robot_contacts".into(), f64::from(out.robot_contacts)),
        ]);
        let series = out
            .series
            .iter()
            .map(|s| SeriesPoint {
                x: s.time_s,
                values: BTreeMap::from([
                    ("coverage".into(), s.coverage),
                    ("relevant_area_m2".into(), s.relevant_area_m2),
                ]),
            })
            .collect();
        Ok(RunOutput { metrics, series })
    }
}

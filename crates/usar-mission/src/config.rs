//! A mission file (TOML): the floor, the time, the team and the crawler. Every field has a
//! default, so an empty file is the built-in mission.

use serde::{Deserialize, Serialize};
use usar_btm::build::BuildConfig;

/// The whole mission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MissionConfig {
    /// A generator name (`office`, `mall`, `course`, `rubble`) or a scene / map file.
    pub scene: String,
    /// The generator's seed.
    pub scene_seed: u64,
    /// Simulated time limit, minutes.
    pub minutes: f64,
    /// Whether robots show in each other's lasers (they always block each other).
    pub robots_in_lasers: bool,
    pub team: TeamPart,
    /// The crawler building a Behavioral Trace Map (`enabled = false`: none).
    pub crawler: CrawlerPart,
}

impl Default for MissionConfig {
    fn default() -> Self {
        Self {
            scene: "office".into(),
            scene_seed: 1,
            minutes: 10.0,
            robots_in_lasers: true,
            team: TeamPart::default(),
            crawler: CrawlerPart::default(),
        }
    }
}

/// Paper 002's wheeled explorers, named as `usar team run` names them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TeamPart {
    pub robots: usize,
    pub robot: String,
    pub strategy: String,
    pub coordination: String,
    pub hypothesis: String,
    pub label_errors: String,
    pub candidates: String,
    pub semantics: String,
    pub localization: String,
}

impl Default for TeamPart {
    fn default() -> Self {
        Self {
            robots: 4,
            robot: usar_team::setup::DEFAULT_ROBOT.into(),
            strategy: "s-mcdm".into(),
            coordination: "mrv1".into(),
            hypothesis: "big".into(),
            label_errors: "perfect".into(),
            candidates: "room".into(),
            semantics: "oracle".into(),
            localization: "true".into(),
        }
    }
}

/// The crawler of paper 004: it builds a BTM and shares it over the radio.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CrawlerPart {
    /// `false`: a mission without a crawler.
    pub enabled: bool,
    pub robot: String,
    /// It sends its whole map to the base station this often, seconds.
    pub share_period_s: f64,
    /// The base station also closes links and nodes the crawler measured narrower than the
    /// team's robots (by default only slopes and stairs: the team's own maps show widths).
    pub keep_out_narrow: bool,
    /// Its builder's parameters (`usar btm build --config`), but for its step, which is the
    /// mission's, and its time limit, which is at least the mission's.
    pub build: BuildConfig,
}

impl Default for CrawlerPart {
    fn default() -> Self {
        Self {
            enabled: true,
            robot: "crawler".into(),
            share_period_s: 10.0,
            keep_out_narrow: false,
            build: BuildConfig::default(),
        }
    }
}

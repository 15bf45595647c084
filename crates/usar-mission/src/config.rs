//! A mission file (TOML): the floor, the time, the team and the crawler. Every field has a
//! default, so an empty file is the built-in mission.

use serde::{Deserialize, Serialize};
use usar_btm::build::BuildConfig;
use usar_rescue::operator::OperatorProfile;

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
    /// Paper 000's robot searching a zone of the floor (`enabled = false`: none).
    pub rescuer: RescuerPart,
    /// The one operator every hand-off goes to.
    pub operator: OperatorProfile,
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
            rescuer: RescuerPart::default(),
            operator: OperatorProfile::expert(),
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

/// Paper 000's semi-autonomous robot: its learned MAXQ policy searches a square zone of the
/// floor around where it is put down, cell by cell, and hands uncertain victims and being stuck
/// to the operator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RescuerPart {
    /// `false`: a mission without it.
    pub enabled: bool,
    pub robot: String,
    /// Where its zone is: `largest-room` (centred on the floor's largest room that is not a
    /// corridor) or `start` (around the start pose the scene gives it).
    pub zone: String,
    /// Side of its zone, in paper 000's 0.914 m cells.
    pub zone_cells: u32,
    /// Lay a rubble arena generated as paper 000's (piles, ramps, drops, buried victims) onto
    /// the free floor of the room its zone is in (`largest-room` only): the collapsed part of the
    /// building.
    pub rubble: bool,
    /// Where the robot is put down in a rubble zone: `arena-start` (the rubble arena's own
    /// start cell, where paper 000's robot enters its arena; the zone's centre when that falls
    /// on a wall of the floor) or `open-turnable` (a variant developed on the report floors:
    /// open floor where its body can turn, in the largest part of the zone it can reach).
    pub put_down: String,
    /// A policy file (`usar maxq train`); empty: trained at the start for `train_trials`
    /// trials on generated rubble scenes (as the console does).
    pub policy: String,
    pub train_trials: u32,
    /// The Table II case of its exploration weights.
    pub weights: String,
    /// Most primitives it may execute.
    pub max_primitives: u64,
    /// `true`: it knows its true pose (paper 000's robot knows its cell, L_R — a named oracle);
    /// `estimated`: it drives on its odometry.
    pub localization: String,
}

impl Default for RescuerPart {
    fn default() -> Self {
        Self {
            enabled: true,
            robot: "cell-crawler".into(),
            zone: "largest-room".into(),
            zone_cells: 10,
            rubble: true,
            put_down: "arena-start".into(),
            policy: String::new(),
            train_trials: 300,
            weights: "equal".into(),
            max_primitives: 3_000,
            localization: "true".into(),
        }
    }
}

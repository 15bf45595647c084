//! What a console runs and where it listens: the mission file (TOML) and the server options.

use serde::Deserialize;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use usar_world::Scene;

/// Why a console could not start.
#[derive(Debug, thiserror::Error)]
pub enum ConsoleError {
    /// The mission file could not be read.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The mission file is not valid: the file, and the field or line.
    #[error("{path}: {message}")]
    MissionFile { path: PathBuf, message: String },
    /// A mission value is out of range.
    #[error("mission field `{field}`: {message}")]
    Field { field: String, message: String },
    /// A non-loopback address without an explicit token.
    #[error(
        "--bind {0}: not a loopback address; serving the console beyond this machine needs an explicit --token"
    )]
    OpenBindWithoutToken(SocketAddr),
    /// The address could not be bound.
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        addr: SocketAddr,
        source: std::io::Error,
    },
    /// The policy file could not be used.
    #[error(transparent)]
    Policy(#[from] usar_rescue::policy::PolicyError),
    /// The team mission could not be set up.
    #[error("team mission: {0}")]
    Team(#[from] usar_team::MissionError),
}

/// The simulated mission (a TOML mission file; every field optional).
///
/// ```toml
/// seed = 1            # scene generator and every random stream
/// team_robots = 3     # robots exploring with S-MCDM
/// strategy = "s-mcdm" # random | distance | d-mcdm | s-mcdm
/// hypothesis = "big"  # big | small (paper 002)
/// speed = 1.0         # simulated seconds per wall-clock second
/// train_trials = 300  # MAXQ training at start when no policy file is given
/// slip_probability = 0.3
/// stuck_after_slips = 2
/// weights = [1.0, 1.0, 1.0]   # w_l, w_p, w_q (paper 000 §V)
/// btm = true          # build a BTM beside the mission
/// minutes = 60        # the team's mission length (simulated)
/// team_robot = "crawler"  # crawler | wheeled (usar-sim presets)
/// floor_cell_m2 = 2.25    # cell area of the generated rubble floor (paper 000: 0.84)
/// ```
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MissionConfig {
    pub seed: u64,
    pub team_robots: usize,
    pub strategy: String,
    pub hypothesis: String,
    pub speed: f64,
    pub train_trials: u32,
    pub slip_probability: f64,
    pub stuck_after_slips: u32,
    pub weights: [f64; 3],
    pub btm: bool,
    pub minutes: f64,
    /// The team's robots: a `usar-sim` preset. The crawler climbs the rubble the MAXQ robot
    /// climbs; the wheeled robot (paper 002's default) stops at every step of 5 cm.
    pub team_robot: String,
    /// Cell area of the generated rubble floor, m². Paper 000's arena has 0.84 m² cells, whose
    /// single-cell gates (0.92 m) leave a 0.6 × 0.45 m crawler too little room to plan through
    /// its inflated map; the console's floor has 1.5 m cells (2.25 m²) so that the team explores
    /// it too. The MAXQ robot works on cells of any size.
    pub floor_cell_m2: f64,
    /// A policy file (`usar maxq train`); trained at start when absent.
    pub policy: Option<PathBuf>,
    /// The scene; a generated rubble floor when absent. Not in the file (given by the CLI).
    #[serde(skip)]
    pub scene: Option<Scene>,
}

impl Default for MissionConfig {
    fn default() -> Self {
        Self {
            seed: 1,
            team_robots: 3,
            strategy: "s-mcdm".into(),
            hypothesis: "big".into(),
            speed: 1.0,
            train_trials: 300,
            slip_probability: 0.3,
            stuck_after_slips: 2,
            weights: [1.0, 1.0, 1.0],
            btm: true,
            minutes: 60.0,
            team_robot: "crawler".into(),
            floor_cell_m2: 2.25,
            policy: None,
            scene: None,
        }
    }
}

impl MissionConfig {
    /// Reads a mission file.
    pub fn from_file(path: &Path) -> Result<Self, ConsoleError> {
        let text = std::fs::read_to_string(path).map_err(|source| ConsoleError::Io {
            path: path.into(),
            source,
        })?;
        let config: MissionConfig =
            toml::from_str(&text).map_err(|e| ConsoleError::MissionFile {
                path: path.into(),
                message: e.to_string().replace('\n', " "),
            })?;
        config.validate()?;
        Ok(config)
    }

    /// Checks ranges.
    pub fn validate(&self) -> Result<(), ConsoleError> {
        let field = |f: &str, m: String| ConsoleError::Field {
            field: f.into(),
            message: m,
        };
        if !(self.speed.is_finite() && self.speed > 0.0 && self.speed <= 1000.0) {
            return Err(field(
                "speed",
                format!("found {}, expected 0 < speed ≤ 1000", self.speed),
            ));
        }
        if !(0.0..=1.0).contains(&self.slip_probability) {
            return Err(field(
                "slip_probability",
                format!("found {}, expected a probability", self.slip_probability),
            ));
        }
        if self.weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return Err(field(
                "weights",
                "expected three non-negative numbers".into(),
            ));
        }
        if !(self.minutes.is_finite() && self.minutes > 0.0) {
            return Err(field(
                "minutes",
                format!("found {}, expected > 0", self.minutes),
            ));
        }
        if usar_sim::RobotSpec::preset(&self.team_robot).is_none() {
            return Err(field(
                "team_robot",
                format!("found {:?}, expected crawler or wheeled", self.team_robot),
            ));
        }
        if !(self.floor_cell_m2.is_finite() && (0.25..=16.0).contains(&self.floor_cell_m2)) {
            return Err(field(
                "floor_cell_m2",
                format!("found {}, expected 0.25 to 16 m²", self.floor_cell_m2),
            ));
        }
        if usar_team::criteria::Hypothesis::named(&self.hypothesis).is_none() {
            return Err(field(
                "hypothesis",
                format!("found {:?}, expected big or small", self.hypothesis),
            ));
        }
        if crate::team_hook::strategy(&self.strategy).is_none() {
            return Err(field(
                "strategy",
                format!(
                    "found {:?}, expected random, distance, d-mcdm or s-mcdm",
                    self.strategy
                ),
            ));
        }
        Ok(())
    }
}

/// The server's options.
#[derive(Clone, Debug)]
pub struct ConsoleConfig {
    pub mission: MissionConfig,
    pub bind: SocketAddr,
    /// The access token; a random one when absent (allowed on loopback only).
    pub token: Option<String>,
}

impl ConsoleConfig {
    /// On 127.0.0.1, a free port, a random token.
    pub fn local(mission: MissionConfig) -> Self {
        Self {
            mission,
            bind: SocketAddr::from(([127, 0, 0, 1], 0)),
            token: None,
        }
    }
}

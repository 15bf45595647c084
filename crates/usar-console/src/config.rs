//! What a console runs and where it listens: the mission file (TOML) and the server options
//! (address, access token, allowed origins, limits).

use serde::Deserialize;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::time::Duration;
use usar_world::Scene;

/// The environment variable `usar console` takes the access token from when neither `--token`
/// nor `--token-file` is given (a command line shows in `ps`; the environment does not).
pub const TOKEN_ENV: &str = "USAR_CONSOLE_TOKEN";

/// The shortest access token accepted on a non-loopback address, characters.
pub const MIN_OPEN_TOKEN_CHARS: usize = 24;
/// The fewest different characters such a token must have.
pub const MIN_OPEN_TOKEN_DISTINCT: usize = 10;
/// The longest access token, characters.
pub const MAX_TOKEN_CHARS: usize = 256;
/// The largest mission file read, bytes (a mission file is a few lines).
pub const MAX_MISSION_FILE_BYTES: u64 = 1 << 20;
/// The most team robots a mission may have.
pub const MAX_TEAM_ROBOTS: usize = 32;
/// The longest team mission, simulated minutes (a week).
pub const MAX_MINUTES: f64 = 7.0 * 24.0 * 60.0;

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
        "--bind {0}: not a loopback address; serving the console beyond this machine needs an explicit access token (--token-file PATH, USAR_CONSOLE_TOKEN or --token) of at least 24 characters with at least 10 different ones"
    )]
    OpenBindWithoutToken(SocketAddr),
    /// A non-loopback address with a token too easy to guess.
    #[error(
        "--bind {0}: not a loopback address, and the access token is too weak: it needs at least 24 characters with at least 10 different ones (e.g. `openssl rand -hex 16`)"
    )]
    WeakToken(SocketAddr),
    /// The token is unusable (empty, too long, spaces or control characters).
    #[error("access token: {0}")]
    Token(String),
    /// The token file could not be read or holds no token.
    #[error("--token-file {path}: {message}")]
    TokenFile { path: PathBuf, message: String },
    /// An `--allow-origin` value that is not an origin.
    #[error("--allow-origin {origin}: {message}")]
    AllowOrigin { origin: String, message: String },
    /// A server limit out of range.
    #[error("{name}: {message}")]
    Limit { name: String, message: String },
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
    /// Reads a mission file and checks every field (unknown fields are refused) before
    /// anything is set up; an error names the file and the field.
    pub fn from_file(path: &Path) -> Result<Self, ConsoleError> {
        let io = |source| ConsoleError::Io {
            path: path.into(),
            source,
        };
        let size = std::fs::metadata(path).map_err(io)?.len();
        if size > MAX_MISSION_FILE_BYTES {
            return Err(ConsoleError::MissionFile {
                path: path.into(),
                message: format!(
                    "{size} bytes; a mission file is at most {MAX_MISSION_FILE_BYTES} bytes"
                ),
            });
        }
        let text = std::fs::read_to_string(path).map_err(io)?;
        let config: MissionConfig =
            toml::from_str(&text).map_err(|e| ConsoleError::MissionFile {
                path: path.into(),
                message: e.to_string().replace('\n', " "),
            })?;
        config.validate().map_err(|e| match e {
            ConsoleError::Field { field, message } => ConsoleError::MissionFile {
                path: path.into(),
                message: format!("field `{field}`: {message}"),
            },
            other => other,
        })?;
        Ok(config)
    }

    /// Checks every value's range (before anything is allocated or trained).
    pub fn validate(&self) -> Result<(), ConsoleError> {
        let field = |f: &str, m: String| ConsoleError::Field {
            field: f.into(),
            message: m,
        };
        if !(1..=MAX_TEAM_ROBOTS).contains(&self.team_robots) {
            return Err(field(
                "team_robots",
                format!(
                    "found {}, expected 1 to {MAX_TEAM_ROBOTS}",
                    self.team_robots
                ),
            ));
        }
        if let Err(e) = usar_rescue::training::check_trials(self.train_trials) {
            return Err(field("train_trials", e.problem()));
        }
        if !(1..=100).contains(&self.stuck_after_slips) {
            return Err(field(
                "stuck_after_slips",
                format!("found {}, expected 1 to 100", self.stuck_after_slips),
            ));
        }
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
        if self
            .weights
            .iter()
            .any(|w| !(w.is_finite() && (0.0..=100.0).contains(w)))
        {
            return Err(field(
                "weights",
                format!(
                    "found {:?}, expected three numbers from 0 to 100",
                    self.weights
                ),
            ));
        }
        if !(self.minutes.is_finite() && self.minutes > 0.0 && self.minutes <= MAX_MINUTES) {
            return Err(field(
                "minutes",
                format!(
                    "found {}, expected 0 < minutes ≤ {MAX_MINUTES} (a week)",
                    self.minutes
                ),
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

/// What one console lets its clients take: connections, time and authentication attempts.
#[derive(Clone, Debug, PartialEq)]
pub struct ConsoleLimits {
    /// Concurrent TCP connections (page loads, API calls, WebSockets); one more is answered
    /// `503 Service Unavailable` and closed. Default 256.
    pub max_connections: usize,
    /// How long a plain HTTP connection may last (it carries one request: the server answers
    /// `Connection: close`); a WebSocket is exempt once upgraded. Default 30 s.
    pub http_deadline: Duration,
    /// How long a WebSocket may stay without the access token (`?token=` or an `auth`
    /// message); then it is closed with code 1008. Default 5 s.
    pub auth_deadline: Duration,
    /// Failed `auth` attempts one WebSocket may make; it is closed (1008) at the last. Default 3.
    pub auth_failures_per_connection: u32,
    /// Failed attempts (WebSocket `auth` or `?token=`, HTTP `Bearer`) one peer address may make
    /// within `auth_window` (IPv6: per /64); then every attempt from it, right or wrong, is
    /// refused (HTTP 429) until the window has passed. Default 10.
    pub auth_failures_per_peer: u32,
    /// See `auth_failures_per_peer`. Default 60 s.
    pub auth_window: Duration,
}

impl Default for ConsoleLimits {
    fn default() -> Self {
        Self {
            max_connections: 256,
            http_deadline: Duration::from_secs(30),
            auth_deadline: Duration::from_secs(5),
            auth_failures_per_connection: 3,
            auth_failures_per_peer: 10,
            auth_window: Duration::from_secs(60),
        }
    }
}

/// The server's options.
#[derive(Clone, Debug)]
pub struct ConsoleConfig {
    pub mission: MissionConfig,
    pub bind: SocketAddr,
    /// The access token; a random one when absent (allowed on loopback only). On a non-loopback
    /// address it needs at least [`MIN_OPEN_TOKEN_CHARS`] characters with at least
    /// [`MIN_OPEN_TOKEN_DISTINCT`] different ones.
    pub token: Option<String>,
    /// Origins (`scheme://host[:port]`) besides the console's own whose pages may use it, e.g.
    /// a reverse proxy's `https://console.example.org`; their hosts are also accepted in `Host`.
    /// The console's own: `http://` + the bound address, and on loopback `localhost`,
    /// `127.0.0.1` and `[::1]` at its port (on 0.0.0.0 / `::`, any IP address at its port).
    pub allow_origins: Vec<String>,
    pub limits: ConsoleLimits,
}

impl ConsoleConfig {
    /// On 127.0.0.1, a free port, a random token, default limits.
    pub fn local(mission: MissionConfig) -> Self {
        Self {
            mission,
            bind: SocketAddr::from(([127, 0, 0, 1], 0)),
            token: None,
            allow_origins: Vec::new(),
            limits: ConsoleLimits::default(),
        }
    }

    /// Checks the server options (the mission is checked when it is set up): a usable token,
    /// a strong one beyond loopback, well-formed origins, limits above zero.
    pub fn validate(&self) -> Result<(), ConsoleError> {
        match &self.token {
            Some(t) => {
                check_token(t)?;
                if !self.bind.ip().is_loopback() && !strong_token(t) {
                    return Err(ConsoleError::WeakToken(self.bind));
                }
            }
            None if !self.bind.ip().is_loopback() => {
                return Err(ConsoleError::OpenBindWithoutToken(self.bind));
            }
            None => {}
        }
        for origin in &self.allow_origins {
            crate::guard::parse_origin(origin).map_err(|message| ConsoleError::AllowOrigin {
                origin: origin.clone(),
                message,
            })?;
        }
        let l = &self.limits;
        let limit = |name: &str, message: &str| ConsoleError::Limit {
            name: name.into(),
            message: message.into(),
        };
        if !(1..=100_000).contains(&l.max_connections) {
            return Err(limit(
                "--max-connections",
                &format!("found {}, expected 1 to 100000", l.max_connections),
            ));
        }
        if l.auth_failures_per_connection == 0 || l.auth_failures_per_peer == 0 {
            return Err(limit(
                "auth failures",
                "expected at least one failed attempt per connection and per peer",
            ));
        }
        if [l.http_deadline, l.auth_deadline, l.auth_window]
            .iter()
            .any(|d| d.is_zero())
        {
            return Err(limit("deadlines", "expected durations above zero"));
        }
        Ok(())
    }
}

/// A token any console accepts: 1 to [`MAX_TOKEN_CHARS`] characters, none of them white space
/// or control characters.
fn check_token(token: &str) -> Result<(), ConsoleError> {
    if token.is_empty() {
        return Err(ConsoleError::Token(
            "empty; expected a secret string".into(),
        ));
    }
    if token.chars().count() > MAX_TOKEN_CHARS {
        return Err(ConsoleError::Token(format!(
            "longer than {MAX_TOKEN_CHARS} characters"
        )));
    }
    if token.chars().any(|c| c.is_whitespace() || c.is_control()) {
        return Err(ConsoleError::Token(
            "contains white space or control characters".into(),
        ));
    }
    Ok(())
}

/// At least [`MIN_OPEN_TOKEN_CHARS`] characters with at least [`MIN_OPEN_TOKEN_DISTINCT`]
/// different ones (a 32-digit random hex token has about 14).
pub fn strong_token(token: &str) -> bool {
    let distinct: std::collections::BTreeSet<char> = token.chars().collect();
    token.chars().count() >= MIN_OPEN_TOKEN_CHARS && distinct.len() >= MIN_OPEN_TOKEN_DISTINCT
}

/// The token in a file: its content without the line break at its end (at most 4 KiB).
pub fn read_token_file(path: &Path) -> Result<String, ConsoleError> {
    let fail = |message: String| ConsoleError::TokenFile {
        path: path.into(),
        message,
    };
    let size = std::fs::metadata(path)
        .map_err(|e| fail(e.to_string()))?
        .len();
    if size > 4096 {
        return Err(fail(format!(
            "{size} bytes; expected a token of at most {MAX_TOKEN_CHARS} characters"
        )));
    }
    let text = std::fs::read_to_string(path).map_err(|e| fail(e.to_string()))?;
    let token = text.trim_end_matches(['\r', '\n']);
    if token.is_empty() {
        return Err(fail("empty; expected the token on the first line".into()));
    }
    if token.contains(['\r', '\n']) {
        return Err(fail("more than one line; expected the token alone".into()));
    }
    Ok(token.to_string())
}

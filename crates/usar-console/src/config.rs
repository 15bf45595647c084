//! What a console runs and where it listens: the mission file (TOML) and the server options
//! (address, access token, allowed origins, limits).

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
    /// The scene could not be read or generated.
    #[error("scene {spec}: {message}")]
    Scene { spec: String, message: String },
    /// The mission could not be set up.
    #[error(transparent)]
    Mission(#[from] usar_mission::MissionError),
    /// The recording could not be started.
    #[error("--record {path}: {message}")]
    Record { path: PathBuf, message: String },
}

impl ConsoleError {
    /// Whether the console's input (its options, mission file or scene) is at fault rather
    /// than the machine (an address in use, a failed set-up thread).
    pub fn is_input(&self) -> bool {
        match self {
            ConsoleError::Bind { .. } => false,
            ConsoleError::Mission(e) => e.is_input(),
            _ => true,
        }
    }
}

/// What the console runs: a mission file of `usar mission run` ([`usar_mission::MissionConfig`],
/// `docs/mission-format.md`) on its seed, at a pace. A person at the console is the mission's
/// operator: every hand-off waits for their answer.
#[derive(Clone, Debug)]
pub struct MissionConfig {
    pub mission: usar_mission::MissionConfig,
    /// The seed of every random stream of the run.
    pub seed: u64,
    /// Simulated seconds per wall-clock second (0 < speed ≤ 1000; default 1).
    pub speed: f64,
    /// The scene; when absent, `mission.scene` names a generator (with `mission.scene_seed`) or
    /// a file.
    pub scene: Option<Scene>,
    /// Record the mission into this MCAP file ([`usar_record`]); it is complete once the
    /// mission has ended (its time limit, or the console stopped).
    pub record: Option<PathBuf>,
}

impl Default for MissionConfig {
    fn default() -> Self {
        Self {
            mission: usar_mission::MissionConfig::default(),
            seed: 1,
            speed: 1.0,
            scene: None,
            record: None,
        }
    }
}

fn field_error(field: &str, message: String) -> ConsoleError {
    ConsoleError::Field {
        field: field.into(),
        message,
    }
}

impl MissionConfig {
    /// Reads a mission file (at most [`MAX_MISSION_FILE_BYTES`]; unknown fields are refused);
    /// an error names the file and the field or line.
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
        let mission = toml::from_str(&text).map_err(|e| ConsoleError::MissionFile {
            path: path.into(),
            message: e.to_string().replace('\n', " "),
        })?;
        let config = Self {
            mission,
            ..Self::default()
        };
        config.validate().map_err(|e| ConsoleError::MissionFile {
            path: path.into(),
            message: match e {
                ConsoleError::Field { field, message } => format!("field `{field}`: {message}"),
                other => other.to_string(),
            },
        })?;
        Ok(config)
    }

    /// Checks every value before anything is set up or trained: the mission's own
    /// ([`usar_mission::MissionConfig::check`]) and what the console adds (its pace, a cap on
    /// the team).
    pub fn validate(&self) -> Result<(), ConsoleError> {
        let field = field_error;
        let speed = self.speed;
        if !(speed.is_finite() && speed > 0.0 && speed <= 1000.0) {
            return Err(field(
                "speed",
                format!("found {speed}, expected 0 < speed ≤ 1000"),
            ));
        }
        let robots = self.mission.team.robots;
        if !(1..=MAX_TEAM_ROBOTS).contains(&robots) {
            return Err(field(
                "team.robots",
                format!("found {robots}, expected 1 to {MAX_TEAM_ROBOTS}"),
            ));
        }
        self.mission.check().map_err(|e| match e {
            usar_mission::MissionError::Config { field, message } => field_error(&field, message),
            other => other.into(),
        })
    }

    /// The scene: the one given, or the one `mission.scene` names.
    pub fn scene(&self) -> Result<Scene, ConsoleError> {
        if let Some(s) = &self.scene {
            return Ok(s.clone());
        }
        let m = &self.mission;
        usar_world::io::source::load_scene(&m.scene, m.scene_seed, &Default::default()).map_err(
            |e| ConsoleError::Scene {
                spec: m.scene.clone(),
                message: e.to_string(),
            },
        )
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

//! `usar console`: the operator console (a live mission served to a browser), and
//! `usar console bench`: many viewers against it.

use crate::cli::ImageArgs;
use crate::failure::{CmdResult, Failure, bad_input};
use crate::scene_source;
use clap::{Args, Subcommand};
use std::net::SocketAddr;
use std::path::PathBuf;
use usar_console::{ConsoleConfig, ConsoleError, ConsoleLimits, MissionConfig, TOKEN_ENV};

/// Run the whole mission live and serve the operator console to a browser: a team exploring
/// with S-MCDM, a crawler building a BTM and a MAXQ semi-autonomous robot on one simulator,
/// with you as their operator (every hand-off waits for your answer).
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct ConsoleArgs {
    #[command(subcommand)]
    pub command: Option<ConsoleCommand>,
    #[command(flatten)]
    pub serve: ConsoleServeArgs,
}

#[derive(Debug, Subcommand)]
pub enum ConsoleCommand {
    /// Measure the simulation's speed and every viewer's updates with many WebSocket viewers
    /// and connections held against the console's limits.
    Bench(ConsoleBenchArgs),
}

#[derive(Debug, Args)]
pub struct ConsoleServeArgs {
    /// The scene (file or generator name); default: the mission file's (the built-in
    /// mission: the generated office floor).
    #[arg(long)]
    pub scene: Option<String>,
    /// Seed of every random stream of the run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// A mission file, as `usar mission run` reads it (docs/mission-format.md: scene, minutes,
    /// [team], [crawler], [rescuer]; its [operator] is you). Unknown fields and out-of-range
    /// values are refused before anything starts.
    #[arg(long)]
    pub mission: Option<PathBuf>,
    /// Simulated minutes (default: the mission file's).
    #[arg(long)]
    pub minutes: Option<f64>,
    /// Where to listen (ADDRESS:PORT). A non-loopback address needs an access token of at least
    /// 24 characters with at least 10 different ones (--token-file, USAR_CONSOLE_TOKEN or
    /// --token).
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub bind: String,
    /// The access token for control and the live view. Visible to other users in `ps`: prefer
    /// --token-file or the environment variable USAR_CONSOLE_TOKEN. Default: a random one,
    /// printed (loopback only).
    #[arg(long, conflicts_with = "token_file")]
    pub token: Option<String>,
    /// Read the access token from this file (its first line; a final line break is ignored).
    #[arg(long, value_name = "PATH")]
    pub token_file: Option<PathBuf>,
    /// Also serve pages from this origin (SCHEME://HOST[:PORT], e.g. a reverse proxy's
    /// https://console.example.org); repeatable. Requests whose Origin or Host is neither the
    /// console's own address (on loopback also localhost, 127.0.0.1 and [::1] at its port) nor
    /// an allowed origin are refused with 403, against other sites' pages and DNS rebinding.
    #[arg(long, value_name = "ORIGIN")]
    pub allow_origin: Vec<String>,
    /// Concurrent connections (page loads, API calls, WebSockets) served at once; one more is
    /// answered 503. A WebSocket without the token is closed after 5 s, an address with 10
    /// wrong tokens within a minute is refused for the rest of it.
    #[arg(long, default_value_t = ConsoleLimits::default().max_connections)]
    pub max_connections: usize,
    /// A MAXQ policy file for the rescuer (`usar maxq train`); default: the mission file's, or
    /// a short training at start.
    #[arg(long)]
    pub policy: Option<PathBuf>,
    /// Simulated seconds per wall-clock second.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Record the mission into this MCAP file (as `usar mission run --record`); complete once
    /// the mission has ended or the console is stopped (Ctrl-C).
    #[arg(long, value_name = "FILE.mcap")]
    pub record: Option<PathBuf>,
    #[command(flatten)]
    pub image: ImageArgs,
}

#[derive(Debug, Args)]
pub struct ConsoleBenchArgs {
    /// Concurrent WebSocket viewers (with the access token).
    #[arg(long, default_value_t = 50)]
    pub viewers: usize,
    /// Bounded connections held during the second measurement: WebSockets without the token,
    /// half idle until the 5 s auth deadline closes them, half announcing a 1 MiB message that
    /// is refused unread; each reconnects 0.5 s after it was closed. Beyond the connection cap
    /// (256) they are refused with 503.
    #[arg(long, default_value_t = 0)]
    pub connections: usize,
    /// Seconds of each measurement (without clients, then with them).
    #[arg(long, default_value_t = 30.0)]
    pub seconds: f64,
    /// Simulated seconds per wall-clock second.
    #[arg(long, default_value_t = 4.0)]
    pub speed: f64,
    /// A mission file.
    #[arg(long)]
    pub mission: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

fn mission_config(path: Option<&PathBuf>) -> CmdResult<MissionConfig> {
    match path {
        Some(p) => MissionConfig::from_file(p).map_err(failure),
        None => Ok(MissionConfig::default()),
    }
}

/// A console error as the command reports it: bad input (exit 2) unless the machine failed.
fn failure(e: ConsoleError) -> Failure {
    if e.is_input() { bad_input(e) } else { e.into() }
}

pub fn run(args: ConsoleArgs) -> CmdResult {
    match args.command {
        Some(ConsoleCommand::Bench(b)) => bench(b),
        None => serve(args.serve),
    }
}

fn serve(args: ConsoleServeArgs) -> CmdResult {
    let mut mission = mission_config(args.mission.as_ref())?;
    mission.seed = args.seed;
    mission.speed = args.speed;
    mission.record = args.record;
    let m = &mut mission.mission;
    if let Some(minutes) = args.minutes {
        m.minutes = minutes;
    }
    if let Some(policy) = args.policy {
        m.rescuer.policy = policy.display().to_string();
    }
    if let Some(spec) = args.scene {
        m.scene = spec;
    }
    mission.scene = Some(scene_source::load(&m.scene, m.scene_seed, &args.image)?);
    mission.validate().map_err(failure)?;
    let bind: SocketAddr = args.bind.parse().map_err(|e| {
        bad_input(anyhow::anyhow!(
            "--bind {}: {e}; expected ADDRESS:PORT, e.g. 127.0.0.1:8080",
            args.bind
        ))
    })?;
    let (token, source) = access_token(args.token, args.token_file)?;
    let config = ConsoleConfig {
        mission,
        bind,
        token,
        allow_origins: args.allow_origin,
        limits: ConsoleLimits {
            max_connections: args.max_connections,
            ..ConsoleLimits::default()
        },
    };
    usar_console::serve_blocking(config, |console| match &source {
        None => {
            println!("usar console: {}", console.url());
            println!("access token: {}", console.token);
            println!("(Ctrl-C to stop)");
        }
        Some(source) => {
            println!("usar console: http://{}/", console.addr);
            println!(
                "access token: from {source}; open http://{}/?token=TOKEN",
                console.addr
            );
            println!("(Ctrl-C to stop)");
        }
    })
    .map_err(failure)
}

/// The access token and where it came from: --token, --token-file, or USAR_CONSOLE_TOKEN
/// (in that order); none: a random one.
fn access_token(
    flag: Option<String>,
    file: Option<PathBuf>,
) -> CmdResult<(Option<String>, Option<String>)> {
    if let Some(token) = flag {
        return Ok((Some(token), Some("--token".into())));
    }
    if let Some(path) = file {
        let token = usar_console::read_token_file(&path).map_err(bad_input)?;
        return Ok((
            Some(token),
            Some(format!("--token-file {}", path.display())),
        ));
    }
    match std::env::var(TOKEN_ENV) {
        Ok(token) => Ok((Some(token), Some(TOKEN_ENV.into()))),
        Err(std::env::VarError::NotPresent) => Ok((None, None)),
        Err(std::env::VarError::NotUnicode(_)) => Err(bad_input(anyhow::anyhow!(
            "{TOKEN_ENV}: not valid UTF-8; expected the access token"
        ))),
    }
}

fn bench(args: ConsoleBenchArgs) -> CmdResult {
    let mut mission = mission_config(args.mission.as_ref())?;
    mission.speed = args.speed;
    mission.validate().map_err(failure)?;
    if args.viewers + args.connections == 0
        || args.viewers > 10_000
        || args.connections > 10_000
        || !(args.seconds.is_finite() && (1.0..=86_400.0).contains(&args.seconds))
    {
        return Err(bad_input(anyhow::anyhow!(
            "--viewers and --connections: 0 to 10000, not both 0; --seconds: 1 to 86400"
        )));
    }
    let report =
        usar_console::bench::run_blocking(mission, args.viewers, args.connections, args.seconds)
            .map_err(failure)?;
    if args.json {
        return super::print_json(&report);
    }
    println!(
        "{} viewers, {} bounded connections, {} s: speed {:.3}× without them, {:.3}× with ({:+.1} %), target {}×",
        report.viewers,
        report.connections,
        report.seconds,
        report.speed_without_viewers,
        report.speed_with_viewers,
        100.0 * report.speed_change,
        report.target_speed
    );
    println!(
        "frames per viewer per second: min {:.1}, mean {:.1}, max {:.1}; longest gap {:.2} s; {} of {} viewers received frames every second",
        report.min_frames_per_s,
        report.mean_frames_per_s,
        report.max_frames_per_s,
        report.max_gap_s,
        report.viewers_receiving_every_second,
        report.viewers
    );
    if report.connections > 0 {
        println!(
            "bounded connections: {} upgrades accepted, {} refused with 503, {} closed by the server",
            report.connections_upgraded,
            report.connections_refused,
            report.connections_closed_by_server
        );
    }
    Ok(())
}

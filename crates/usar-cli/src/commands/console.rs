//! `usar console`: the operator console (a live mission served to a browser), and
//! `usar console bench`: many viewers against it.

use crate::cli::ImageArgs;
use crate::failure::{CmdResult, bad_input};
use crate::scene_source;
use clap::{Args, Subcommand};
use std::net::SocketAddr;
use std::path::PathBuf;
use usar_console::{ConsoleConfig, MissionConfig};

/// Start a live simulated mission and serve the operator console to a browser: a MAXQ
/// semi-autonomous robot that hands off to you, a team exploring with S-MCDM, a BTM being built.
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
    /// Measure the simulation's speed and every viewer's updates with many WebSocket viewers.
    Bench(ConsoleBenchArgs),
}

#[derive(Debug, Args)]
pub struct ConsoleServeArgs {
    /// The scene (file or generator name); default: a generated rubble floor.
    #[arg(long)]
    pub scene: Option<String>,
    /// Seed of the generated scene and of every random stream.
    #[arg(long)]
    pub seed: Option<u64>,
    /// A mission file (TOML: team_robots, team_robot, strategy, hypothesis, speed, train_trials,
    /// floor_cell_m2, …; see the crate usar-console, `MissionConfig`).
    #[arg(long)]
    pub mission: Option<PathBuf>,
    /// Where to listen. A non-loopback address needs --token.
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub bind: String,
    /// The access token for control (default: a random one, printed).
    #[arg(long)]
    pub token: Option<String>,
    /// A MAXQ policy file (`usar maxq train`); default: a short training at start.
    #[arg(long)]
    pub policy: Option<PathBuf>,
    /// Simulated seconds per wall-clock second.
    #[arg(long)]
    pub speed: Option<f64>,
    #[command(flatten)]
    pub image: ImageArgs,
}

#[derive(Debug, Args)]
pub struct ConsoleBenchArgs {
    /// Concurrent WebSocket viewers.
    #[arg(long, default_value_t = 50)]
    pub viewers: usize,
    /// Seconds of each measurement (without viewers, then with them).
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
        Some(p) => MissionConfig::from_file(p).map_err(bad_input),
        None => Ok(MissionConfig::default()),
    }
}

pub fn run(args: ConsoleArgs) -> CmdResult {
    match args.command {
        Some(ConsoleCommand::Bench(b)) => bench(b),
        None => serve(args.serve),
    }
}

fn serve(args: ConsoleServeArgs) -> CmdResult {
    let mut mission = mission_config(args.mission.as_ref())?;
    if let Some(seed) = args.seed {
        mission.seed = seed;
    }
    if let Some(speed) = args.speed {
        mission.speed = speed;
    }
    if let Some(policy) = args.policy {
        mission.policy = Some(policy);
    }
    if let Some(spec) = &args.scene {
        mission.scene = Some(scene_source::load(spec, mission.seed, &args.image)?);
    }
    mission.validate().map_err(bad_input)?;
    let bind: SocketAddr = args.bind.parse().map_err(|e| {
        bad_input(anyhow::anyhow!(
            "--bind {}: {e}; expected ADDRESS:PORT, e.g. 127.0.0.1:8080",
            args.bind
        ))
    })?;
    let config = ConsoleConfig {
        mission,
        bind,
        token: args.token,
    };
    usar_console::serve_blocking(config, |console| {
        println!("usar console: {}", console.url());
        println!("access token: {}", console.token);
        println!("(Ctrl-C to stop)");
    })
    .map_err(bad_input)
}

fn bench(args: ConsoleBenchArgs) -> CmdResult {
    let mut mission = mission_config(args.mission.as_ref())?;
    mission.speed = args.speed;
    mission.validate().map_err(bad_input)?;
    if args.viewers == 0 || !(args.seconds.is_finite() && args.seconds >= 1.0) {
        return Err(bad_input(anyhow::anyhow!(
            "--viewers must be at least 1 and --seconds at least 1"
        )));
    }
    let report = usar_console::bench::run_blocking(mission, args.viewers, args.seconds)
        .map_err(bad_input)?;
    if args.json {
        return super::print_json(&report);
    }
    println!(
        "{} viewers, {} s: speed {:.3}× without viewers, {:.3}× with ({:+.1} %), target {}×",
        report.viewers,
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
    Ok(())
}

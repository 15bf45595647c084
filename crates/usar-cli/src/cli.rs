//! Command-line arguments.

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// usar — semi-autonomous robotic urban search and rescue: scenes, robots, maps, planners,
/// exploration.
///
/// SCENE arguments accept a usar scene file (.json), a ROS map_server map (.yaml), a bare map
/// image (.pgm/.png, with --resolution), a MovingAI map (.map), or the name of a generator
/// (rubble, office, mall, course) used with --seed.
///
/// Exit codes: 0 success, 1 internal failure, 2 bad input (the message names the file and the
/// problem).
///
/// Inputs are bounded: a file may not make usar allocate or work past the limits below (grid
/// cells, file size, laser beams, training trials); each is checked before anything is
/// allocated, and every command takes the options to raise them.
#[derive(Debug, Parser)]
#[command(name = "usar", version, about, long_about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Limits on what an input may make usar do (see `usar_world::limits`).
#[derive(Debug, Args)]
#[command(next_help_heading = "Input limits")]
pub struct LimitArgs {
    /// Most cells of a grid read from a file (a map image, a scene, a MovingAI map).
    #[arg(long, global = true, value_name = "N", default_value_t = usar_world::limits::Limits::DEFAULT.max_cells)]
    pub max_cells: u64,
    /// Most MiB read from one input file.
    #[arg(long, global = true, value_name = "MIB", default_value_t = usar_world::limits::Limits::DEFAULT.max_file_bytes >> 20)]
    pub max_file_mb: u64,
    /// Most beams of one laser or depth sensor in a robot file.
    #[arg(long, global = true, value_name = "N", default_value_t = usar_world::limits::Limits::DEFAULT.max_beams)]
    pub max_beams: u64,
    /// Most trials of one MAXQ training run.
    #[arg(long, global = true, value_name = "N", default_value_t = usar_world::limits::Limits::DEFAULT.max_trials)]
    pub max_trials: u64,
}

impl LimitArgs {
    pub fn limits(&self) -> usar_world::limits::Limits {
        usar_world::limits::Limits {
            max_cells: self.max_cells,
            max_file_bytes: self.max_file_mb.saturating_mul(1 << 20),
            max_beams: self.max_beams,
            max_trials: self.max_trials,
        }
    }
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Generate, import, export, render and describe scenes.
    #[command(subcommand)]
    Scene(SceneCommand),
    /// Plan paths: check a MovingAI scenario file, or plan from A to B on a scene.
    Plan(PlanArgs),
    /// Explore a scene with a team of wheeled robots going to their nearest frontiers.
    Explore(ExploreArgs),
    /// Paper 002's semantically-informed multirobot exploration (strategies, coordination,
    /// relevant area).
    #[command(subcommand)]
    Team(TeamCommand),
    /// The whole mission in one world: paper 002's wheeled team, paper 004's crawler (its BTM
    /// shared over the radio) and paper 000's MAXQ robot on one physics, hand-offs to one
    /// operator (`usar mission run --help`).
    #[command(subcommand)]
    Mission(MissionCommand),
    /// Run the main job on built-in defaults: the whole mission on a generated office floor —
    /// four wheeled robots (S-MCDM + MRv1), a crawler sharing its BTM, a MAXQ robot searching a
    /// zone, one operator answering hand-offs; writes a report folder (map, victims, hand-offs,
    /// coverage over time, summary.json).
    Demo(DemoArgs),
    /// Measure the speed of the hot loops (laser scans, A*, distance fields, frontiers).
    Bench(BenchArgs),
    /// Experiments: run campaigns (resumable, parallel, shardable), merge shards, report
    /// statistics and plots, export CSV.
    #[command(subcommand)]
    Campaign(CampaignCommand),
    /// Paper 000's hierarchical reinforcement learning (MAXQ-Q).
    #[command(subcommand)]
    Maxq(MaxqCommand),
    /// Paper 004's Behavioral Trace Maps: show, export, plan on and merge topological maps.
    /// A BTM file is a BTM database (.sqlite), its JSON export (.json) or compact binary (.btmb).
    /// Every map read is checked (finite, non-negative measures, named kinds, links between
    /// existing nodes, unique ids); a bad one is refused with exit 2.
    #[command(subcommand)]
    Btm(BtmCommand),
    /// The operator console: a live mission in the browser (`usar console --help`).
    Console(crate::commands::console::ConsoleArgs),
    /// Real robot logs — CARMEN (.log/.clf, gzipped or not), DP-SLAM, Thrun's O/L logs,
    /// rosbag2 in MCAP storage: what a log holds, and the log as ROS 2 messages in MCAP.
    #[command(subcommand)]
    Log(LogCommand),
    /// Occupancy maps from real robot logs, with scan matching.
    #[command(subcommand)]
    Map(MapCommand),
    /// A live ROS 2 bridge (pure Rust, no ROS installation; built with `--features ros2`): a
    /// simulated robot for RViz2 or Nav2, and usar's explorer and BTM builder as ROS 2 nodes.
    /// Joins domain $ROS_DOMAIN_ID (or --domain); Ctrl-C or --seconds stops a node, which then
    /// prints what it did as JSON.
    #[command(subcommand)]
    Ros2(Ros2Command),
}

#[derive(Debug, Subcommand)]
pub enum Ros2Command {
    /// A simulated robot on a scene: publishes /scan (sensor QoS), /odom, /tf, /tf_static,
    /// /map (transient local: the scene, as map_server would) and /clock; obeys
    /// geometry_msgs/Twist on /cmd_vel (a robot without a command for 0.5 s stops).
    Sim(Ros2SimArgs),
    /// usar's frontier explorer on a robot's /scan and /odom: publishes its goal
    /// (geometry_msgs/PoseStamped on /goal_pose, for Nav2), its /map and the frontier
    /// candidates as markers (/markers).
    Explore(Ros2ExploreArgs),
    /// The passive BTM builder on a robot's /scan and /odom: publishes the BTM as markers
    /// (/markers) and writes it to a BTM database.
    Btm(Ros2BtmArgs),
}

#[derive(Debug, Args)]
pub struct Ros2Args {
    /// DDS domain; default: $ROS_DOMAIN_ID, else 0.
    #[arg(long)]
    pub domain: Option<u16>,
    /// Only on 127.0.0.1 (also when $ROS_LOCALHOST_ONLY=1): discovery by unicast on loopback.
    #[arg(long)]
    pub localhost: bool,
    /// Rename a topic: FROM:=TO (scan, odom, tf, tf_static, map, clock, cmd_vel, goal_pose,
    /// markers), repeatable, e.g. --remap scan:=/robot1/scan.
    #[arg(long = "remap", value_name = "FROM:=TO")]
    pub remaps: Vec<String>,
    /// Stop after this many seconds (default: at Ctrl-C).
    #[arg(long)]
    pub seconds: Option<f64>,
}

#[derive(Debug, Args)]
pub struct Ros2SimArgs {
    /// The scene (file, map or generator name); the robot starts at its first start pose.
    #[arg(long, default_value = "office")]
    pub scene: String,
    #[arg(long, default_value_t = 1)]
    pub scene_seed: u64,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Robot model: wheeled, crawler or a robot TOML file.
    #[arg(long, default_value = "wheeled")]
    pub robot: String,
    /// Seed of the sensor and odometry noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Simulated seconds per wall second.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    #[command(flatten)]
    pub ros: Ros2Args,
}

#[derive(Debug, Args)]
pub struct Ros2ExploreArgs {
    /// Side of the explorer's square map, metres (centred where the robot starts).
    #[arg(long, default_value_t = 100.0)]
    pub size: f64,
    /// Map cell, metres.
    #[arg(long, default_value_t = 0.05)]
    pub resolution: f64,
    /// Odometry alone (no correlative scan matching).
    #[arg(long)]
    pub no_scan_matching: bool,
    #[command(flatten)]
    pub ros: Ros2Args,
}

#[derive(Debug, Args)]
pub struct Ros2BtmArgs {
    /// The BTM database to write (.sqlite); written as FILE.partial and named when the node
    /// stops.
    #[arg(long)]
    pub out: PathBuf,
    /// Robot model whose width makes a passage: wheeled, crawler or a robot TOML file.
    #[arg(long, default_value = "wheeled")]
    pub robot: String,
    /// Odometry alone (no correlative scan matching).
    #[arg(long)]
    pub no_scan_matching: bool,
    #[command(flatten)]
    pub ros: Ros2Args,
}

#[derive(Debug, Subcommand)]
pub enum LogCommand {
    /// Read a log into timed scans and odometry and say what it holds (format, beams, field of
    /// view, the no-return value stated or found, times, odometry path); with --out, write it
    /// as an MCAP file of ROS 2 messages (/scan, /odom, /tf, /tf_static, /clock) for Foxglove.
    Import(LogImportArgs),
}

#[derive(Debug, Args)]
pub struct LogImportArgs {
    /// The log: a text log, an .mcap file or a rosbag2 folder.
    pub log: PathBuf,
    /// Its format (carmen, dpslam, thrun, rosbag2); default: told by its content.
    #[arg(long)]
    pub format: Option<String>,
    /// Write the log as ROS 2 messages into this MCAP file.
    #[arg(long, value_name = "FILE.mcap")]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Subcommand)]
pub enum MapCommand {
    /// Build an occupancy grid from a log: odometry corrected by scan matching, the grid as a
    /// ROS map (map.yaml + map.pgm), pictures of the map with the paths, frontiers and
    /// candidates (map.png) and of its rooms (rooms.png), the trajectory (trajectory.csv) and
    /// the drift figures (summary.json).
    Build(MapBuildArgs),
}

#[derive(Debug, Args)]
pub struct MapBuildArgs {
    /// The log (see `usar log import`).
    #[arg(long, value_name = "LOG")]
    pub from_log: PathBuf,
    /// Its format; default: told by its content.
    #[arg(long)]
    pub format: Option<String>,
    /// Output folder.
    #[arg(long, default_value = "out/map")]
    pub out: PathBuf,
    /// Cell size, metres.
    #[arg(long, default_value_t = 0.05)]
    pub resolution: f64,
    /// Returns farther than this are drawn as free space up to it, metres.
    #[arg(long, default_value_t = 20.0)]
    pub usable_range: f64,
    /// correlative (Olson 2009, the default), icp (the simulated robots' matcher) or odometry
    /// (no correction).
    #[arg(long, default_value = "correlative")]
    pub matcher: String,
    /// Readings at or above this are no return, metres; default: the log's stated maximum, or
    /// the saturation spike found in its readings.
    #[arg(long)]
    pub no_return: Option<f64>,
    /// Only the scans up to this time, seconds: the map, frontiers and candidates as they
    /// were then.
    #[arg(long)]
    pub until: Option<f64>,
    /// Frontiers shorter than this are not shown as candidates, metres.
    #[arg(long, default_value_t = 0.5)]
    pub min_frontier: f64,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Subcommand)]
pub enum BtmCommand {
    /// Build a BTM autonomously: one robot explores the scene from its first start pose (or
    /// --start) with the paper-004 behaviours until no un-searched link is left, writing every
    /// node and link to an SQLite database as it drives.
    Build(BtmBuildArgs),
    /// Draw a BTM (nodes by kind, searched links, un-searched stubs) as PNG or SVG.
    Show(BtmShowArgs),
    /// Print every node and link, or convert to .json / .graphml / .btmb (compact binary) / .sqlite.
    Export(BtmExportArgs),
    /// Find a route on a BTM for a robot: links narrower, steeper or with higher steps than it
    /// can take are never used; exit 3 with the reason when there is no route.
    Plan(BtmPlanArgs),
    /// Join local BTMs of several robots into one global BTM.
    Merge(BtmMergeArgs),
}

#[derive(Debug, Args)]
pub struct BtmBuildArgs {
    /// Scene: a scene file, a map (.yaml, .pgm/.png with --resolution, .map) or a generator
    /// name (course, office, mall, rubble).
    #[arg(long, default_value = "course")]
    pub scene: String,
    /// Instead of driving in a scene: build the BTM passively along the path of a real robot
    /// log (see `usar log import`), its poses from `usar map build`'s scan matching; no
    /// obstacle nodes (a log has no tilted laser). --robot gives the width of a passage.
    #[arg(long, value_name = "LOG", conflicts_with_all = ["scene", "start", "max_minutes", "trace"])]
    pub from_log: Option<PathBuf>,
    /// The log's scan matcher (with --from-log): correlative, icp or odometry.
    #[arg(long, default_value = "correlative", requires = "from_log")]
    pub matcher: String,
    /// Seed of a generated scene (ignored for files).
    #[arg(long, default_value_t = 1)]
    pub scene_seed: u64,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Robot model: crawler, wheeled or a robot TOML file.
    #[arg(long, default_value = "crawler")]
    pub robot: String,
    /// Seed of the sensor and odometry noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Start pose "x,y" or "x,y,theta" (metres, radians) instead of the scene's first one.
    #[arg(long, value_parser = parse_pose, allow_hyphen_values = true)]
    pub start: Option<(f64, f64, f64)>,
    /// Build parameters (TOML; any of the fields listed in docs/btm-format.md, e.g.
    /// configs/btm-real-floor.toml for a cluttered real floor).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Stop after this many simulated minutes even if links are left un-searched.
    #[arg(long)]
    pub max_minutes: Option<f64>,
    /// The BTM database to write (.sqlite). It is written as `FILE.partial` while the robot
    /// drives (each update committed at once) and renamed to FILE when the build ends.
    #[arg(long)]
    pub out: PathBuf,
    /// Also draw the BTM over the scene with the robot's trace (.png or .svg).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Also write the robot's trajectory as CSV: time_s, the estimated and the true pose
    /// (x_m, y_m, theta_rad) and the run mode at every step.
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Record the build into this MCAP file of ROS 2 messages: /clock and /tf (the crawler's
    /// true pose) four times a simulated second; its scan, its own pose estimate and the BTM
    /// so far as markers every second.
    #[arg(long, value_name = "FILE.mcap", conflicts_with = "from_log")]
    pub record: Option<PathBuf>,
    /// Print the build as JSON: `nodes_by_kind`, `links_searched`, `links_unsearched`, every
    /// node and link (fields as `usar btm export --json`), the stop reason, time, distance,
    /// collisions and `bytes` (the map's sizes as .btmb, JSON and SQLite against the grid's).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct BtmShowArgs {
    pub btm: PathBuf,
    /// Draw over this scene (file, map or generator name).
    #[arg(long)]
    pub scene: Option<String>,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Output .png or .svg.
    #[arg(long)]
    pub out: PathBuf,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct BtmExportArgs {
    pub btm: PathBuf,
    /// Write the map to this .json, .graphml, .btmb (compact binary) or .sqlite file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the map as JSON: `nodes_by_kind` (counts by "kind/subtype"), `links_searched`,
    /// `links_unsearched`, every node (`id`, `kind`, `subtype`, `x_m`, `y_m`,
    /// `slope_inclination_rad`, `step_height_m`, `max_robot_inclination_rad`, `operator_note`,
    /// the derived `links` and `link_angles_rad`) and every link (`id`, `start`, `end`,
    /// `searched`, `direction_rad`, `length_m`, `min_width_m`, `max_inclination_rad`,
    /// `max_step_m`); `extra` where a node or link has extension attributes. Metres and
    /// radians; `null` where not measured (`end`: an un-searched link's far end).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct BtmPlanArgs {
    pub btm: PathBuf,
    /// Robot model: crawler, wheeled or a robot TOML file.
    #[arg(long, default_value = "wheeled")]
    pub robot: String,
    /// Start: a node id, or "x,y" in metres (the nearest node).
    #[arg(long, allow_hyphen_values = true)]
    pub from: String,
    /// Goal: a node id, or "x,y" in metres (the nearest node).
    #[arg(long, allow_hyphen_values = true)]
    pub to: String,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct BtmMergeArgs {
    /// The local BTMs.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// The global BTM to write (.sqlite, .json, .graphml or .btmb).
    #[arg(long)]
    pub out: PathBuf,
    /// Nodes of the same kind closer than this are one place, metres.
    #[arg(long, default_value_t = 1.0)]
    pub radius: f64,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Subcommand)]
pub enum MaxqCommand {
    /// Check the MAXQ-Q engine on Dietterich's Taxi domain: trains MAXQ-Q and flat Q with the
    /// same seed and compares their greedy policies with the optimum (value iteration).
    Taxi(MaxqTaxiArgs),
    /// Train paper 000's USAR hierarchy (and flat Q on the same scenes) over random rubble
    /// scenes; write the policy file and the learning curves (Fig. 7a/7b).
    Train(MaxqTrainArgs),
    /// Evaluate a policy on scenes A, B, C × 3 start poses × the 4 weight cases of Table II ×
    /// repetitions: steps, coverage, collisions, victims, hand-offs; ANOVA and paired t-tests.
    Eval(MaxqEvalArgs),
    /// Semi-autonomous vs teleoperated trials of 10 simulated operators (paper 000 §VII-B).
    TeleopStudy(MaxqTeleopArgs),
}

#[derive(Debug, Args)]
pub struct MaxqTrainArgs {
    /// Trials, one random scene each (paper: 1800).
    #[arg(long, default_value_t = 1800)]
    pub trials: u32,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Where to write the policy (JSON, versioned).
    #[arg(long)]
    pub out: PathBuf,
    /// Learning curves: cumulative reward per trial (Fig. 7a); the steps plot (Fig. 7b) is
    /// written beside it with `-steps` added to the name. .png or .svg.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Skip the flat Q-learner.
    #[arg(long)]
    pub no_flat: bool,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct MaxqEvalArgs {
    /// A policy written by `usar maxq train`.
    #[arg(long)]
    pub policy: PathBuf,
    /// Repetitions per (scene, start, weights) (paper: 6).
    #[arg(long, default_value_t = 6)]
    pub reps: u32,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Generator seed of scenes A, B, C.
    #[arg(long, default_value_t = 1)]
    pub scene_seed: u64,
    /// Primitive steps after which a run is cut off.
    #[arg(long, default_value_t = 6000)]
    pub max_steps: u64,
    /// Fig. 9-like bar chart of the steps per scene and weight case (.png or .svg).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Print every run too.
    #[arg(long)]
    pub runs: bool,
    /// Record one run of the design into this MCAP file of ROS 2 messages (the robot's pose
    /// at every primitive step, its cell map and possible victims every 10): run --record-run
    /// in design order (scene, start, weights, repetition), replayed with its own seed.
    #[arg(long, value_name = "FILE.mcap")]
    pub record: Option<PathBuf>,
    /// Which run --record records (0-based, design order).
    #[arg(long, default_value_t = 0, requires = "record")]
    pub record_run: usize,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct MaxqTeleopArgs {
    /// A policy written by `usar maxq train`; without it one is trained first (--trials).
    #[arg(long)]
    pub policy: Option<PathBuf>,
    #[arg(long, default_value_t = 300)]
    pub trials: u32,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Draw Fig. 16 (% explored per participant, both modes) into this .png or .svg file, and
    /// beside it `-victims` (Fig. 17), `-collisions` (Fig. 18) and `-time` (Table III).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct MaxqTaxiArgs {
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Learning episodes per learner.
    #[arg(long, default_value_t = 4000)]
    pub episodes: u64,
    /// Random starts the greedy policies are evaluated on (at least 500 for the check).
    #[arg(long, default_value_t = 1000)]
    pub eval_starts: usize,
    /// Draw the learning curves (greedy return vs episodes) into this .png or .svg file.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Print the report as JSON (with the curve).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Subcommand)]
pub enum CampaignCommand {
    /// Run a campaign file or a built-in preset into a result folder. Runs already in the
    /// folder's database are not redone: run the same command again to resume. One run at a
    /// time uses a folder: a second one is refused at once (exit 2).
    Run(CampaignRunArgs),
    /// Combine the result folders of shards of one campaign into a new folder. A shard still
    /// being run is refused (exit 2).
    Merge(CampaignMergeArgs),
    /// Tables (mean (sd)), the comparisons the campaign asks for, and plots. Reads the runs
    /// finished so far (also during a run); one report at a time writes DIR/report/.
    Report(CampaignReportArgs),
    /// One CSV row per run: factors and final metrics (columns: docs/campaign-format.md).
    Export(CampaignExportArgs),
    /// List the built-in presets and the runners with their factors and metrics.
    List(CampaignListArgs),
    /// Write a SLURM job array for a campaign into DIR/slurm/ (and submit it with --submit):
    /// task K runs shard K of N into DIR/shards/K (a database of its own: SQLite is not safe on
    /// network file systems); a job depending on the array merges them into DIR/merged and
    /// writes its report. Submitting again resumes: finished runs are skipped.
    Slurm(CampaignSlurmArgs),
    /// Where a SLURM submission stands: each shard done, running, partial or missing, and
    /// whether DIR/merged holds the whole design.
    Status(CampaignStatusArgs),
}

#[derive(Debug, Args)]
pub struct CampaignSlurmArgs {
    /// The campaign file (TOML); or use --preset.
    #[arg(required_unless_present = "preset", conflicts_with = "preset")]
    pub file: Option<PathBuf>,
    /// A built-in campaign (see `usar campaign list`).
    #[arg(long)]
    pub preset: Option<String>,
    /// Result folder, on a file system every node sees.
    #[arg(long)]
    pub out: PathBuf,
    /// Array tasks (shards), 1 to 1000.
    #[arg(long)]
    pub tasks: u64,
    /// `#SBATCH --partition`.
    #[arg(long)]
    pub partition: Option<String>,
    /// `#SBATCH --time` of each task, e.g. 02:00:00.
    #[arg(long)]
    pub time: Option<String>,
    /// `#SBATCH --cpus-per-task`: parallel runs within a task.
    #[arg(long, default_value_t = 1)]
    pub cpus_per_task: u32,
    /// Submit with `sbatch` (the array, then the merge with --dependency=afterok).
    #[arg(long)]
    pub submit: bool,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct CampaignStatusArgs {
    /// A folder written by `usar campaign slurm`.
    pub dir: PathBuf,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct CampaignRunArgs {
    /// The campaign file (TOML); or use --preset.
    #[arg(required_unless_present = "preset", conflicts_with = "preset")]
    pub file: Option<PathBuf>,
    /// A built-in campaign (see `usar campaign list`), e.g. smoke.
    #[arg(long)]
    pub preset: Option<String>,
    /// Result folder (default: out/campaigns/NAME). It is locked for the run (lock file
    /// `.usar-campaign.lock`, released when the run ends, however it ends).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Parallel runs (default: one per core).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Run only the deterministic slice K of N of the design (e.g. 3/8), for job arrays.
    #[arg(long, default_value = "1/1")]
    pub shard: String,
    /// Print a JSON summary (no progress bar).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct CampaignMergeArgs {
    /// Result folders of the shards.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// New result folder.
    #[arg(long)]
    pub out: PathBuf,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ReportFormat {
    Md,
    Html,
}

#[derive(Debug, Args)]
pub struct CampaignReportArgs {
    /// A result folder.
    pub dir: PathBuf,
    /// Written into DIR/report/ with the plots.
    #[arg(long, value_enum, default_value_t = ReportFormat::Md)]
    pub format: ReportFormat,
    /// Print the tables and every test as JSON (the files are written too).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct CampaignExportArgs {
    /// A result folder.
    pub dir: PathBuf,
    /// The CSV file to write.
    #[arg(long)]
    pub csv: PathBuf,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct CampaignListArgs {
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Subcommand)]
pub enum SceneCommand {
    /// Generate a scene with a seeded generator (the same seed gives the same file).
    Gen(SceneGenArgs),
    /// Import a map made elsewhere (ROS map_server YAML, bare PGM/PNG, MovingAI .map).
    Import(SceneImportArgs),
    /// Export a scene as a ROS map_server map (YAML + PGM) or a PNG rendering.
    Export(SceneExportArgs),
    /// Render a scene to PNG: walls, floor heights, room labels, victims, start poses.
    Show(SceneShowArgs),
    /// Describe a scene: size, rooms and labels, doors, victims, junctions, reachable area.
    Info(SceneInfoArgs),
    /// Room segmentation: split the free space into rooms and corridors at doorways and label
    /// the rooms by area (the room layer `team run` uses for maps without one); optionally
    /// score it against a ground truth in the format of Bormann et al. 2016.
    Segment(SceneSegmentArgs),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum GeneratorKind {
    /// Paper 000 rubble arena: 20×20 cells of 0.84 m², dense rubble, 7–8 victims.
    Rubble,
    /// Paper 002 office floor: corridors, mostly small and medium rooms.
    Office,
    /// Paper 002 mall floor: wide galleries, a few very big rooms.
    Mall,
    /// Paper 004 test course: passages, junctions, a hall, a slope and stairs.
    Course,
}

#[derive(Debug, Args)]
pub struct SceneGenArgs {
    pub kind: GeneratorKind,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Office and mall only: share of each room's floor covered by furniture, 0 to 0.3
    /// (default: the generator's, 0.05 office, 0.03 mall). Paper 002's rooms have "some
    /// obstacles"; how much clutter changes how S-MCDM compares with D-MCDM (README, issue 5).
    #[arg(long, value_name = "SHARE")]
    pub furniture: Option<f64>,
    /// Output scene file (.json).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Print a JSON summary instead of a line of text.
    #[arg(long)]
    pub json: bool,
}

/// A scene to read or generate: its name, a generator's seed and how to read a map image.
#[derive(Debug, Args)]
pub struct SceneSpec {
    /// The scene: a scene file, a ROS map, a map image, a MovingAI map or a generator name.
    pub scene: String,
    /// Seed of a generated scene.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub image: ImageArgs,
}

/// How to read a map image.
#[derive(Debug, Args, Clone)]
pub struct ImageArgs {
    /// Metres per pixel of a bare PGM/PNG map (required for bare images; ROS YAML files carry
    /// their own).
    #[arg(long, allow_negative_numbers = true)]
    pub resolution: Option<f64>,
    /// Dark pixels are free instead of occupied (ROS `negate: 1`).
    #[arg(long)]
    pub negate: bool,
    /// Occupancy above which a pixel is occupied (ROS default 0.65).
    #[arg(long, default_value_t = 0.65)]
    pub occupied_thresh: f64,
    /// Occupancy below which a pixel is free (ROS default 0.196).
    #[arg(long, default_value_t = 0.196)]
    pub free_thresh: f64,
}

impl ImageArgs {
    /// The command line's defaults (ROS map_server's), for a command that reads no image.
    pub fn none() -> Self {
        Self {
            resolution: None,
            negate: false,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
        }
    }
}

#[derive(Debug, Args)]
pub struct SceneImportArgs {
    /// The map to import: .yaml (ROS map_server), .pgm/.png (bare image), .map (MovingAI).
    pub input: PathBuf,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Output scene file (.json).
    #[arg(short, long)]
    pub output: PathBuf,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SceneExportArgs {
    #[command(flatten)]
    pub source: SceneSpec,
    /// Write a ROS map_server map: this YAML and a PGM beside it.
    #[arg(long)]
    pub ros: Option<PathBuf>,
    /// Write a PNG rendering.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Write the scene in the usar scene format (.json).
    #[arg(long)]
    pub scene_file: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SceneShowArgs {
    #[command(flatten)]
    pub source: SceneSpec,
    /// Output PNG file.
    #[arg(long)]
    pub png: PathBuf,
    /// Pixels per grid cell (default: fit the image in 1600 px).
    #[arg(long)]
    pub px_per_cell: Option<u32>,
    /// Draw ground-truth junctions.
    #[arg(long)]
    pub ground_truth: bool,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SceneInfoArgs {
    #[command(flatten)]
    pub source: SceneSpec,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SceneSegmentArgs {
    #[command(flatten)]
    pub source: SceneSpec,
    /// Segmentation parameters (TOML; missing fields keep their defaults): min_region_area_m2,
    /// door_ratio, max_door_width_m, min_depth_m, min_core_area_m2, min_room_area_m2,
    /// corridor_elongation, [thresholds] small_below_m2, medium_below_m2.
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Draw the segments (one colour each; corridors pale; doors as crosses) into this PNG.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Write the scene with the segmentation as its room layer (.json).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Ground-truth room image of the same size (floor > 250, black lines between rooms):
    /// report per-room recall, precision and best-match Jaccard.
    #[arg(long)]
    pub truth_rooms: Option<PathBuf>,
    /// Ground-truth class image of the same size (77 room, 115 hallway): report the
    /// room-vs-corridor pixel accuracy.
    #[arg(long)]
    pub truth_classes: Option<PathBuf>,
    /// Score against the scene's own room layer (a generated floor's rooms and corridors),
    /// on its free cells.
    #[arg(long, conflicts_with_all = ["truth_rooms", "truth_classes"])]
    pub against_layer: bool,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ConnectivityArg {
    #[value(name = "4")]
    Four,
    #[value(name = "8")]
    Eight,
}

#[derive(Debug, Args)]
pub struct PlanArgs {
    /// A MovingAI .scen file: plan every scenario (8-connected, no corner cutting) and compare
    /// with the published optimal lengths: within 1e-3 beyond the rounding of the printed
    /// digits ("3166.91" stands for 3166.905..3166.915).
    #[arg(long, conflicts_with_all = ["scene", "from", "to"])]
    pub scen: Option<PathBuf>,
    /// A scene to plan on (with --from and --to).
    #[arg(long, requires_all = ["from", "to"])]
    pub scene: Option<String>,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Start point "x,y" in metres.
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub from: Option<(f64, f64)>,
    /// Goal point "x,y" in metres.
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub to: Option<(f64, f64)>,
    /// Robot model whose size inflates the obstacles and whose climbing limits apply: crawler,
    /// wheeled, or a robot TOML file.
    #[arg(long, default_value = "wheeled")]
    pub robot: String,
    #[arg(long, value_enum, default_value_t = ConnectivityArg::Eight)]
    pub connectivity: ConnectivityArg,
    /// Draw the path over the scene into this PNG.
    #[arg(long)]
    pub png: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

fn parse_point(s: &str) -> Result<(f64, f64), String> {
    let (x, y) = s
        .split_once(',')
        .ok_or_else(|| format!("expected \"x,y\" in metres, found {s:?}"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("expected a finite number, found {v:?} in {s:?}"))
    };
    Ok((parse(x)?, parse(y)?))
}

/// "x,y" or "x,y,theta" (metres, radians; theta defaults to 0).
fn parse_pose(s: &str) -> Result<(f64, f64, f64), String> {
    let parts: Vec<&str> = s.split(',').collect();
    if !(2..=3).contains(&parts.len()) {
        return Err(format!(
            "expected \"x,y\" or \"x,y,theta\" (metres, radians), found {s:?}"
        ));
    }
    let parse = |v: &str| {
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("expected a number, found {v:?} in {s:?}"))
    };
    let theta = parts.get(2).map_or(Ok(0.0), |t| parse(t))?;
    Ok((parse(parts[0])?, parse(parts[1])?, theta))
}

#[derive(Debug, Args)]
pub struct ExploreArgs {
    /// The scene (file, map or generator name).
    #[arg(long, default_value = "office")]
    pub scene: String,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Number of robots.
    #[arg(long, default_value_t = 4)]
    pub robots: usize,
    /// Seed of the run (and of the generator when --scene names one).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Robot model: crawler, wheeled, or a robot TOML file.
    #[arg(long, default_value = "wheeled")]
    pub robot: String,
    /// Simulated time limit, minutes.
    #[arg(long, default_value_t = 20.0)]
    pub minutes: f64,
    /// Stop once this fraction of the reachable area is known.
    #[arg(long)]
    pub stop_at_coverage: Option<f64>,
    /// Stop once coverage grew by less than 0.2 % in this many minutes (0: never).
    #[arg(long, default_value_t = 3.0)]
    pub stall_minutes: f64,
    /// Write a report folder (map, coverage CSV and plot, summary.json) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Record the run into this MCAP file of ROS 2 messages (/clock, /tf, each robot's scan
    /// and odometry, the goals, the merged map; see `usar mission run --record`).
    #[arg(long, value_name = "FILE.mcap")]
    pub record: Option<PathBuf>,
    /// Print the outcome as JSON (no progress bar).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Subcommand)]
pub enum MissionCommand {
    /// Run a mission file (TOML; every field has a default, so no file is the built-in
    /// mission: an office floor, four wheeled robots with S-MCDM + MRv1 exploring the big
    /// rooms first, a crawler building a Behavioral Trace Map that it sends to the base station
    /// every 10 s, whose links too steep, narrow or high for the wheeled robots the base
    /// station closes to them; robots see and block each other). Prints what each system did;
    /// writes a report folder with --out.
    Run(MissionRunArgs),
}

#[derive(Debug, Args)]
pub struct MissionRunArgs {
    /// The mission file (see docs/mission-format.md); none: the built-in mission.
    pub file: Option<PathBuf>,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Simulated minutes (overrides the file's `minutes`).
    #[arg(long)]
    pub minutes: Option<f64>,
    /// Report folder (map with the BTM and trajectories, victims, coverage, summary.json).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The crawler's map is also written to this BTM database (.sqlite).
    #[arg(long)]
    pub btm: Option<PathBuf>,
    /// Record the run into this MCAP file of ROS 2 messages (/clock, /tf, scans, odometry,
    /// the merged map, BTM / victim / goal markers) for Foxglove, Lichtblick, Rerun or ros2 bag.
    #[arg(long, value_name = "FILE.mcap")]
    pub record: Option<PathBuf>,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Print the outcome as JSON (no progress bar).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Report folder.
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Record the run into this MCAP file (see `usar mission run --record`).
    #[arg(long, value_name = "FILE.mcap")]
    pub record: Option<PathBuf>,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print the summary as JSON (no progress bar).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Fewer repetitions (a quick look, noisier).
    #[arg(long)]
    pub quick: bool,
    /// Instead: the scaling table — simulated ÷ wall time and peak memory of teams of 1, 8,
    /// 32, 128 and 512 robots on the mall floor, for the simulator with mapping and the
    /// nearest-frontier explorer and for paper 002's S-MCDM + MRv1 team, one core.
    #[arg(long)]
    pub scaling: bool,
    /// Simulated seconds of each scaling run.
    #[arg(long, default_value_t = 60.0, requires = "scaling")]
    pub scaling_seconds: f64,
    /// Team sizes of the scaling table (comma-separated).
    #[arg(long, value_delimiter = ',', default_values_t = usar_bench::scaling::SIZES, requires = "scaling")]
    pub sizes: Vec<usize>,
    /// Only this pipeline (`nearest` or `s-mcdm-mrv1`), in this process: one cell of the table
    /// (the whole table runs each cell in a process of its own, for its peak memory).
    #[arg(long, requires = "scaling")]
    pub pipeline: Option<String>,
    /// Instead: what recording costs — the demo's mission timed alone and with `--record`,
    /// alternately, three times each (the MAXQ robot's training included, as `usar demo`).
    #[arg(long, conflicts_with_all = ["scaling", "laser_reference"])]
    pub recording: bool,
    /// Instead: the laser (`lidar_scans_per_s`) beside the Python reference — raycast2D's C
    /// raycaster with an OpenCV occupancy update — on the same floor and poses, in this run.
    #[arg(long, conflicts_with = "scaling")]
    pub laser_reference: bool,
    /// The Python that runs the reference (it needs `raycast2D`, `opencv-python-headless` and
    /// `numpy`); default: $USAR_PYTHON, else `python3`.
    #[arg(long, requires = "laser_reference")]
    pub python: Option<PathBuf>,
    /// Print one JSON object with every figure.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Subcommand)]
pub enum TeamCommand {
    /// One run of paper 002's exploration: a team explores a floor with an exploration
    /// strategy and a coordination method; prints the explored relevant area, total area and
    /// distance at the end and every simulated minute. Relevant area and labels come from the
    /// scene's room layer.
    Run(TeamRunArgs),
}

#[derive(Debug, Args)]
pub struct TeamRunArgs {
    /// The scene: office, mall (generated with --scene-seed), or a scene file or map (.json,
    /// .yaml, .pgm/.png with --resolution); one without a room layer is segmented into rooms
    /// and corridors (`usar scene segment`), and start poses are added around its first one.
    #[arg(long, default_value = "office")]
    pub scene: String,
    /// Seed of the generated floor (the paper runs every configuration on one floor).
    #[arg(long, default_value_t = 1)]
    pub scene_seed: u64,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Number of robots.
    #[arg(long, default_value_t = 6)]
    pub robots: usize,
    /// Exploration strategy: random, distance, d-mcdm, s-mcdm (or nearest: the baseline).
    #[arg(long, default_value = "s-mcdm")]
    pub strategy: String,
    /// Coordination method: sr, mrv1, mrv2.
    #[arg(long, default_value = "sr")]
    pub coordination: String,
    /// Where the victims are believed to be: big (rooms) or small (rooms).
    #[arg(long, default_value = "big")]
    pub hypothesis: String,
    /// Simulated time limit, minutes.
    #[arg(long, default_value_t = 20.0)]
    pub minutes: f64,
    /// Seed of the run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Robot model: crawler, wheeled, wheeled-paper-pace (the wheeled robot at 0.3 × its
    /// speeds, near the pace of paper 002's robots), or a robot TOML file.
    #[arg(long, default_value = usar_team::setup::DEFAULT_ROBOT)]
    pub robot: String,
    /// Semantic errors (paper 002 §4.4): `perfect`, `random:RATE` (each classification wrong
    /// with probability RATE) or `until-known:FRACTION` (random label while less than
    /// FRACTION of the room is known).
    #[arg(long, default_value = "perfect")]
    pub label_errors: String,
    /// Candidate locations of the auctions: `room` (one per room, its whole frontier; corridors
    /// keep one per frontier cluster) or `cluster` (one per frontier cluster, as paper 002 §3.1
    /// has it; a furnished room then has one behind each piece of furniture).
    #[arg(long, default_value = "room")]
    pub candidates: String,
    /// Where rooms and labels come from: `oracle` (the scene's room layer, as paper 002
    /// assumes) or `segmented` (a room segmentation of the team's merged map as it grows).
    #[arg(long, default_value = "oracle")]
    pub semantics: String,
    /// The pose robots map and drive at: `true` (the localization oracle, paper 002's
    /// error-free mapping) or `estimated` (odometry corrected by scan matching).
    #[arg(long, default_value = "true")]
    pub localization: String,
    /// Stop once this fraction of the relevant area is known (e.g. 0.9).
    #[arg(long)]
    pub stop_at_relevant: Option<f64>,
    /// The base station merges the maps this often, seconds.
    #[arg(long, default_value_t = 2.5)]
    pub merge_period: f64,
    /// Radio range from the base station (the first start pose), metres (default: unlimited).
    #[arg(long)]
    pub radio_range: Option<f64>,
    /// Probability that a map upload or a bid is lost.
    #[arg(long, default_value_t = 0.0)]
    pub radio_drop: f64,
    /// A robot fails: ROBOT@SECONDS (0-based robot index), repeatable.
    #[arg(long = "fail")]
    pub failures: Vec<String>,
    /// Also draw the explored map with the robots' trajectories to this PNG file.
    #[arg(long)]
    pub png: Option<std::path::PathBuf>,
    /// Also write every allocation of the auctions (time, robot, candidate, perceived label,
    /// S(p), frontier length, path length, winning bid, i(p), known fraction of its room) to this CSV
    /// file.
    #[arg(long)]
    pub trace: Option<std::path::PathBuf>,
    /// Record the run into this MCAP file of ROS 2 messages (/clock, /tf, each robot's scan
    /// and odometry, the goals, the merged map; see `usar mission run --record`).
    #[arg(long, value_name = "FILE.mcap")]
    pub record: Option<PathBuf>,
    /// Print the run as JSON (no progress bar).
    #[arg(long)]
    pub json: bool,
}

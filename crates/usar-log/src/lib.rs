//! Real robot logs in: one stream of timed laser scans and odometry, whatever the log's format.
//!
//! - [`read_log`] reads a log file (or a rosbag2 folder) into a [`RobotLog`], its format told
//!   by [`LogFormat::detect`] or given:
//!   - [`carmen`]: CARMEN logs (`FLASER` / `RLASER`, `ROBOTLASER1`, `RAWLASER1`–`4`, `ODOM`;
//!     `.log`, `.clf`, gzipped or not);
//!   - [`dpslam`]: DP-SLAM's `Odometry` / `Laser` pairs (Duke's logs, no timestamps);
//!   - [`thrun`]: the `O` / `L` logs of Thrun's course (CMU Wean Hall, centimetres);
//!   - [`rosbag2`]: rosbag2 in MCAP storage (`sensor_msgs/msg/LaserScan`,
//!     `nav_msgs/msg/Odometry`, the laser's mount from `/tf_static`).
//! - [`no_return`]: which reading means "nothing within range" when a log does not say.
//! - [`odometry`]: the robot's raw odometry at each scan ([`RobotLog::scans`]).
//! - [`mapping`]: an occupancy grid from a log with scan matching, and how far the log's
//!   odometry drifts from it.
//!
//! Nothing is assumed of a log that it does not state: not the beam count, the field of view,
//! the unit, the "no return" value, nor that its timestamps grow. A bad record is refused with
//! its file and line ([`LogError`]); limits ([`limits`]) bound what a log may declare.
//!
//! # Example
//!
//! ```
//! use usar_log::{LogFormat, parse_log};
//! let text = "Odometry 0.0 0.0 0.0\nLaser 3 1.0 2.0 8.191\n\
//!             Odometry 0.1 0.0 0.0\nLaser 3 1.1 2.0 8.191\n";
//! let log = parse_log(text.as_bytes(), "tiny.log", LogFormat::DpSlam).unwrap();
//! let scans = log.scans().unwrap();
//! assert_eq!(scans.len(), 2);
//! assert_eq!(scans[1].odometry.x, 0.1);
//! assert_eq!(scans[0].scan.ranges_m, vec![1.0, 2.0, 8.191]);
//! ```

pub mod carmen;
pub mod dpslam;
pub mod export;
pub mod mapping;
pub mod matcher;
pub mod no_return;
pub mod odometry;
pub mod output;
pub mod rosbag2;
mod text;
pub mod thrun;

pub use self::odometry::ScanAt;

use serde::Serialize;
use std::path::{Path, PathBuf};
use usar_world::Pose2;

/// What a log may declare, at most: a log past these is refused, not read. The bytes of a
/// log (decompressed) and of each file of a bag count against `usar_world::limits`' input
/// file size (`--max-file-mb`).
pub mod limits {
    /// Beams in one scan.
    pub const MAX_BEAMS: usize = 100_000;
    /// Scans and odometry readings in one log.
    pub const MAX_RECORDS: usize = 5_000_000;
    /// Bytes in one line of a text log.
    pub const MAX_LINE_BYTES: usize = 4 << 20;
    /// Bytes of one message of a rosbag2.
    pub const MAX_MESSAGE_BYTES: usize = 64 << 20;
}

/// The formats read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LogFormat {
    Carmen,
    DpSlam,
    Thrun,
    Rosbag2,
}

impl LogFormat {
    pub const NAMES: [&'static str; 4] = ["carmen", "dpslam", "thrun", "rosbag2"];

    pub fn name(self) -> &'static str {
        match self {
            Self::Carmen => "carmen",
            Self::DpSlam => "dpslam",
            Self::Thrun => "thrun",
            Self::Rosbag2 => "rosbag2",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Carmen, Self::DpSlam, Self::Thrun, Self::Rosbag2]
            .into_iter()
            .find(|f| f.name() == name)
    }

    /// The format of the log at `path`: a folder or an `.mcap` file is a rosbag2; a text log
    /// is told by the first record keyword it holds (`FLASER`, `ROBOTLASER1`, `ODOM`, …:
    /// CARMEN; `Odometry` / `Laser`: DP-SLAM; `O` / `L`: Thrun's).
    pub fn detect(path: &Path) -> Result<Self, LogError> {
        if path.is_dir() || path.extension().is_some_and(|e| e == "mcap") {
            return Ok(Self::Rosbag2);
        }
        let mut lines = text::Lines::open(path)?;
        while let Some((line_no, line)) = lines.next_line()? {
            let Some(word) = line.split_ascii_whitespace().next() else {
                continue;
            };
            if carmen::KEYWORDS.contains(&word) {
                return Ok(Self::Carmen);
            }
            match word {
                "Odometry" | "Laser" => return Ok(Self::DpSlam),
                "O" | "L" => return Ok(Self::Thrun),
                _ if line_no > 1000 => break,
                _ => {}
            }
        }
        Err(LogError::Unknown {
            path: path.to_path_buf(),
        })
    }
}

/// One laser scan of a log, in the laser's own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct LoggedScan {
    /// Seconds, as logged (see [`RobotLog::timestamps`]).
    pub t_s: f64,
    /// Metres; `f32::INFINITY`: no return within range; NaN: no valid reading.
    pub ranges_m: Vec<f32>,
    pub angle_min_rad: f64,
    pub angle_increment_rad: f64,
    /// Readings at or above this are no return, when the log says so (ROBOTLASER1,
    /// RAWLASER, LaserScan's `range_max`).
    pub range_max_m: Option<f64>,
    /// The laser's pose as the log stamps it, in the log's world frame: odometry, or a SLAM
    /// estimate in a corrected log.
    pub logged_pose: Option<Pose2>,
    /// The robot's odometry as the scan record gives it.
    pub odometry: Option<Pose2>,
    /// The laser's pose on the robot (robot frame), when the log gives it.
    pub mount: Option<Pose2>,
}

/// One record of a log, in file order.
#[derive(Clone, Debug, PartialEq)]
pub enum LogEvent {
    /// The robot's odometry. `restart`: the odometry frame starts anew here (no motion from
    /// the reading before), as the corrected CARMEN logs' ODOM lines after each scan do.
    Odometry {
        t_s: f64,
        pose: Pose2,
        restart: bool,
    },
    Scan(LoggedScan),
}

/// Where a log's times come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Timestamps {
    /// As logged (they may go back: [`RobotLog::backward_steps`] counts the scans that do).
    Logged,
    /// The log has none: record k of each kind is at k seconds.
    Synthetic,
}

/// A log read: its records in file order.
#[derive(Clone, Debug)]
pub struct RobotLog {
    pub path: PathBuf,
    pub format: LogFormat,
    pub timestamps: Timestamps,
    pub events: Vec<LogEvent>,
}

/// A log that cannot be read: the file, the line (or message), what was found and what was
/// expected.
#[derive(Debug, thiserror::Error)]
pub enum LogError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}:{line}: {what}")]
    Record {
        path: PathBuf,
        line: u64,
        what: String,
    },
    #[error("{path}: {what}")]
    Bag { path: PathBuf, what: String },
    #[error(
        "{path}: no record of a known log format in its first 1000 lines (expected CARMEN, DP-SLAM, Thrun's O/L, or a rosbag2 .mcap)"
    )]
    Unknown { path: PathBuf },
    #[error("{path}: no laser scan in the log")]
    NoScans { path: PathBuf },
    #[error(
        "{path}: no scan has odometry (no odometry record before it and none in its own record)"
    )]
    NoOdometry { path: PathBuf },
}

/// Reads the log at `path`; `format` `None`: [`LogFormat::detect`].
pub fn read_log(path: &Path, format: Option<LogFormat>) -> Result<RobotLog, LogError> {
    let format = match format {
        Some(f) => f,
        None => LogFormat::detect(path)?,
    };
    let log = match format {
        LogFormat::Rosbag2 => rosbag2::read(path)?,
        text_format => {
            let lines = text::Lines::open(path)?;
            parse_lines(lines, text_format)?
        }
    };
    if log.scan_count() == 0 {
        return Err(LogError::NoScans {
            path: path.to_path_buf(),
        });
    }
    Ok(log)
}

/// Parses a text log from memory (`name` stands for its path in errors).
pub fn parse_log(bytes: &[u8], name: &str, format: LogFormat) -> Result<RobotLog, LogError> {
    if format == LogFormat::Rosbag2 {
        return rosbag2::parse(bytes, Path::new(name));
    }
    parse_lines(text::Lines::from_bytes(bytes, name), format)
}

fn parse_lines(lines: text::Lines, format: LogFormat) -> Result<RobotLog, LogError> {
    match format {
        LogFormat::Carmen => carmen::parse(lines),
        LogFormat::DpSlam => dpslam::parse(lines),
        LogFormat::Thrun => thrun::parse(lines),
        LogFormat::Rosbag2 => unreachable!("rosbag2 is binary"),
    }
}

impl RobotLog {
    pub fn scan_count(&self) -> usize {
        self.events
            .iter()
            .filter(|e| matches!(e, LogEvent::Scan(_)))
            .count()
    }

    pub fn odometry_count(&self) -> usize {
        self.events.len() - self.scan_count()
    }

    fn logged_scans(&self) -> impl Iterator<Item = &LoggedScan> {
        self.events.iter().filter_map(|e| match e {
            LogEvent::Scan(s) => Some(s),
            LogEvent::Odometry { .. } => None,
        })
    }

    /// Scans whose time is earlier than the scan's before (the Intel log has four).
    pub fn backward_steps(&self) -> usize {
        let times: Vec<f64> = self.logged_scans().map(|s| s.t_s).collect();
        times.windows(2).filter(|w| w[1] < w[0]).count()
    }

    /// A summary of what the log holds.
    pub fn summary(&self) -> LogSummary {
        let scans: Vec<&LoggedScan> = self.logged_scans().collect();
        let beams = |f: fn(usize, usize) -> usize| {
            scans
                .iter()
                .map(|s| s.ranges_m.len())
                .reduce(f)
                .unwrap_or(0)
        };
        let no_return = no_return::estimate(self);
        let times = scans.iter().map(|s| s.t_s);
        let fov = scans.first().map_or(0.0, |s| {
            (s.ranges_m.len().saturating_sub(1) as f64 * s.angle_increment_rad).to_degrees()
        });
        LogSummary {
            path: self.path.clone(),
            format: self.format,
            timestamps: self.timestamps,
            scans: scans.len(),
            odometry_readings: self.odometry_count(),
            beams_min: beams(usize::min),
            beams_max: beams(usize::max),
            field_of_view_deg: fov,
            first_beam_deg: scans.first().map_or(0.0, |s| s.angle_min_rad.to_degrees()),
            no_return_m: no_return.threshold_m,
            no_return_source: no_return.source,
            no_return_share: no_return.share,
            longest_return_m: no_return.longest_return_m,
            t_first_s: times.clone().reduce(f64::min).unwrap_or(0.0),
            t_last_s: times.reduce(f64::max).unwrap_or(0.0),
            backward_steps: self.backward_steps(),
            odometry_path_m: self
                .scans()
                .map(|s| odometry::path_length_m(&s))
                .unwrap_or(0.0),
        }
    }
}

/// What `usar log import` reports of a log.
#[derive(Clone, Debug, Serialize)]
pub struct LogSummary {
    pub path: PathBuf,
    pub format: LogFormat,
    pub timestamps: Timestamps,
    pub scans: usize,
    pub odometry_readings: usize,
    pub beams_min: usize,
    pub beams_max: usize,
    pub field_of_view_deg: f64,
    pub first_beam_deg: f64,
    /// Readings at or above are no return (`None`: every reading is a return).
    pub no_return_m: Option<f64>,
    pub no_return_source: no_return::Source,
    /// Share of the readings that are no return.
    pub no_return_share: f64,
    pub longest_return_m: f64,
    pub t_first_s: f64,
    pub t_last_s: f64,
    pub backward_steps: usize,
    /// Length of the path the robot's raw odometry reports at the scans.
    pub odometry_path_m: f64,
}

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! CARMEN logs (`.log`, `.clf`): one record a line, a keyword first, times in seconds.
//!
//! Read (the front laser and odometry; other records are skipped):
//! - `FLASER n r₁…rₙ x y θ odom_x odom_y odom_θ ipc_time host logger_time`: the old laser
//!   record. It states no field of view: like CARMEN's own reader, 180° from −90°, one beam
//!   every π/(n−1) when n is odd (the last beam at +90°) and π/n when even. `x y θ` is the
//!   pose the log stamps the scan with (a SLAM estimate in a corrected log), `odom_*` the
//!   robot's odometry.
//! - `ROBOTLASER1 type start fov resolution max_range accuracy remission_mode n r₁…rₙ m e₁…eₘ
//!   laser_x laser_y laser_θ robot_x robot_y robot_θ tv rv forward_safety side_safety
//!   turn_axis ipc_time host logger_time`: angles, maximum range and the laser's mount stated.
//! - `RAWLASER1 type start fov resolution max_range accuracy remission_mode n r… m e… ipc_time
//!   host logger_time`: a scan with no pose.
//! - `ODOM x y θ tv rv accel ipc_time host logger_time`. An `ODOM` at time 0 starts the
//!   odometry anew: GMapping's corrected logs re-anchor the odometry at each corrected scan
//!   pose so, and the raw odometry between two scans is what the `ODOM` lines after that add.

use crate::text::{Fields, Lines, check_records};
use crate::{LogError, LogEvent, LogFormat, LoggedScan, RobotLog, Timestamps, limits};
use std::f64::consts::PI;
use usar_map::localization::relative;
use usar_world::Pose2;

/// The keywords of CARMEN records (read or skipped), which tell the format.
pub const KEYWORDS: [&str; 14] = [
    "FLASER",
    "RLASER",
    "ROBOTLASER1",
    "ROBOTLASER2",
    "RAWLASER1",
    "RAWLASER2",
    "RAWLASER3",
    "RAWLASER4",
    "ODOM",
    "TRUEPOS",
    "PARAM",
    "SYNC",
    "NEFF",
    "POSITIONLASER",
];

pub(crate) fn parse(mut lines: Lines) -> Result<RobotLog, LogError> {
    let mut events = Vec::new();
    let path = lines.path.clone();
    while let Some((line_no, line)) = lines.next_line()? {
        let Some(mut f) = Fields::new(line, &path, line_no) else {
            continue;
        };
        let event = match f.keyword() {
            "FLASER" => Some(flaser(&mut f)?),
            "ROBOTLASER1" => Some(robot_laser(&mut f)?),
            "RAWLASER1" => Some(raw_laser(&mut f)?),
            "ODOM" => Some(odom(&mut f)?),
            _ => None,
        };
        if let Some(e) = event {
            events.push(e);
            check_records(&lines, events.len())?;
        }
    }
    Ok(RobotLog {
        path,
        format: LogFormat::Carmen,
        timestamps: Timestamps::Logged,
        events,
    })
}

fn flaser(f: &mut Fields) -> Result<LogEvent, LogError> {
    let n = f.count("beam count", limits::MAX_BEAMS)?;
    let ranges_m = f.readings(n, 1.0)?;
    let logged = f.pose("pose", 1.0)?;
    let odometry = f.pose("odometry", 1.0)?;
    let t_s = f.number("time")?;
    let increment = if n % 2 == 1 {
        PI / (n.max(2) - 1) as f64
    } else {
        PI / n.max(1) as f64
    };
    Ok(LogEvent::Scan(LoggedScan {
        t_s,
        ranges_m,
        angle_min_rad: -PI / 2.0,
        angle_increment_rad: increment,
        range_max_m: None,
        logged_pose: Some(logged),
        odometry: Some(odometry),
        mount: None,
    }))
}

/// `type start fov resolution max_range accuracy remission_mode n r… m e…`: the scan's
/// geometry and readings.
fn laser_head(f: &mut Fields) -> Result<(f64, f64, f64, Vec<f32>), LogError> {
    f.skip(1, "laser type")?;
    let start = f.number("start angle")?;
    f.skip(1, "field of view")?;
    let resolution = f.number("angular resolution")?;
    let max_range = f.number("maximum range")?;
    f.skip(2, "accuracy and remission mode")?;
    let n = f.count("beam count", limits::MAX_BEAMS)?;
    let ranges = f.readings(n, 1.0)?;
    let m = f.count("remission count", limits::MAX_BEAMS)?;
    f.skip(m, "remissions")?;
    if resolution <= 0.0 {
        return Err(f.error(format!(
            "angular resolution {resolution} (expected a positive angle in radians)"
        )));
    }
    Ok((start, resolution, max_range, ranges))
}

fn robot_laser(f: &mut Fields) -> Result<LogEvent, LogError> {
    let head = laser_head(f)?;
    let laser = f.pose("laser pose", 1.0)?;
    let robot = f.pose("robot pose", 1.0)?;
    f.skip(5, "velocities and safety distances")?;
    let t_s = f.number("time")?;
    let posed = Some((laser, robot, relative(robot, laser)));
    Ok(LogEvent::Scan(stated_scan(t_s, head, posed)))
}

fn raw_laser(f: &mut Fields) -> Result<LogEvent, LogError> {
    let head = laser_head(f)?;
    let t_s = f.number("time")?;
    Ok(LogEvent::Scan(stated_scan(t_s, head, None)))
}

/// A scan whose geometry its record states (`laser_head`), with its laser pose, robot pose
/// and mount when the record gives them.
fn stated_scan(
    t_s: f64,
    (start, resolution, max_range, ranges_m): (f64, f64, f64, Vec<f32>),
    posed: Option<(Pose2, Pose2, Pose2)>,
) -> LoggedScan {
    LoggedScan {
        t_s,
        ranges_m,
        angle_min_rad: start,
        angle_increment_rad: resolution,
        range_max_m: (max_range > 0.0).then_some(max_range),
        logged_pose: posed.map(|p| p.0),
        odometry: posed.map(|p| p.1),
        mount: posed.map(|p| p.2),
    }
}

fn odom(f: &mut Fields) -> Result<LogEvent, LogError> {
    let pose = f.pose("odometry", 1.0)?;
    f.skip(3, "velocities and acceleration")?;
    let t_s = f.number("time")?;
    Ok(LogEvent::Odometry {
        t_s,
        pose,
        restart: t_s == 0.0,
    })
}

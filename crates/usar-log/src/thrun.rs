//! The logs of Thrun's 16-899 course (CMU Wean Hall, `ascii-robotdata*.log`): lengths in
//! centimetres, angles in radians, times in seconds from the start.
//!
//! - `O x y θ t`: odometry;
//! - `L x y θ xl yl θl r₁…rₙ t`: a scan, with the robot's and the laser's odometry poses
//!   (interpolated to the scan's time; the laser sits about 25 cm ahead). The format's text
//!   gives 180 readings spanning 180° "starting from the right and going left": n beams from
//!   −90°, one every π/n. n is the count of fields between the poses and the time.

use crate::text::{Fields, Lines, check_records};
use crate::{LogError, LogEvent, LogFormat, LoggedScan, RobotLog, Timestamps, limits};
use std::f64::consts::PI;
use usar_map::localization::relative;

/// Centimetres to metres.
const CM: f64 = 0.01;

pub(crate) fn parse(mut lines: Lines) -> Result<RobotLog, LogError> {
    let mut events = Vec::new();
    let path = lines.path.clone();
    while let Some((line_no, line)) = lines.next_line()? {
        let Some(mut f) = Fields::new(line, &path, line_no) else {
            continue;
        };
        match f.keyword() {
            "O" => {
                let pose = f.pose("odometry", CM)?;
                let t_s = f.number("time")?;
                events.push(LogEvent::Odometry {
                    t_s,
                    pose,
                    restart: false,
                });
            }
            "L" => {
                let robot = f.pose("robot pose", CM)?;
                let laser = f.pose("laser pose", CM)?;
                let fields = line.split_ascii_whitespace().count() - 7;
                if !(2..=limits::MAX_BEAMS + 1).contains(&fields) {
                    return Err(f.error(format!(
                        "{fields} fields after the poses (expected 1 to {} readings and a time)",
                        limits::MAX_BEAMS
                    )));
                }
                let n = fields - 1;
                let ranges_m = f.readings(n, CM)?;
                let t_s = f.number("time")?;
                events.push(LogEvent::Scan(LoggedScan {
                    t_s,
                    ranges_m,
                    angle_min_rad: -PI / 2.0,
                    angle_increment_rad: PI / n as f64,
                    range_max_m: None,
                    logged_pose: Some(laser),
                    odometry: Some(robot),
                    mount: Some(relative(robot, laser)),
                }));
            }
            other => {
                return Err(f.error(format!("an unknown record {other:?} (expected O or L)")));
            }
        }
        check_records(&lines, events.len())?;
    }
    Ok(RobotLog {
        path,
        format: LogFormat::Thrun,
        timestamps: Timestamps::Logged,
        events,
    })
}

//! DP-SLAM's logs (Duke, Eliazar & Parr): pairs of lines, `Odometry x y θ` (metres, radians)
//! then `Laser n r₁…rₙ` (metres). Its README: the readings "start at −90 degrees, and occur at
//! every 1 degree up to +90 degrees" (181 of them): n beams over 180°, one every π/(n−1).
//! Keywords in any case (the README writes `ODOMETRY` / `LASER`, the logs `Odometry` /
//! `Laser`). The log has no times: record k of each kind is at k seconds
//! ([`Timestamps::Synthetic`]).

use crate::text::{Fields, Lines, check_records};
use crate::{LogError, LogEvent, LogFormat, LoggedScan, RobotLog, Timestamps, limits};
use std::f64::consts::PI;

pub(crate) fn parse(mut lines: Lines) -> Result<RobotLog, LogError> {
    let mut events = Vec::new();
    let (mut odometry, mut scans) = (0usize, 0usize);
    let path = lines.path.clone();
    while let Some((line_no, line)) = lines.next_line()? {
        let Some(mut f) = Fields::new(line, &path, line_no) else {
            continue;
        };
        if f.keyword().eq_ignore_ascii_case("odometry") {
            let pose = f.pose("odometry", 1.0)?;
            events.push(LogEvent::Odometry {
                t_s: odometry as f64,
                pose,
                restart: false,
            });
            odometry += 1;
        } else if f.keyword().eq_ignore_ascii_case("laser") {
            let n = f.count("beam count", limits::MAX_BEAMS)?;
            let ranges_m = f.readings(n, 1.0)?;
            if f.rest() != 0 {
                return Err(f.error(format!("more than the {n} readings it declares")));
            }
            events.push(LogEvent::Scan(LoggedScan {
                t_s: scans as f64,
                ranges_m,
                angle_min_rad: -PI / 2.0,
                angle_increment_rad: PI / (n.max(2) - 1) as f64,
                range_max_m: None,
                logged_pose: None,
                odometry: None,
                mount: None,
            }));
            scans += 1;
        } else {
            return Err(f.error("an unknown record (expected Odometry or Laser)".into()));
        }
        check_records(&lines, events.len())?;
    }
    Ok(RobotLog {
        path,
        format: LogFormat::DpSlam,
        timestamps: Timestamps::Synthetic,
        events,
    })
}

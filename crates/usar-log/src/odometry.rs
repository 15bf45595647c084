//! The robot's raw odometry at each scan: the scan record's own odometry when it has one
//! (FLASER's `odom_*`, ROBOTLASER1's robot pose, Thrun's `L` robot pose: taken at the scan's
//! time), else the chain of the motions between consecutive odometry records, started at the
//! first record, up to the latest record at or before the scan's time (when the log's times
//! grow; else the latest before it in the file). A record that restarts the odometry
//! ([`LogEvent::Odometry::restart`]) adds no motion. A log whose odometry restarts is a
//! corrected log (GMapping's re-anchor the odometry at each corrected scan pose, and write the
//! corrected pose into FLASER's odometry fields too): there the chain alone is raw odometry and
//! the scan records' fields are not used. Scans with neither are left out.

use crate::{LogError, LogEvent, LoggedScan, RobotLog};
use usar_map::localization::{compose, relative};
use usar_world::Pose2;

/// A scan with the robot's odometry when it was taken.
#[derive(Clone, Copy, Debug)]
pub struct ScanAt<'a> {
    /// The scan's index among the log's scans.
    pub index: usize,
    pub scan: &'a LoggedScan,
    /// The robot's raw odometry.
    pub odometry: Pose2,
    /// The laser's pose on the robot (identity when the log does not say).
    pub mount: Pose2,
}

impl ScanAt<'_> {
    /// The laser's pose by odometry.
    pub fn laser_odometry(&self) -> Pose2 {
        compose(self.odometry, self.mount)
    }
}

impl RobotLog {
    /// Every scan that has odometry, in file order.
    pub fn scans(&self) -> Result<Vec<ScanAt<'_>>, LogError> {
        let corrected = self
            .events
            .iter()
            .any(|e| matches!(e, LogEvent::Odometry { restart: true, .. }));
        // The chained odometry at each odometry record: (time, position in the file, pose).
        let mut chain: Vec<(f64, usize, Pose2)> = Vec::new();
        let mut last_reading: Option<Pose2> = None;
        for (at, event) in self.events.iter().enumerate() {
            if let LogEvent::Odometry { t_s, pose, restart } = event {
                let chained = match (chain.last(), last_reading) {
                    (Some(&(_, _, c)), Some(prev)) if !restart => compose(c, relative(prev, *pose)),
                    (Some(&(_, _, c)), _) => c,
                    (None, _) => *pose,
                };
                chain.push((*t_s, at, chained));
                last_reading = Some(*pose);
            }
        }
        // A scan takes the latest odometry at or before its time when the times can be
        // trusted (a bag writes a step's scan and odometry in either order); else the latest
        // before it in the file.
        let by_time = !corrected
            && self.timestamps == crate::Timestamps::Logged
            && chain.windows(2).all(|w| w[0].0 <= w[1].0);
        let mut out = Vec::new();
        let mut index = 0;
        for (at, event) in self.events.iter().enumerate() {
            let LogEvent::Scan(scan) = event else {
                continue;
            };
            let before = if by_time {
                chain.partition_point(|r| r.0 <= scan.t_s)
            } else {
                chain.partition_point(|r| r.1 < at)
            };
            let chained = before.checked_sub(1).map(|k| chain[k].2);
            let own = scan.odometry.filter(|_| !corrected);
            let odometry = own.or(chained).or(scan.logged_pose.filter(|_| !corrected));
            if let Some(odometry) = odometry {
                out.push(ScanAt {
                    index,
                    scan,
                    odometry,
                    mount: scan.mount.unwrap_or_default(),
                });
            }
            index += 1;
        }
        if out.is_empty() {
            return Err(LogError::NoOdometry {
                path: self.path.clone(),
            });
        }
        Ok(out)
    }
}

/// The length of the path the odometry reports through `scans`, metres.
pub fn path_length_m(scans: &[ScanAt<'_>]) -> f64 {
    scans
        .windows(2)
        .map(|w| w[0].odometry.position().distance(w[1].odometry.position()))
        .sum()
}

#[cfg(test)]
mod tests {
    use crate::{LogEvent, LogFormat, LoggedScan, RobotLog, Timestamps, parse_log};
    use usar_world::Pose2;

    /// A bag that writes a step's scan before its odometry: the scan takes the odometry of
    /// its own time, not the one a step before it in the file.
    #[test]
    fn a_scan_takes_the_odometry_of_its_time() {
        let odom = |t: f64, x: f64| LogEvent::Odometry {
            t_s: t,
            pose: Pose2::new(x, 0.0, 0.0),
            restart: false,
        };
        let scan = |t: f64| {
            LogEvent::Scan(LoggedScan {
                t_s: t,
                ranges_m: vec![1.0],
                angle_min_rad: 0.0,
                angle_increment_rad: 0.1,
                range_max_m: None,
                logged_pose: None,
                odometry: None,
                mount: None,
            })
        };
        let mut log = RobotLog {
            path: "bag".into(),
            format: LogFormat::Rosbag2,
            timestamps: Timestamps::Logged,
            events: vec![
                odom(0.0, 0.0),
                scan(1.0),
                odom(1.0, 0.5),
                scan(2.0),
                odom(2.0, 1.0),
            ],
        };
        let xs = |log: &RobotLog| -> Vec<f64> {
            log.scans().unwrap().iter().map(|s| s.odometry.x).collect()
        };
        assert_eq!(xs(&log), vec![0.5, 1.0]);
        // Without times to trust, file order.
        log.timestamps = Timestamps::Synthetic;
        assert_eq!(xs(&log), vec![0.0, 0.5]);
    }

    /// A corrected CARMEN log: each ODOM at time 0 re-anchors at the corrected pose; the raw
    /// odometry is the chain of the motions between the other readings.
    #[test]
    fn restarts_add_no_motion() {
        let text = "ODOM 0 0 0 0 0 0 1 h 1\n\
                    ODOM 1 0 0 0 0 0 2 h 2\n\
                    FLASER 2 1 1 5 5 0 5 5 0 2 h 2\n\
                    ODOM 5 5 0 0 0 0 0 h 0\n\
                    ODOM 5 6 0 0 0 0 3 h 3\n\
                    FLASER 2 1 1 5 6.2 0 5 6.2 0 3 h 3\n";
        let log = parse_log(text.as_bytes(), "c.log", LogFormat::Carmen).unwrap();
        let scans = log.scans().unwrap();
        assert_eq!(scans.len(), 2);
        // Not FLASER's odometry fields (the corrected pose): the chain.
        assert_eq!((scans[0].odometry.x, scans[0].odometry.y), (1.0, 0.0));
        // One metre along y after the restart, from where the chain was.
        assert!((scans[1].odometry.x - 1.0).abs() < 1e-12);
        assert!((scans[1].odometry.y - 1.0).abs() < 1e-12);
        // A raw log: each scan's own odometry field.
        let raw = text.replace(" 0 h 0\n", " 2.5 h 2.5\n");
        let log = parse_log(raw.as_bytes(), "r.log", LogFormat::Carmen).unwrap();
        let scans = log.scans().unwrap();
        assert_eq!((scans[1].odometry.x, scans[1].odometry.y), (5.0, 6.2));
    }
}

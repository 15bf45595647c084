//! The robot's raw odometry at each scan: the scan record's own odometry when it has one
//! (FLASER's `odom_*`, ROBOTLASER1's robot pose, Thrun's `L` robot pose: taken at the scan's
//! time), else the chain of the motions between consecutive odometry records up to it,
//! started at the first record. A record that restarts the odometry
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
        let mut chain: Option<Pose2> = None;
        let mut last_reading: Option<Pose2> = None;
        let mut out = Vec::new();
        let mut index = 0;
        for event in &self.events {
            match event {
                LogEvent::Odometry { pose, restart, .. } => {
                    chain = match (chain, last_reading) {
                        (Some(c), Some(prev)) if !restart => {
                            Some(compose(c, relative(prev, *pose)))
                        }
                        (Some(c), _) => Some(c),
                        (None, _) => Some(*pose),
                    };
                    last_reading = Some(*pose);
                }
                LogEvent::Scan(scan) => {
                    let own = scan.odometry.filter(|_| !corrected);
                    let odometry = own.or(chain).or(scan.logged_pose.filter(|_| !corrected));
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
            }
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
    use crate::{LogFormat, parse_log};

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

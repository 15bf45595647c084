//! A log as an MCAP file of ROS 2 messages (what `usar log import --out` writes), for Foxglove,
//! Lichtblick or `ros2 bag play`, one message of each a scan: `/scan` (`sensor_msgs/LaserScan`
//! in frame `laser`, no return as +∞ and no reading as NaN, per REP 117), `/odom`
//! (`nav_msgs/Odometry`, `odom` → `base_link`, the raw odometry the mapper uses), `/tf` (the
//! same), `/tf_static` (the laser's mount, once) and `/clock`. Headers
//! carry the logged times; the messages' log times never go back (a time that goes back is
//! recorded at the time before it), so a player replays the file in its order.

use crate::RobotLog;
use crate::no_return::{self, Reading};
use std::io::{Seek, Write};
use usar_record::msgs::{self, Frame};
use usar_record::{RecordError, Recording};

/// Writes the scans of `log` that have odometry (those the mapper draws) into `w`; returns
/// the messages written.
pub fn write_mcap<W: Write + Seek>(log: &RobotLog, w: W) -> Result<u64, RecordError> {
    let threshold = no_return::estimate(log).threshold_m;
    let scans = log.scans().unwrap_or_default();
    let mut rec = Recording::new(w)?;
    let mut clock = f64::NEG_INFINITY;
    for (k, at) in scans.iter().enumerate() {
        let (s, t) = (at.scan, at.scan.t_s);
        clock = clock.max(t);
        if k == 0 {
            let m = at.mount;
            let frame = Frame {
                parent: "base_link",
                child: "laser",
                x: m.x,
                y: m.y,
                yaw: m.theta,
            };
            rec.write("/tf_static", msgs::tf_type, clock, &msgs::tf(t, &[frame]))?;
        }
        rec.write("/clock", msgs::clock_type, clock, &msgs::clock(clock))?;
        let ranges: Vec<f32> = s
            .ranges_m
            .iter()
            .map(|&r| match no_return::classify(f64::from(r), threshold) {
                Reading::Return(r) => r as f32,
                Reading::NoReturn => f32::INFINITY,
                Reading::Invalid => f32::NAN,
            })
            .collect();
        // Without a stated or found maximum, the longest reading stands for it.
        let range_max = threshold.unwrap_or_else(|| {
            ranges
                .iter()
                .filter(|r| r.is_finite())
                .fold(0.0f32, |a, &r| a.max(r))
                .into()
        });
        let o = at.odometry;
        let frame = Frame {
            parent: "odom",
            child: "base_link",
            x: o.x,
            y: o.y,
            yaw: o.theta,
        };
        rec.write("/tf", msgs::tf_type, clock, &msgs::tf(t, &[frame]))?;
        let odom = msgs::odometry(t, "odom", "base_link", (o.x, o.y, o.theta), (0.0, 0.0));
        rec.write("/odom", msgs::odometry_type, clock, &odom)?;
        // After its odometry, as a robot's driver publishes both at one time.
        let scan = msgs::laser_scan(
            t,
            "laser",
            s.angle_min_rad,
            s.angle_increment_rad,
            range_max,
            &ranges,
        );
        rec.write("/scan", msgs::laser_scan_type, clock, &scan)?;
    }
    rec.finish()
}

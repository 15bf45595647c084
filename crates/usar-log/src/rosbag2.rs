//! rosbag2 in MCAP storage: a bag folder (its `.mcap` files, in name order) or one `.mcap`
//! file. Read: the `sensor_msgs/msg/LaserScan` topic and the `nav_msgs/msg/Odometry` topic with
//! the most messages (one laser, one odometry: a bag with two lasers gives the busier one), and
//! the laser's mount from `/tf_static` when it holds the transform from the odometry's child
//! frame to the scan's frame. Times are the messages' header stamps. Readings follow REP 117:
//! below `range_min` or NaN no reading, +∞ or at least `range_max` no return.

use crate::{LogError, LogEvent, LogFormat, LoggedScan, RobotLog, Timestamps, limits};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use usar_record::cdr::{CdrError, CdrReader};
use usar_world::Pose2;

const SCAN: &str = "sensor_msgs/msg/LaserScan";
const ODOMETRY: &str = "nav_msgs/msg/Odometry";
const TF: &str = "tf2_msgs/msg/TFMessage";

/// Reads the bag at `path` (a folder or an `.mcap` file).
pub(crate) fn read(path: &Path) -> Result<RobotLog, LogError> {
    let io = |source| LogError::Io {
        path: path.to_path_buf(),
        source,
    };
    let files: Vec<PathBuf> = if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(io)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "mcap"))
            .collect();
        files.sort();
        files
    } else {
        vec![path.to_path_buf()]
    };
    if files.is_empty() {
        return Err(bag_error(
            path,
            "a folder without .mcap files (expected a rosbag2 in MCAP storage)".into(),
        ));
    }
    let mut bytes = Vec::new();
    let mut log: Option<RobotLog> = None;
    for file in &files {
        // A bag is read whole: its files count against the input file size limit.
        let size = std::fs::metadata(file).map_err(io)?.len();
        let max = usar_world::limits::limits().max_file_bytes;
        if size > max {
            return Err(bag_error(
                file,
                format!("{size} bytes (at most {max}; raise the limit with --max-file-mb)"),
            ));
        }
        bytes.clear();
        std::io::Read::read_to_end(&mut std::fs::File::open(file).map_err(io)?, &mut bytes)
            .map_err(io)?;
        let part = parse(&bytes, file)?;
        match &mut log {
            None => log = Some(part),
            Some(l) => l.events.extend(part.events),
        }
    }
    let mut log = log.expect("at least one file");
    log.path = path.to_path_buf();
    Ok(log)
}

fn bag_error(path: &Path, what: String) -> LogError {
    LogError::Bag {
        path: path.to_path_buf(),
        what,
    }
}

/// One message kept, before the topics are chosen.
struct Kept {
    channel: u16,
    event: LogEvent,
    frame: String,
    child: String,
}

/// Parses one `.mcap` file of a bag.
pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<RobotLog, LogError> {
    if !bytes.starts_with(mcap::MAGIC) {
        return Err(bag_error(
            path,
            "not an MCAP file (expected a rosbag2 .mcap: its first bytes are MCAP's magic)".into(),
        ));
    }
    let stream = mcap::MessageStream::new(bytes)
        .map_err(|e| bag_error(path, format!("not an MCAP file: {e}")))?;
    let mut kept: Vec<Kept> = Vec::new();
    let mut counts: BTreeMap<(bool, u16), usize> = BTreeMap::new();
    let mut mounts: Vec<(String, String, Pose2)> = Vec::new();
    for (k, message) in stream.enumerate() {
        let message = message.map_err(|e| bag_error(path, format!("message {k}: {e}")))?;
        let Some(schema) = &message.channel.schema else {
            continue;
        };
        if message.channel.message_encoding != "cdr" {
            continue;
        }
        if message.data.len() > limits::MAX_MESSAGE_BYTES {
            return Err(bag_error(
                path,
                format!(
                    "message {k} on {} has {} bytes (at most {})",
                    message.channel.topic,
                    message.data.len(),
                    limits::MAX_MESSAGE_BYTES
                ),
            ));
        }
        let what = |e: CdrError| {
            bag_error(
                path,
                format!(
                    "message {k} on {} ({}): {e}",
                    message.channel.topic, schema.name
                ),
            )
        };
        let channel = message.channel.id;
        match schema.name.as_str() {
            SCAN => {
                let (frame, scan) = decode_scan(&message.data).map_err(what)?;
                *counts.entry((true, channel)).or_default() += 1;
                kept.push(Kept {
                    channel,
                    event: LogEvent::Scan(scan),
                    frame,
                    child: String::new(),
                });
            }
            ODOMETRY => {
                let (frame, child, t_s, pose) = decode_odometry(&message.data).map_err(what)?;
                *counts.entry((false, channel)).or_default() += 1;
                kept.push(Kept {
                    channel,
                    event: LogEvent::Odometry {
                        t_s,
                        pose,
                        restart: false,
                    },
                    frame,
                    child,
                });
            }
            TF if message.channel.topic == "/tf_static" => {
                mounts.extend(decode_tf(&message.data).map_err(what)?);
            }
            _ => {}
        }
        if kept.len() > limits::MAX_RECORDS {
            return Err(bag_error(
                path,
                format!(
                    "more than {} scans and odometry messages",
                    limits::MAX_RECORDS
                ),
            ));
        }
    }
    let busiest = |laser: bool| {
        counts
            .iter()
            .filter(|((l, _), _)| *l == laser)
            .max_by_key(|(_, n)| **n)
            .map(|((_, c), _)| *c)
    };
    let (scan_channel, odom_channel) = (busiest(true), busiest(false));
    let base = kept
        .iter()
        .find(|k| Some(k.channel) == odom_channel)
        .map(|k| k.child.clone());
    let scan_frame = kept
        .iter()
        .find(|k| Some(k.channel) == scan_channel)
        .map(|k| k.frame.clone());
    let mount = match (&base, &scan_frame) {
        (Some(base), Some(laser)) => mounts
            .iter()
            .find(|(parent, child, _)| parent == base && child == laser)
            .map(|m| m.2),
        _ => None,
    };
    let events = kept
        .into_iter()
        .filter(|k| Some(k.channel) == scan_channel || Some(k.channel) == odom_channel)
        .map(|k| match k.event {
            LogEvent::Scan(mut s) => {
                s.mount = mount;
                LogEvent::Scan(s)
            }
            e => e,
        })
        .collect();
    Ok(RobotLog {
        path: path.to_path_buf(),
        format: LogFormat::Rosbag2,
        timestamps: Timestamps::Logged,
        events,
    })
}

/// `std_msgs/Header`: the stamp in seconds and the frame.
fn header<'a>(r: &mut CdrReader<'a>) -> Result<(f64, &'a str), CdrError> {
    let sec = r.i32("header stamp")?;
    let nanosec = r.u32("header stamp")?;
    let frame = r.string("header frame_id")?;
    Ok((f64::from(sec) + f64::from(nanosec) * 1e-9, frame))
}

/// A pose (position, quaternion) as a planar pose: x, y and the yaw.
fn planar_pose(r: &mut CdrReader) -> Result<Pose2, CdrError> {
    let (x, y, _z) = (r.f64("position")?, r.f64("position")?, r.f64("position")?);
    let q = [
        r.f64("orientation")?,
        r.f64("orientation")?,
        r.f64("orientation")?,
        r.f64("orientation")?,
    ];
    Ok(Pose2::new(x, y, yaw(q)))
}

/// The yaw of quaternion (x, y, z, w).
fn yaw([x, y, z, w]: [f64; 4]) -> f64 {
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

fn decode_scan(data: &[u8]) -> Result<(String, LoggedScan), CdrError> {
    let mut r = CdrReader::new(data)?;
    let (t_s, frame) = header(&mut r)?;
    let angle_min = r.f32("angle_min")?;
    let _angle_max = r.f32("angle_max")?;
    let increment = r.f32("angle_increment")?;
    r.skip::<4>(2, "time_increment and scan_time")?;
    let range_min = r.f32("range_min")?;
    let range_max = r.f32("range_max")?;
    let mut ranges_m = r.f32s("ranges")?;
    for v in &mut ranges_m {
        if *v < range_min {
            *v = f32::NAN;
        }
    }
    let stated = f64::from(range_max);
    Ok((
        frame.to_owned(),
        LoggedScan {
            t_s,
            ranges_m,
            angle_min_rad: f64::from(angle_min),
            angle_increment_rad: f64::from(increment),
            range_max_m: (stated.is_finite() && stated > 0.0).then_some(stated),
            logged_pose: None,
            odometry: None,
            mount: None,
        },
    ))
}

fn decode_odometry(data: &[u8]) -> Result<(String, String, f64, Pose2), CdrError> {
    let mut r = CdrReader::new(data)?;
    let (t_s, frame) = header(&mut r)?;
    let child = r.string("child_frame_id")?;
    let pose = planar_pose(&mut r)?;
    Ok((frame.to_owned(), child.to_owned(), t_s, pose))
}

/// Each transform of a `TFMessage`: parent frame, child frame, planar pose.
fn decode_tf(data: &[u8]) -> Result<Vec<(String, String, Pose2)>, CdrError> {
    let mut r = CdrReader::new(data)?;
    // A transform takes at least 7 doubles.
    let n = r.len(56, "transforms")?;
    (0..n)
        .map(|_| {
            let (_, parent) = header(&mut r)?;
            let child = r.string("child_frame_id")?;
            let pose = planar_pose(&mut r)?;
            Ok((parent.to_owned(), child.to_owned(), pose))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_record::msgs;

    #[test]
    fn our_own_scan_and_odometry_messages_decode() {
        let scan = msgs::laser_scan(12.5, "laser", -1.0, 0.5, 8.0, &[1.0, f32::INFINITY, 3.0]);
        let (frame, s) = decode_scan(&scan).unwrap();
        assert_eq!(frame, "laser");
        assert_eq!(s.t_s, 12.5);
        assert_eq!((s.angle_min_rad, s.angle_increment_rad), (-1.0, 0.5));
        assert_eq!(s.range_max_m, Some(8.0));
        assert_eq!(s.ranges_m[1], f32::INFINITY);
        let odom = msgs::odometry(3.0, "odom", "base_link", (1.0, 2.0, 0.5), (0.0, 0.0));
        let (frame, child, t, pose) = decode_odometry(&odom).unwrap();
        assert_eq!(
            (frame.as_str(), child.as_str(), t),
            ("odom", "base_link", 3.0)
        );
        assert!((pose.x - 1.0).abs() < 1e-12 && (pose.theta - 0.5).abs() < 1e-12);
    }
}

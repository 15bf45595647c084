//! `usar ros2 btm`: the passive BTM builder ([`usar_btm::build::passive`]) as a ROS 2 node on
//! a robot's `/scan` and `/odom`, its poses by odometry corrected by correlative scan matching.
//! Every second it publishes the BTM so far on `/markers` (`visualization_msgs/MarkerArray`:
//! a sphere per node — divergence blue, free space green, terminal grey — and one line list
//! of the links); when it stops it makes the end node and, with a store, has written every
//! node and link to the BTM database as it went.

use crate::msgs::{self, Header, Marker, MarkerArray};
use crate::{
    Bridge, BridgeError, BridgeOptions, SensorFeed, StopFlag, Topics, qos, scan_reading, stopped,
    types,
};
use std::time::{Duration, Instant};
use usar_btm::Btm;
use usar_btm::build::BuildConfig;
use usar_btm::build::passive::PassiveBuilder;
use usar_btm::model::kind;
use usar_btm::store::BtmStore;
use usar_log::matcher::{MatcherParams, Tracker};
use usar_map::localization::ScanView;

/// The BTM as markers.
pub fn btm_markers(t: f64, btm: &Btm) -> MarkerArray {
    let mut markers = vec![Marker::delete_all(t, "btm")];
    for n in &btm.nodes {
        let rgba = match n.kind.as_str() {
            kind::DIVERGENCE => [0.2, 0.4, 1.0, 1.0],
            kind::FREE_SPACE => [0.1, 0.7, 0.2, 1.0],
            _ => [0.5, 0.5, 0.5, 1.0],
        };
        markers.push(Marker::sphere(
            t,
            "btm",
            n.id as i32,
            (n.x_m, n.y_m),
            0.35,
            rgba,
        ));
    }
    let mut points = Vec::new();
    for l in &btm.links {
        if let (Some(a), Some(b)) = (btm.node(l.start), l.end.and_then(|e| btm.node(e))) {
            points.push(msgs::Point {
                x: a.x_m,
                y: a.y_m,
                z: 0.0,
            });
            points.push(msgs::Point {
                x: b.x_m,
                y: b.y_m,
                z: 0.0,
            });
        }
    }
    markers.push(Marker {
        header: Header::new(t, "map"),
        ns: "btm_links".into(),
        r#type: Marker::LINE_LIST,
        scale: msgs::Vector3 {
            x: 0.08,
            y: 0.0,
            z: 0.0,
        },
        color: msgs::ColorRgba {
            r: 0.3,
            g: 0.95,
            b: 0.55,
            a: 0.8,
        },
        points,
        ..Marker::default()
    });
    MarkerArray { markers }
}

/// Runs the node until `stop` is set or `duration_s` wall seconds have passed; returns the
/// BTM with its end node.
#[allow(clippy::too_many_arguments)]
pub fn run_btm(
    config: BuildConfig,
    robot_width_m: f64,
    scan_matching: bool,
    store: Option<&BtmStore>,
    duration_s: Option<f64>,
    bridge: &BridgeOptions,
    topics: &Topics,
    stop: &StopFlag,
) -> Result<Btm, BridgeError> {
    let mut node = Bridge::new("usar_btm", bridge)?;
    let mut feed = SensorFeed::new(&mut node, topics)?;
    let markers =
        node.publisher::<MarkerArray>(&topics.markers, types::MARKER_ARRAY, qos::reliable())?;
    let mut builder = PassiveBuilder::new(config, robot_width_m, store);
    let mut tracker = Tracker::new(scan_matching.then(MatcherParams::default));
    let started = Instant::now();
    let mut next = Duration::ZERO;
    let mut stamp = 0.0;
    let mut failed = None;
    while !stopped(stop) && duration_s.is_none_or(|d| started.elapsed().as_secs_f64() < d) {
        let busy = feed.poll(|at, scan| {
            let view = ScanView::from_scan(&scan_reading(scan, at));
            let pose = tracker.update(at, &view.points);
            if failed.is_none()
                && let Err(e) = builder.observe(pose, &view)
            {
                failed = Some(e);
            }
            stamp = scan.header.stamp.as_s();
        });
        if let Some(e) = failed.take() {
            return Err(e.into());
        }
        if started.elapsed() >= next {
            next = started.elapsed() + Duration::from_secs(1);
            markers
                .publish(btm_markers(stamp, builder.btm()))
                .map_err(crate::dds)?;
        }
        if !busy {
            std::thread::sleep(Duration::from_millis(5));
        }
    }
    let btm = builder.finish()?;
    markers
        .publish(btm_markers(stamp, &btm))
        .map_err(crate::dds)?;
    Ok(btm)
}

//! A BTM build recorded as it runs (`usar btm build --record`): [`BtmRecorder`] takes what
//! the build shows four times per simulated second ([`BuildProgress`]) and writes `/clock`,
//! `/tf` (`map` → `crawler` at its true pose) at that rate, and every second the crawler's
//! `/crawler/scan`, its own pose estimate as `/crawler/odom` and the map built so far as `/btm`
//! markers (a sphere per node, a line list of the links).

use crate::msgs::{self, Frame, Marker, Shape};
use crate::recording::Sticky;
use crate::team::{Schedule, sphere};
use crate::{RecordError, Recording};
use std::io::{Seek, Write};
use usar_btm::Btm;
use usar_btm::build::BuildProgress;

/// The crawler's BTM: a sphere per node, one line list of its links between nodes (an empty
/// array without a map).
pub(crate) fn btm_markers(t: f64, btm: Option<&Btm>) -> Vec<u8> {
    let Some(btm) = btm else {
        return msgs::marker_array(t, "map", &[]);
    };
    let green = [0.3, 0.95, 0.55, 1.0];
    let mut markers: Vec<Marker<'_>> = btm
        .nodes
        .iter()
        .map(|n| sphere("btm_nodes", n.id as i32, (n.x_m, n.y_m), 0.3, green))
        .collect();
    let mut points = Vec::new();
    for l in &btm.links {
        if let (Some(a), Some(b)) = (btm.node(l.start), l.end.and_then(|e| btm.node(e))) {
            points.push((a.x_m, a.y_m));
            points.push((b.x_m, b.y_m));
        }
    }
    markers.push(Marker {
        ns: "btm_links",
        id: 0,
        shape: Shape::LineList,
        at: (0.0, 0.0, 0.05),
        scale: (0.08, 0.0, 0.0),
        rgba: [0.3, 0.95, 0.55, 0.8],
        points,
        text: String::new(),
    });
    msgs::marker_array(t, "map", &markers)
}

/// See the [module documentation](self).
pub struct BtmRecorder<W: Write + Seek> {
    sink: Sticky<W>,
    schedule: Schedule,
}

impl<W: Write + Seek> BtmRecorder<W> {
    pub fn new(recording: Recording<W>) -> Self {
        Self {
            sink: Sticky::new(recording),
            schedule: Schedule::default(),
        }
    }

    pub fn observe(&mut self, p: &BuildProgress<'_>) {
        let schedule = &mut self.schedule;
        self.sink.write_with(|rec| record(rec, schedule, p));
    }

    /// Completes the file; the messages written, or the error that ended the recording.
    pub fn finish(self) -> Result<u64, RecordError> {
        self.sink.finish()
    }
}

fn record<W: Write + Seek>(
    rec: &mut Recording<W>,
    schedule: &mut Schedule,
    p: &BuildProgress<'_>,
) -> Result<(), RecordError> {
    let t = p.time_s;
    rec.write("/clock", msgs::clock_type, t, &msgs::clock(t))?;
    let truth = Frame {
        parent: "map",
        child: "crawler",
        x: p.truth.x,
        y: p.truth.y,
        yaw: p.truth.theta,
    };
    rec.write("/tf", msgs::tf_type, t, &msgs::tf(t, &[truth]))?;
    if !schedule.sensors_due(t) {
        return Ok(());
    }
    let view = p.scan;
    let ranges: Vec<f32> = view
        .beams
        .iter()
        .map(|b| b.map_or(f32::INFINITY, |q| q.x.hypot(q.y) as f32))
        .collect();
    let scan = msgs::laser_scan(
        t,
        "crawler",
        view.angle_min_rad,
        view.angle_increment_rad,
        view.max_range_m,
        &ranges,
    );
    rec.write("/crawler/scan", msgs::laser_scan_type, t, &scan)?;
    let e = p.estimated;
    let odom = msgs::odometry(t, "map", "crawler", (e.x, e.y, e.theta), (0.0, 0.0));
    rec.write("/crawler/odom", msgs::odometry_type, t, &odom)?;
    rec.write(
        "/btm",
        msgs::marker_array_type,
        t,
        &btm_markers(t, Some(p.btm)),
    )
}

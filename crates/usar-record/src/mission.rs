//! A mission recorded as it runs: [`MissionRecorder`] is a [`MissionHook`] that writes, at the
//! simulated rates a viewer needs,
//!
//! | topic | type | when |
//! |---|---|---|
//! | `/clock` | `rosgraph_msgs/Clock` | every step |
//! | `/tf` | `tf2_msgs/TFMessage`: `map` → each robot (`team_1`…, `crawler`, `rescuer`) | every step |
//! | `/team_K/scan` | `sensor_msgs/LaserScan`: the robot's last scan, in its frame | every second |
//! | `/ROBOT/odom` | `nav_msgs/Odometry`: what its wheels tell, in `map` | every second |
//! | `/map` | `nav_msgs/OccupancyGrid`: the base station's merged map | every 2.5 s |
//! | `/btm` | `visualization_msgs/MarkerArray`: the crawler's BTM, nodes and links | every second |
//! | `/victims` | `MarkerArray`: the team's reports and the rescuer's possible victims | every second |
//! | `/goals` | `MarkerArray`: where each team robot is heading | every second |
//!
//! `/tf` gives the robots' true poses (the recording is the evaluation's picture of the run);
//! scans, odometry, the map, the BTM, the victims and the goals are what the robots reported.

use crate::msgs::{self, Frame, Marker, Shape};
use crate::{RecordError, Recording};
use std::io::{Seek, Write};
use usar_map::CellClass;
use usar_mission::{LiveMission, MissionHook};
use usar_rescue::VictimMark;

/// The rates of the table in the [module documentation](self), simulated seconds.
const SENSOR_PERIOD_S: f64 = 1.0;
const MAP_PERIOD_S: f64 = 2.5;

/// See the [module documentation](self).
pub struct MissionRecorder<W: Write + Seek> {
    recording: Recording<W>,
    next_sensors_s: f64,
    next_map_s: f64,
    /// The first write that failed: the mission is ended and the error reported.
    pub error: Option<RecordError>,
}

impl<W: Write + Seek> MissionRecorder<W> {
    pub fn new(recording: Recording<W>) -> Self {
        Self {
            recording,
            next_sensors_s: 0.0,
            next_map_s: 0.0,
            error: None,
        }
    }

    /// Completes the file; the messages written, or the error that ended the recording.
    pub fn finish(self) -> Result<u64, RecordError> {
        match self.error {
            Some(e) => Err(e),
            None => self.recording.finish(),
        }
    }

    fn record(&mut self, live: &LiveMission<'_, '_>) -> Result<(), RecordError> {
        let t = live.time_s();
        let rec = &mut self.recording;
        rec.write("/clock", msgs::clock_type, t, &msgs::clock(t))?;
        let robots = robots(live);
        let truth = live.evaluator();
        let frames: Vec<Frame<'_>> = robots
            .iter()
            .map(|(name, id)| {
                let p = truth.robot(*id).pose;
                Frame {
                    parent: "map",
                    child: name,
                    x: p.x,
                    y: p.y,
                    yaw: p.theta,
                }
            })
            .collect();
        rec.write("/tf", msgs::tf_type, t, &msgs::tf(t, &frames))?;
        if t + 1e-9 >= self.next_sensors_s {
            self.next_sensors_s += SENSOR_PERIOD_S;
            let team = live.team();
            for k in 0..live.team_len() {
                if let Some(scan) = team.last_scan(k) {
                    let frame = format!("team_{}", k + 1);
                    let data = msgs::laser_scan(
                        t,
                        &frame,
                        scan.angle_min_rad,
                        scan.angle_increment_rad,
                        scan.max_range_m,
                        &scan.ranges_m,
                    );
                    rec.write(&format!("/{frame}/scan"), msgs::laser_scan_type, t, &data)?;
                }
            }
            for (name, id) in &robots {
                let r = truth.robot(*id);
                let e = r.odometry.estimate;
                let v = r.last_motion();
                let data = msgs::odometry(
                    t,
                    "map",
                    name,
                    (e.x, e.y, e.theta),
                    (v.linear_mps, v.angular_radps),
                );
                rec.write(&format!("/{name}/odom"), msgs::odometry_type, t, &data)?;
            }
            rec.write("/btm", msgs::marker_array_type, t, &btm_markers(t, live))?;
            rec.write(
                "/victims",
                msgs::marker_array_type,
                t,
                &victim_markers(t, live),
            )?;
            rec.write("/goals", msgs::marker_array_type, t, &goal_markers(t, live))?;
        }
        if t + 1e-9 >= self.next_map_s {
            self.next_map_s += MAP_PERIOD_S;
            rec.write("/map", msgs::occupancy_grid_type, t, &merged_map(t, live))?;
        }
        Ok(())
    }
}

impl<W: Write + Seek> MissionHook for MissionRecorder<W> {
    fn after_decide(&mut self, live: &mut LiveMission<'_, '_>) -> bool {
        if self.error.is_some() {
            return false;
        }
        match self.record(live) {
            Ok(()) => true,
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }
}

/// Every robot's frame name and host id: `team_1`…, `crawler`, `rescuer`.
fn robots(live: &LiveMission<'_, '_>) -> Vec<(String, usar_sim::RobotId)> {
    let mut out: Vec<_> = (0..live.team_len())
        .filter_map(|k| live.team_robot(k).map(|id| (format!("team_{}", k + 1), id)))
        .collect();
    out.extend(live.crawler_robot().map(|id| ("crawler".to_string(), id)));
    out.extend(live.rescuer_robot().map(|id| ("rescuer".to_string(), id)));
    out
}

/// The base station's merged map: −1 unknown, 0 free, 100 occupied.
fn merged_map(t: f64, live: &LiveMission<'_, '_>) -> Vec<u8> {
    let merged = &live.team().base_station().merged;
    let g = *merged.geometry();
    let data: Vec<i8> = (0..g.len())
        .map(|i| match merged.class_at_index(i) {
            CellClass::Unknown => -1,
            CellClass::Free => 0,
            CellClass::Occupied => 100,
        })
        .collect();
    msgs::occupancy_grid(
        t,
        "map",
        g.resolution_m,
        (g.width, g.height),
        (g.origin.x, g.origin.y),
        &data,
    )
}

fn sphere(
    ns: &'static str,
    id: i32,
    (x, y): (f64, f64),
    size: f64,
    rgba: [f32; 4],
) -> Marker<'static> {
    Marker {
        ns,
        id,
        shape: Shape::Sphere,
        at: (x, y, 0.1),
        scale: (size, size, size),
        rgba,
        points: Vec::new(),
        text: String::new(),
    }
}

/// The crawler's BTM: a sphere per node, one line list of its links between nodes.
fn btm_markers(t: f64, live: &LiveMission<'_, '_>) -> Vec<u8> {
    let Some(btm) = live.crawler().map(|c| c.btm()) else {
        return msgs::marker_array(t, "map", &[]);
    };
    let mut markers: Vec<Marker<'_>> = btm
        .nodes
        .iter()
        .map(|n| {
            sphere(
                "btm_nodes",
                n.id as i32,
                (n.x_m, n.y_m),
                0.3,
                [0.3, 0.95, 0.55, 1.0],
            )
        })
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

/// Yellow: undecided; green: a victim (tagged or confirmed); grey: dismissed.
fn victim_colour(decided: Option<bool>) -> [f32; 4] {
    match decided {
        None => [1.0, 0.85, 0.2, 1.0],
        Some(true) => [0.2, 1.0, 0.2, 1.0],
        Some(false) => [0.5, 0.5, 0.5, 1.0],
    }
}

fn victim_markers(t: f64, live: &LiveMission<'_, '_>) -> Vec<u8> {
    let mut markers = Vec::new();
    for (k, e) in live.board().entries.iter().enumerate() {
        let decided = e.confirmed.map(|(tag, _)| tag);
        markers.push(sphere(
            "team_reports",
            k as i32,
            (e.at.x, e.at.y),
            0.5,
            victim_colour(decided),
        ));
    }
    if let Some(r) = live.rescuer()
        && let Some(agent) = r.agent()
    {
        for (k, ((c, row), mark, _)) in agent.possible_victims().enumerate() {
            let p = r.zone().cell_center(usar_world::Cell::new(c, row));
            let decided = match mark {
                VictimMark::Pending => None,
                VictimMark::Tagged => Some(true),
                VictimMark::Dismissed => Some(false),
            };
            markers.push(sphere(
                "rescuer",
                k as i32,
                (p.x, p.y),
                0.5,
                victim_colour(decided),
            ));
        }
    }
    msgs::marker_array(t, "map", &markers)
}

fn goal_markers(t: f64, live: &LiveMission<'_, '_>) -> Vec<u8> {
    let team = live.team();
    let markers: Vec<Marker<'_>> = (0..live.team_len())
        .filter_map(|k| {
            let g = team.robot_goal(k)?;
            Some(sphere(
                "goals",
                k as i32,
                (g.x, g.y),
                0.25,
                [0.24, 0.65, 1.0, 0.9],
            ))
        })
        .collect();
    msgs::marker_array(t, "map", &markers)
}

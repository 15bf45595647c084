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

use crate::btm::btm_markers;
use crate::msgs;
use crate::recording::Sticky;
use crate::team::{
    Schedule, goal_markers, merged_map, sphere, write_clock_and_tf, write_odometry,
    write_team_scans,
};
use crate::{RecordError, Recording};
use std::io::{Seek, Write};
use usar_mission::{LiveMission, MissionHook};
use usar_rescue::VictimMark;
use usar_sim::SimRobot;

/// See the [module documentation](self).
pub struct MissionRecorder<W: Write + Seek> {
    /// A failed write ends the mission; the error is reported by `finish`.
    sink: Sticky<W>,
    schedule: Schedule,
}

impl<W: Write + Seek> MissionRecorder<W> {
    pub fn new(recording: Recording<W>) -> Self {
        Self {
            sink: Sticky::new(recording),
            schedule: Schedule::default(),
        }
    }

    /// Completes the file; the messages written, or the error that ended the recording.
    pub fn finish(self) -> Result<u64, RecordError> {
        self.sink.finish()
    }
}

fn record<W: Write + Seek>(
    rec: &mut Recording<W>,
    schedule: &mut Schedule,
    live: &LiveMission<'_, '_>,
) -> Result<(), RecordError> {
    let t = live.time_s();
    let truth = live.evaluator();
    let robots: Vec<(String, &SimRobot)> = robots(live)
        .into_iter()
        .map(|(name, id)| (name, truth.robot(id)))
        .collect();
    write_clock_and_tf(rec, t, &robots)?;
    if schedule.sensors_due(t) {
        write_team_scans(rec, t, live.team(), live.team_len())?;
        write_odometry(rec, t, &robots)?;
        let btm = live.crawler().map(|c| c.btm());
        rec.write("/btm", msgs::marker_array_type, t, &btm_markers(t, btm))?;
        rec.write(
            "/victims",
            msgs::marker_array_type,
            t,
            &victim_markers(t, live),
        )?;
        let goals = goal_markers(t, live.team(), live.team_len());
        rec.write("/goals", msgs::marker_array_type, t, &goals)?;
    }
    if schedule.map_due(t) {
        let map = merged_map(t, live.team().base_station());
        rec.write("/map", msgs::occupancy_grid_type, t, &map)?;
    }
    Ok(())
}

impl<W: Write + Seek> MissionHook for MissionRecorder<W> {
    /// A failed write ends the mission.
    fn after_decide(&mut self, live: &mut LiveMission<'_, '_>) -> bool {
        let schedule = &mut self.schedule;
        self.sink.write_with(|rec| record(rec, schedule, live))
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

//! A paper-002 team run recorded as it runs (`usar team run --record`, `usar explore
//! --record`): [`TeamRecorder`] observes a [`TeamMission`] after each step and writes the
//! team's topics of the [mission table](crate::MissionRecorder) — `/clock` and `/tf` every
//! step, `/team_K/scan`, `/team_K/odom` and `/goals` every second, the merged `/map` every
//! 2.5 s. The pieces are shared with the mission recorder.

use crate::msgs::{self, Frame, Marker, Shape};
use crate::recording::Sticky;
use crate::{RecordError, Recording};
use std::io::{Seek, Write};
use usar_map::CellClass;
use usar_sim::SimRobot;
use usar_team::base_station::BaseStation;
use usar_team::{TeamController, TeamMission};

/// The rates of the recorded topics, simulated seconds.
pub(crate) const SENSOR_PERIOD_S: f64 = 1.0;
pub(crate) const MAP_PERIOD_S: f64 = 2.5;

/// When the periodic topics are due.
#[derive(Debug, Default)]
pub(crate) struct Schedule {
    next_sensors_s: f64,
    next_map_s: f64,
}

impl Schedule {
    pub fn sensors_due(&mut self, t: f64) -> bool {
        let due = t + 1e-9 >= self.next_sensors_s;
        if due {
            self.next_sensors_s += SENSOR_PERIOD_S;
        }
        due
    }

    pub fn map_due(&mut self, t: f64) -> bool {
        let due = t + 1e-9 >= self.next_map_s;
        if due {
            self.next_map_s += MAP_PERIOD_S;
        }
        due
    }
}

/// `/clock` and `/tf`: `map` → each named robot at its true pose.
pub(crate) fn write_clock_and_tf<W: Write + Seek>(
    rec: &mut Recording<W>,
    t: f64,
    robots: &[(String, &SimRobot)],
) -> Result<(), RecordError> {
    rec.write("/clock", msgs::clock_type, t, &msgs::clock(t))?;
    let frames: Vec<Frame<'_>> = robots
        .iter()
        .map(|(name, r)| Frame {
            parent: "map",
            child: name,
            x: r.pose.x,
            y: r.pose.y,
            yaw: r.pose.theta,
        })
        .collect();
    rec.write("/tf", msgs::tf_type, t, &msgs::tf(t, &frames))
}

/// `/ROBOT/odom`: what each robot's wheels tell, in `map`.
pub(crate) fn write_odometry<W: Write + Seek>(
    rec: &mut Recording<W>,
    t: f64,
    robots: &[(String, &SimRobot)],
) -> Result<(), RecordError> {
    for (name, r) in robots {
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
    Ok(())
}

/// `/team_K/scan`: each team robot's last scan, in its frame.
pub(crate) fn write_team_scans<W: Write + Seek>(
    rec: &mut Recording<W>,
    t: f64,
    team: &TeamController,
    robots: usize,
) -> Result<(), RecordError> {
    for k in 0..robots {
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
    Ok(())
}

/// The base station's merged map: −1 unknown, 0 free, 100 occupied.
pub(crate) fn merged_map(t: f64, base: &BaseStation) -> Vec<u8> {
    let merged = &base.merged;
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

pub(crate) fn sphere(
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

/// `/goals`: where each team robot is heading.
pub(crate) fn goal_markers(t: f64, team: &TeamController, robots: usize) -> Vec<u8> {
    let markers: Vec<Marker<'_>> = (0..robots)
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

/// See the [module documentation](self).
pub struct TeamRecorder<W: Write + Seek> {
    sink: Sticky<W>,
    schedule: Schedule,
}

impl<W: Write + Seek> TeamRecorder<W> {
    pub fn new(recording: Recording<W>) -> Self {
        Self {
            sink: Sticky::new(recording),
            schedule: Schedule::default(),
        }
    }

    /// Records the mission as it stands after a step.
    pub fn observe(&mut self, mission: &TeamMission) {
        let schedule = &mut self.schedule;
        self.sink
            .write_with(|rec| record_team(rec, schedule, mission));
    }

    /// Completes the file; the messages written, or the error that ended the recording.
    pub fn finish(self) -> Result<u64, RecordError> {
        self.sink.finish()
    }
}

fn record_team<W: Write + Seek>(
    rec: &mut Recording<W>,
    schedule: &mut Schedule,
    mission: &TeamMission,
) -> Result<(), RecordError> {
    let sim = mission.simulation();
    let t = sim.time_s();
    let robots: Vec<(String, &SimRobot)> = mission
        .robot_ids()
        .iter()
        .enumerate()
        .map(|(k, &id)| (format!("team_{}", k + 1), sim.robot(id)))
        .collect();
    write_clock_and_tf(rec, t, &robots)?;
    let team = mission.team();
    if schedule.sensors_due(t) {
        write_team_scans(rec, t, team, robots.len())?;
        write_odometry(rec, t, &robots)?;
        rec.write(
            "/goals",
            msgs::marker_array_type,
            t,
            &goal_markers(t, team, robots.len()),
        )?;
    }
    if schedule.map_due(t) {
        rec.write(
            "/map",
            msgs::occupancy_grid_type,
            t,
            &merged_map(t, mission.base_station()),
        )?;
    }
    Ok(())
}

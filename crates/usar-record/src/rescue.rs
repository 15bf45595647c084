//! A paper-000 evaluation run recorded step by step (`usar maxq eval --record`):
//! [`RescueRecorder`] observes the MAXQ robot's domain after every primitive step and writes
//! `/clock` (the run's time) and `/tf` (`map` → `rescuer` at its cell's centre, facing its
//! heading) at each step, and every [`MAP_EVERY`] steps the robot's cell map as `/rescuer/map`
//! (`nav_msgs/OccupancyGrid` on the scene's cell grid: −1 unknown, 0 open, 50 climbable rubble,
//! 100 obstacle, non-climbable or a victim's cell) and its possible victims as `/victims`
//! markers (yellow undecided, green tagged, grey dismissed).

use crate::msgs;
use crate::recording::Sticky;
use crate::team::sphere;
use crate::{RecordError, Recording};
use std::io::{Seek, Write};
use usar_rescue::VictimMark;
use usar_rescue::cell_map::MapCell;
use usar_rescue::evaluation::EvalDomain;
use usar_world::Cell;

/// Primitive steps between two maps.
pub const MAP_EVERY: u64 = 10;

/// See the [module documentation](self).
pub struct RescueRecorder<W: Write + Seek> {
    sink: Sticky<W>,
    steps: u64,
}

impl<W: Write + Seek> RescueRecorder<W> {
    pub fn new(recording: Recording<W>) -> Self {
        Self {
            sink: Sticky::new(recording),
            steps: 0,
        }
    }

    pub fn observe(&mut self, domain: &EvalDomain<'_>) {
        let with_map = self.steps.is_multiple_of(MAP_EVERY);
        self.sink.write_with(|rec| record(rec, with_map, domain));
        self.steps += 1;
    }

    /// Completes the file; the messages written, or the error that ended the recording.
    pub fn finish(self) -> Result<u64, RecordError> {
        self.sink.finish()
    }
}

/// One step: the pose, and the map and the victims when `with_map`.
fn record<W: Write + Seek>(
    rec: &mut Recording<W>,
    with_map: bool,
    d: &EvalDomain<'_>,
) -> Result<(), RecordError> {
    let g = d.scene().view.geometry;
    let t = d.agent.stats.time_s;
    rec.write("/clock", msgs::clock_type, t, &msgs::clock(t))?;
    let robot = &d.agent.robot;
    let at = g.cell_center(robot.cell);
    let frame = msgs::Frame {
        parent: "map",
        child: "rescuer",
        x: at.x,
        y: at.y,
        yaw: f64::from(robot.heading) * std::f64::consts::FRAC_PI_2,
    };
    rec.write("/tf", msgs::tf_type, t, &msgs::tf(t, &[frame]))?;
    if !with_map {
        return Ok(());
    }
    let map = &d.agent.map;
    let data: Vec<i8> = map
        .cells
        .iter()
        .map(|c| match c {
            MapCell::Unknown => -1,
            MapCell::OpenUnvisited | MapCell::OpenVisited => 0,
            MapCell::ClimbableUnvisited | MapCell::ClimbableVisited => 50,
            MapCell::UnknownObstacle | MapCell::NonClimbable | MapCell::Victim => 100,
        })
        .collect();
    let grid = msgs::occupancy_grid(
        t,
        "map",
        g.resolution_m,
        (map.cols as u32, map.rows as u32),
        (g.origin.x, g.origin.y),
        &data,
    );
    rec.write("/rescuer/map", msgs::occupancy_grid_type, t, &grid)?;
    let markers: Vec<msgs::Marker<'_>> = d
        .possible_victims()
        .enumerate()
        .map(|(k, ((c, r), mark, _))| {
            let p = g.cell_center(Cell::new(c, r));
            let rgba = match mark {
                VictimMark::Pending => [1.0, 0.85, 0.2, 1.0],
                VictimMark::Tagged => [0.2, 1.0, 0.2, 1.0],
                VictimMark::Dismissed => [0.5, 0.5, 0.5, 1.0],
            };
            sphere("rescuer", k as i32, (p.x, p.y), 0.5, rgba)
        })
        .collect();
    rec.write(
        "/victims",
        msgs::marker_array_type,
        t,
        &msgs::marker_array(t, "map", &markers),
    )
}

//! What the robot reads at the end of a primitive: D_xy classified for the cell ahead, the
//! infrared ring as a mask over its neighbours, the thermal camera's warm regions in its zone —
//! all from its own sensors through the fleet's I/O.

use super::RescueController;
use crate::agent::{HeatReading, RescueAgent};
use crate::exploration::Direction;
use crate::perception::{RubbleClassifier, infrared_mask};
use usar_sim::host::FleetIo;
use usar_sim::sensors::DetectionId;
use usar_world::cellview::CellClass;
use usar_world::{Cell, Pose2, Rect};

/// Points this close to a cell's border are left out of its plane fit, metres: half the
/// 5 cm grid of the generated scenes (the cell-physics runs use half the scene's own grid).
pub(super) const DEPTH_MARGIN_M: f64 = 0.025;

impl RescueController {
    /// The pose the robot believes: the localization oracle's, else its odometry.
    pub(super) fn pose(io: &FleetIo<'_>) -> Pose2 {
        io.true_pose(0).unwrap_or_else(|| io.odometry(0).estimate)
    }

    /// The class D_xy gives the cell ahead (`None`: it lies outside the zone).
    pub(super) fn front(
        &self,
        agent: &RescueAgent<DetectionId>,
        classifier: &RubbleClassifier,
        io: &mut FleetIo<'_>,
    ) -> Option<CellClass> {
        let (dc, dr) = Direction::from_index(usize::from(agent.robot.heading)).step();
        let ahead = Cell::new(agent.robot.cell.col + dc, agent.robot.cell.row + dr);
        if !self.zone.contains(ahead) {
            return None;
        }
        let image = io.depth(0);
        let floor_m = image.sensor_z_m - io.spec(0).depth.mount_height_m;
        let centre = self.zone.cell_center(ahead);
        let half = 0.5 * self.zone.resolution_m;
        let rect = Rect::new(
            centre.x - half,
            centre.y - half,
            centre.x + half,
            centre.y + half,
        );
        Some(classifier.classify(&image, image.pose, floor_m, rect, centre))
    }

    /// Infrared hits closer than a cell, as a mask over [`crate::perception::INFRARED_NEIGHBOURS`].
    pub(super) fn infrared(&self, io: &mut FleetIo<'_>) -> u8 {
        infrared_mask(&io.infrared(0), self.zone.resolution_m)
    }

    /// The thermal camera's warm regions inside the zone.
    pub(super) fn heat(&self, io: &mut FleetIo<'_>) -> Vec<HeatReading<DetectionId>> {
        let pose = Self::pose(io);
        io.thermal(0)
            .into_iter()
            .filter_map(|t| {
                let at = pose
                    .position()
                    .offset(pose.theta + t.bearing_rad, t.range_m);
                let c = self.zone.world_to_cell(at);
                self.zone.contains(c).then_some(HeatReading {
                    cell: (c.col, c.row),
                    human_signature: t.human_signature,
                    size_m2: t.size_m2,
                    source: t.id,
                })
            })
            .collect()
    }
}

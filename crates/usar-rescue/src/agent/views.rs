//! What the robot shows of itself: to its operator (hand-off requests), to a display (its
//! possible victims, visited cells) and to a person tuning it live.

use super::{HeatSource, RescueAgent, Status, UncertainVictim};
use crate::cell_map::MapCell;
use crate::domain::VictimMark;
use crate::exploration::{Direction, ExplorationWeights, Explorer};
use crate::operator::NavigationRequest;
use usar_world::cellview::CellClass;

impl<T: HeatSource> RescueAgent<T> {
    /// What the operator is shown when asked to drive, with what the robot's cameras show of
    /// its four neighbours (by [`Direction::index`]: terrain, and whether a victim lies there).
    pub fn navigation_request(&self, camera: [(CellClass, bool); 4]) -> NavigationRequest {
        let c = self.robot.cell;
        let mut neighbours = [MapCell::NonClimbable; 4];
        for d in Direction::ALL {
            let (dc, dr) = d.step();
            neighbours[d.index()] = self.map.get(c.col + dc, c.row + dr);
        }
        NavigationRequest {
            cell: (c.col, c.row),
            heading: self.heading(),
            neighbours,
            camera,
            suggested: self.desired_heading(),
        }
    }

    /// The uncertain possible victim at hand, if any (HC₂ asks the operator about it).
    pub fn uncertain_victim(&self) -> Option<UncertainVictim<T>> {
        let (k, _) = self.current?;
        let v = &self.victims[k];
        (v.status == Status::UncertainAtHand).then(|| UncertainVictim {
            cell: v.cell,
            probability: v.probability.unwrap_or(0.0),
            size_m2: v.first_size_m2,
            source: v.source,
        })
    }

    /// Replaces the exploration weights while the robot runs (the console's live w_l, w_p,
    /// w_q) and recomputes the guidance from the map as it is.
    pub fn set_exploration_weights(&mut self, weights: ExplorationWeights) {
        self.explorer = Explorer::new(weights, &self.map);
        if !self.done {
            self.replan();
        }
    }

    /// The possible victims met so far: cell, status and measured probability (if measured).
    pub fn possible_victims(
        &self,
    ) -> impl Iterator<Item = ((i32, i32), VictimMark, Option<f64>)> + '_ {
        self.victims
            .iter()
            .map(|v| (v.cell, mark(v.status), v.probability))
    }

    /// The possible victims met so far, by source, and what became of each.
    pub fn victim_sources(&self) -> impl Iterator<Item = (T, VictimMark)> + '_ {
        self.victims.iter().map(|v| (v.source, mark(v.status)))
    }

    /// Whether the robot is stuck (its navigation is handed to the operator).
    pub fn is_stuck(&self) -> bool {
        self.stuck
    }

    /// Whether the run is over (the robot exited).
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// Cells the robot has visited (row-major).
    pub fn visited(&self) -> impl Iterator<Item = bool> + '_ {
        self.map.cells.iter().map(|c| c.is_visited())
    }
}

/// What a status shows on a display.
fn mark(status: Status) -> VictimMark {
    match status {
        Status::Tagged => VictimMark::Tagged,
        Status::Rejected => VictimMark::Dismissed,
        _ => VictimMark::Pending,
    }
}

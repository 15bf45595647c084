//! The cell robot of paper 000: it occupies one coarse cell of the [`CellView`] and moves by the
//! primitive actions forward (F), backward (B) and rotate by θ. A move into a cell it cannot
//! enter (non-climbable rubble, a drop, climbable rubble for a robot that cannot climb, or out of
//! the arena) does not happen and counts as a collision.

use serde::{Deserialize, Serialize};
use usar_world::cellview::CellView;
use usar_world::{Cell, Pose2};

/// The rotation step θ. Paper 000 leaves θ open; 90° gives the four headings of a grid walk,
/// 45° lets the robot face and enter its diagonal neighbours (C₁…C₈ of Fig. 3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RotationStep {
    #[default]
    Quarter,
    Eighth,
}

impl RotationStep {
    fn headings(self) -> u8 {
        match self {
            RotationStep::Quarter => 4,
            RotationStep::Eighth => 8,
        }
    }
}

/// A primitive action of the cell robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CellAction {
    Forward,
    Backward,
    /// Rotate counter-clockwise by θ.
    RotateLeft,
    /// Rotate clockwise by θ.
    RotateRight,
}

impl CellAction {
    pub const ALL: [CellAction; 4] = [
        CellAction::Forward,
        CellAction::Backward,
        CellAction::RotateLeft,
        CellAction::RotateRight,
    ];
}

/// What an action did.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CellOutcome {
    Moved,
    Rotated,
    /// The move was refused: the robot stays where it is.
    Collided,
    /// The robot tried to climb onto rubble and its tracks slipped: the command did not take
    /// effect (paper 000 §VII-B: "physically stuck in a cell due to unsteady terrain"). Not a
    /// collision.
    Slipped,
}

/// A robot on the coarse cells. `heading` counts steps of θ counter-clockwise from east.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CellRobot {
    pub cell: Cell,
    pub heading: u8,
    pub rotation: RotationStep,
    pub can_climb: bool,
    pub collisions: u32,
    pub steps: u32,
}

impl CellRobot {
    pub fn new(cell: Cell, heading: u8, rotation: RotationStep, can_climb: bool) -> Self {
        Self {
            cell,
            heading: heading % rotation.headings(),
            rotation,
            can_climb,
            collisions: 0,
            steps: 0,
        }
    }

    /// Heading angle, radians counter-clockwise from east.
    pub fn heading_rad(&self) -> f64 {
        f64::from(self.heading) * std::f64::consts::TAU / f64::from(self.rotation.headings())
    }

    /// The (dcol, drow) of one cell ahead.
    pub fn ahead(&self) -> (i32, i32) {
        const EIGHT: [(i32, i32); 8] = [
            (1, 0),
            (1, 1),
            (0, 1),
            (-1, 1),
            (-1, 0),
            (-1, -1),
            (0, -1),
            (1, -1),
        ];
        let k = match self.rotation {
            RotationStep::Quarter => self.heading as usize * 2,
            RotationStep::Eighth => self.heading as usize,
        };
        EIGHT[k % 8]
    }

    /// The world pose at the centre of its cell, facing its heading.
    pub fn pose(&self, view: &CellView) -> Pose2 {
        let c = view.cell_center(self.cell);
        Pose2::new(c.x, c.y, usar_world::normalize_angle(self.heading_rad()))
    }

    /// Whether the robot may enter `target` from its cell: terrain it can cross, and for a
    /// diagonal step both cells beside the diagonal too (no squeezing between two piles).
    pub fn can_enter(&self, view: &CellView, target: Cell) -> bool {
        let (dc, dr) = (target.col - self.cell.col, target.row - self.cell.row);
        let ok = |c: Cell| view.is_passable(c, self.can_climb);
        ok(target)
            && (dc == 0
                || dr == 0
                || (ok(Cell::new(self.cell.col + dc, self.cell.row))
                    && ok(Cell::new(self.cell.col, self.cell.row + dr))))
    }

    /// The cell a forward or backward move aims at (`None` for a rotation).
    pub fn move_target(&self, action: CellAction) -> Option<Cell> {
        let (dc, dr) = self.ahead();
        let sign = match action {
            CellAction::Forward => 1,
            CellAction::Backward => -1,
            CellAction::RotateLeft | CellAction::RotateRight => return None,
        };
        Some(Cell::new(
            self.cell.col + sign * dc,
            self.cell.row + sign * dr,
        ))
    }

    /// Applies one primitive action among things the terrain classes do not show: a move into a
    /// cell for which `occupied` holds (a victim lying there) is a collision, and a move onto
    /// climbable rubble for which `slips` holds does not take effect ([`CellOutcome::Slipped`]).
    pub fn apply_with(
        &mut self,
        action: CellAction,
        view: &CellView,
        occupied: impl Fn(Cell) -> bool,
        slips: impl FnOnce(Cell) -> bool,
    ) -> CellOutcome {
        if let Some(target) = self.move_target(action) {
            if occupied(target) {
                self.steps += 1;
                self.collisions += 1;
                return CellOutcome::Collided;
            }
            if self.can_enter(view, target)
                && view.terrain_class(target) == usar_world::cellview::CellClass::Climbable
                && slips(target)
            {
                self.steps += 1;
                return CellOutcome::Slipped;
            }
        }
        self.apply(action, view)
    }

    /// Applies one primitive action.
    pub fn apply(&mut self, action: CellAction, view: &CellView) -> CellOutcome {
        self.steps += 1;
        let n = self.rotation.headings();
        match action {
            CellAction::RotateLeft => {
                self.heading = (self.heading + 1) % n;
                CellOutcome::Rotated
            }
            CellAction::RotateRight => {
                self.heading = (self.heading + n - 1) % n;
                CellOutcome::Rotated
            }
            CellAction::Forward | CellAction::Backward => {
                let (dc, dr) = self.ahead();
                let sign = if action == CellAction::Forward { 1 } else { -1 };
                let target = Cell::new(self.cell.col + sign * dc, self.cell.row + sign * dr);
                if self.can_enter(view, target) {
                    self.cell = target;
                    CellOutcome::Moved
                } else {
                    self.collisions += 1;
                    CellOutcome::Collided
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::cellview::{CellClass, CellViewParams};
    use usar_world::generate::{RubbleParams, generate_rubble};

    #[test]
    fn the_robot_never_enters_a_cell_it_cannot_cross() {
        let scene = generate_rubble(3, &RubbleParams::default());
        let view = CellView::from_scene(&scene, &CellViewParams::default());
        let start = view
            .cell_of(scene.start_poses[0].position())
            .expect("start inside");
        for (rotation, can_climb) in [(RotationStep::Quarter, true), (RotationStep::Eighth, false)]
        {
            let mut robot = CellRobot::new(start, 0, rotation, can_climb);
            let mut moved = 0;
            for k in 0..2000u32 {
                let action = CellAction::ALL[(k.wrapping_mul(2_654_435_761) >> 7) as usize % 4];
                let before = robot.cell;
                if robot.apply(action, &view) == CellOutcome::Moved {
                    moved += 1;
                    assert!(
                        view.is_passable(robot.cell, can_climb),
                        "entered {:?} ({:?})",
                        robot.cell,
                        view.class(robot.cell)
                    );
                    assert!(robot.cell.chebyshev(before) == 1);
                } else {
                    assert_eq!(robot.cell, before);
                }
                if !can_climb {
                    assert_ne!(view.terrain_class(robot.cell), CellClass::Climbable);
                }
            }
            assert!(
                moved > 100 && robot.collisions > 0,
                "moved {moved}, collisions {}",
                robot.collisions
            );
        }
    }

    #[test]
    fn victims_block_and_climbs_may_slip() {
        let scene = generate_rubble(3, &RubbleParams::default());
        let view = CellView::from_scene(&scene, &CellViewParams::default());
        let climbable = (0..view.classes.len())
            .map(|i| view.geometry.cell_of_index(i))
            .find(|&c| {
                view.terrain_class(c) == CellClass::Climbable
                    && view.is_passable(Cell::new(c.col - 1, c.row), true)
            })
            .expect("a climbable cell with a passable west neighbour");
        let from = Cell::new(climbable.col - 1, climbable.row);
        let mut r = CellRobot::new(from, 0, RotationStep::Quarter, true);
        assert_eq!(r.move_target(CellAction::Forward), Some(climbable));
        assert_eq!(
            r.apply_with(CellAction::Forward, &view, |_| false, |_| true),
            CellOutcome::Slipped
        );
        assert_eq!((r.cell, r.collisions, r.steps), (from, 0, 1));
        assert_eq!(
            r.apply_with(CellAction::Forward, &view, |c| c == climbable, |_| false),
            CellOutcome::Collided
        );
        assert_eq!((r.cell, r.collisions), (from, 1));
        assert_eq!(
            r.apply_with(CellAction::Forward, &view, |_| false, |_| false),
            CellOutcome::Moved
        );
        assert_eq!(r.cell, climbable);
    }

    #[test]
    fn headings_turn_counter_clockwise_from_east() {
        let mut r = CellRobot::new(Cell::new(5, 5), 0, RotationStep::Quarter, true);
        assert_eq!(r.ahead(), (1, 0));
        r.heading = 1;
        assert_eq!(r.ahead(), (0, 1));
        let mut r8 = CellRobot::new(Cell::new(5, 5), 3, RotationStep::Eighth, true);
        assert_eq!(r8.ahead(), (-1, 1));
        r8.heading = 7;
        assert_eq!(r8.ahead(), (1, -1));
    }
}

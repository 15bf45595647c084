//! A primitive executed: navigation begun and finished around the body's motion, Tag,
//! Reject and Exit, and what follows each (replanning, the count of primitives without
//! progress). Rewards are Table I's ([`crate::rewards`]).

use super::{Begun, CellReading, HeatSource, Move, RescueAgent, Status};
use crate::cell_map::MapCell;
use crate::exploration::Direction;
use crate::hierarchy::action;
use crate::rewards;
use usar_sim::{CellAction, CellOutcome};
use usar_world::cellview::CellClass;

impl<T: HeatSource> RescueAgent<T> {
    /// Begins primitive `a` (see [`action`]): a navigation primitive for the body, or Tag,
    /// Reject and Exit, done at once.
    pub fn begin(&mut self, a: usize) -> Begun<T> {
        let progress_before = self.progress;
        let act = match a {
            action::FORWARD => CellAction::Forward,
            action::BACKWARD => CellAction::Backward,
            action::ROTATE_LEFT => CellAction::RotateLeft,
            action::ROTATE_RIGHT => CellAction::RotateRight,
            action::TAG => {
                let tagged = self.tag();
                self.after(a, progress_before, self.progress);
                return Begun::Tagged(tagged);
            }
            action::REJECT => {
                let r = self.reject();
                self.after(a, progress_before, self.progress);
                return Begun::Done(r);
            }
            _ => {
                let r = self.exit();
                self.after(a, progress_before, self.progress);
                return Begun::Done(r);
            }
        };
        let by_operator = std::mem::take(&mut self.operator_turn) || self.teleoperated;
        self.operator_drove = by_operator;
        self.stats.steps += 1;
        let before = self.robot.cell;
        let (dc, dr) = self.heading().step();
        Begun::Move(Move {
            action: act,
            by_operator,
            before,
            desired: self.desired_heading(),
            ahead: self.map.index(before.col + dc, before.row + dr),
            came_against_obstacle: std::mem::take(&mut self.facing_obstacle_after_move),
            progress_before,
        })
    }

    /// Completes navigation primitive `m` after the body executed it (`self.robot` holds
    /// where it ended): `outcome` as the robot felt it, `felt` the terrain under it now, and
    /// the sensors' reading there. Returns Table I's reward.
    pub fn finish(
        &mut self,
        m: Move,
        outcome: CellOutcome,
        felt: CellClass,
        reading: CellReading<'_, T>,
    ) -> f64 {
        let before = m.before;
        let desired = m.desired;
        let reward = match outcome {
            CellOutcome::Collided => {
                if m.by_operator {
                    self.stats.operator_collisions += 1;
                } else {
                    self.stats.robot_collisions += 1;
                }
                if let Some(t) = self.robot.move_target(m.action)
                    && let Some(i) = self.map.index(t.col, t.row)
                    && self.map.cells[i] != MapCell::NonClimbable
                    && self.map.cells[i] != MapCell::Victim
                {
                    // The bump corrects the map: whatever the depth sensor said, the robot
                    // cannot drive there.
                    self.set_cell(i, MapCell::NonClimbable);
                    self.progress += 1;
                }
                rewards::COLLISION
            }
            CellOutcome::Slipped => {
                self.slips_in_row += 1;
                if !self.stuck && self.slips_in_row >= self.config.stuck_after_slips {
                    self.stuck = true;
                    self.stats.handoffs_stuck += 1;
                    self.handoffs_asked += 1;
                }
                rewards::VISITED
            }
            CellOutcome::Moved => {
                self.stale = true;
                self.slips_in_row = 0;
                self.stuck = false;
                let c = self.robot.cell;
                let i = self.index(c);
                let was = self.map.cells[i];
                self.set_cell(i, was.visited_on(felt));
                if was.is_visited() {
                    rewards::VISITED
                } else {
                    self.progress += 1;
                    let moved = Direction::ALL
                        .into_iter()
                        .find(|d| d.step() == (c.col - before.col, c.row - before.row));
                    if moved.is_some() && moved == desired {
                        rewards::UNVISITED_IN_DIRECTION
                    } else {
                        0.0
                    }
                }
            }
            CellOutcome::Rotated => {
                if m.came_against_obstacle
                    && let Some(i) = m.ahead
                    && !self.avoided[i]
                {
                    self.avoided[i] = true;
                    rewards::OBSTACLE_AVOIDED
                } else {
                    rewards::VISITED
                }
            }
        };
        self.perceive(reading);
        let moved_along = outcome == CellOutcome::Moved
            && desired.is_some_and(|d| {
                let c = self.robot.cell;
                d.step() == (c.col - before.col, c.row - before.row)
            });
        // A bump also corrects the map (progress), but it is never on course; nor is progress
        // off the heading (a cell classified while turning away from the one NG was sent to
        // face). Progress made by the replanning that follows (a victim brought at hand)
        // counts too (`after`).
        let faces_heading = desired == Some(self.heading());
        self.on_course = moved_along
            || (outcome != CellOutcome::Collided
                && self.progress != m.progress_before
                && faces_heading);
        self.collided = outcome == CellOutcome::Collided;
        if outcome == CellOutcome::Moved && m.action == CellAction::Forward {
            let (dc, dr) = self.heading().step();
            let c = self.robot.cell;
            self.facing_obstacle_after_move = matches!(
                self.map.get(c.col + dc, c.row + dr),
                MapCell::NonClimbable | MapCell::Victim
            );
        }
        let a = match m.action {
            CellAction::Forward => action::FORWARD,
            CellAction::Backward => action::BACKWARD,
            CellAction::RotateLeft => action::ROTATE_LEFT,
            CellAction::RotateRight => action::ROTATE_RIGHT,
        };
        self.after(a, m.progress_before, self.progress);
        reward
    }

    /// What follows every primitive: replanning, and for a navigation primitive the count of
    /// primitives without progress (stuck after `stuck_after_idle_steps`).
    fn after(&mut self, a: usize, progress_before: u32, progress_acted: u32) {
        if !self.done {
            self.replan();
        }
        if a <= action::ROTATE_RIGHT {
            if self.progress != progress_before {
                // Progress of the replanning (a victim brought at hand) is on course.
                if self.progress != progress_acted {
                    self.on_course |= !self.collided;
                }
                self.idle_steps = 0;
                self.stuck_idle = false;
            } else if !std::mem::take(&mut self.operator_drove) {
                self.idle_steps += 1;
                if !self.stuck_idle && self.idle_steps >= self.config.stuck_after_idle_steps {
                    self.stuck_idle = true;
                    self.stats.handoffs_stuck += 1;
                    self.handoffs_asked += 1;
                }
            }
        }
    }

    /// Tags the possible victim at hand: its source, or `None` when none is at hand.
    fn tag(&mut self) -> Option<T> {
        self.operator_turn = false;
        let at_hand = self.current.filter(|&(k, _)| {
            matches!(
                self.victims[k].status,
                Status::CertainAtHand | Status::UncertainAtHand
            )
        });
        let (k, _) = at_hand?;
        let source = self.victims[k].source;
        self.release(k, Status::Tagged);
        Some(source)
    }

    fn reject(&mut self) -> f64 {
        self.operator_turn = false;
        if let Some((k, _)) = self.current
            && matches!(
                self.victims[k].status,
                Status::CertainAtHand | Status::UncertainAtHand
            )
        {
            self.release(k, Status::Rejected);
        }
        0.0
    }

    fn exit(&mut self) -> f64 {
        self.done = true;
        if self.guidance.heading.is_some() {
            return rewards::EXIT_EARLY;
        }
        // A possible victim the robot could still reach and decide.
        if self.current.is_some() {
            rewards::EXIT_EXPLORED
        } else {
            rewards::EXIT_EXPLORED + rewards::TASK_COMPLETED
        }
    }
}

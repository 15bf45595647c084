//! Table I of paper 000: the transition rewards of the USAR hierarchy, exactly.
//!
//! | subtask | robot state transition | reward |
//! |---|---|---|
//! | Root | the overall USAR task is completed | +100 |
//! | NUR | exit the scene after exploring all of it | +10 |
//! | NUR | exit while known regions remain to explore | −10 |
//! | VI | correctly tagging a victim found in the scene | +10 |
//! | VI | Tag executed when no new victim is identified | −10 |
//! | NG | moving into an unvisited region in the desired exploration direction | +15 |
//! | NG | avoiding an obstacle | +10 |
//! | NG | obstacle collision | −20 |
//! | NG | navigating into already visited area | −1 |
//!
//! How each transition is recognised is documented at [`crate::domain::RescueDomain`]: a
//! navigation primitive that leaves the robot in an already visited cell (a turn, a slip, a
//! move into a visited cell) is "navigating into already visited area"; a move into an
//! unvisited cell off the desired direction is none of the rows and earns 0.

/// Root: the overall USAR task is completed (Exit with the scene explored and no victim left
/// undecided).
pub const TASK_COMPLETED: f64 = 100.0;
/// NUR: Exit after the whole reachable scene is explored.
pub const EXIT_EXPLORED: f64 = 10.0;
/// NUR: Exit while known regions remain to explore.
pub const EXIT_EARLY: f64 = -10.0;
/// VI: a new victim tagged correctly.
pub const TAG_CORRECT: f64 = 10.0;
/// VI: Tag when no new victim is identified.
pub const TAG_WRONG: f64 = -10.0;
/// NG: into an unvisited cell in the desired exploration direction.
pub const UNVISITED_IN_DIRECTION: f64 = 15.0;
/// NG: an obstacle avoided.
pub const OBSTACLE_AVOIDED: f64 = 10.0;
/// NG: a collision.
pub const COLLISION: f64 = -20.0;
/// NG: navigating in already visited area.
pub const VISITED: f64 = -1.0;

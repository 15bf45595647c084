//! b(p, r) on grid paths (paper 002 §3.2): the time to follow the planned path at the robot's
//! linear and angular speeds, length / v + Σ|turns| / ω.
//!
//! A bidder's paths to all candidates descend the same distance field towards the robot, so
//! they share their ends near it. [`TravelTimes`] memoises the turning accumulated from the
//! robot to every cell it has priced, so each cell of the field is walked at most once per
//! bidder instead of once per candidate; the sums are made in the same order as
//! [`grid_travel_time_s`], so the times are bit-for-bit the same.

use usar_map::planning::DistanceField;
use usar_world::{Cell, NEIGHBORS8};

/// The octant (0 = east, counter-clockwise in 45° steps) of each move of [`NEIGHBORS8`] (east,
/// north, west, south, north-east, north-west, south-west, south-east).
const DIRECTION_OCTANT: [u8; 8] = [0, 2, 4, 6, 1, 3, 5, 7];
/// Octant of a source cell (no move into it).
const NO_MOVE: u8 = u8::MAX;

/// The octant of the move from `a` to its neighbour `b` (0 if they are not neighbours).
fn octant(a: Cell, b: Cell) -> u8 {
    NEIGHBORS8
        .iter()
        .position(|&(dc, dr)| (b.col - a.col, b.row - a.row) == (dc, dr))
        .map_or(0, |k| DIRECTION_OCTANT[k])
}

/// The turn between two octants, radians.
fn turn(from: u8, to: u8) -> f64 {
    let k = (to + 8 - from) % 8;
    f64::from(k.min(8 - k)) * std::f64::consts::FRAC_PI_4
}

/// The turn onto the first step of a path (octant `to`) from heading `theta`, radians.
fn first_turn(theta: f64, to: u8) -> f64 {
    let heading = f64::from(to) * std::f64::consts::FRAC_PI_4;
    usar_world::normalize_angle(heading - theta).abs()
}

/// b(p, r) on a grid path given from the goal back to the robot (`cells`, as a distance field's
/// descent returns it) of `length_m`: length / v + Σ|turns| / ω, the turns being the robot's
/// turn onto the first step and the 45° multiples between consecutive steps — what
/// [`crate::criteria::travel_time_s`] gives on the cell centres, without a trigonometric call
/// per step. The reference for [`TravelTimes`].
pub fn grid_travel_time_s(
    cells: &[Cell],
    length_m: f64,
    theta: f64,
    spec: &usar_sim::RobotSpec,
) -> f64 {
    let mut turning = 0.0;
    let mut previous: Option<u8> = None;
    for w in cells.windows(2).rev() {
        // Walking from the robot (end of `cells`) towards the goal.
        let d = octant(w[1], w[0]);
        turning += match previous {
            None => first_turn(theta, d),
            Some(p) => turn(p, d),
        };
        previous = Some(d);
    }
    length_m / spec.max_linear_mps + turning / spec.max_angular_radps
}

/// Memoised turning along the descents of one distance field (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct TravelTimes {
    /// Per cell of the field's grid: the epoch its entries were computed in.
    stamp: Vec<u32>,
    epoch: u32,
    /// Per cell: turning from the robot to the cell along its descent, radians.
    turning: Vec<f64>,
    /// Per cell: octant of the last move of that way ([`NO_MOVE`] at the source).
    last_move: Vec<u8>,
    /// Cells of the descent not memoised yet, with the octant of the move into each from the
    /// robot's side.
    stack: Vec<(Cell, u8)>,
    theta: f64,
}

impl TravelTimes {
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets what was memoised: `field` was (re)computed for a robot at heading `theta`.
    pub fn reset(&mut self, field: &DistanceField, theta: f64) {
        let n = field.geometry().len();
        if self.stamp.len() != n {
            self.stamp = vec![0; n];
            self.turning = vec![0.0; n];
            self.last_move = vec![NO_MOVE; n];
            self.epoch = 0;
        }
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        self.theta = theta;
    }

    /// b(p, r) of the descent from `goal` in `field` (the one given to the last
    /// [`TravelTimes::reset`]), `length_m` long: the same as [`grid_travel_time_s`] on
    /// `field.path_to_source(goal)`. `None` when `goal` is unreachable.
    pub fn time_s(
        &mut self,
        field: &DistanceField,
        goal: Cell,
        length_m: f64,
        spec: &usar_sim::RobotSpec,
    ) -> Option<f64> {
        let g = *field.geometry();
        self.stack.clear();
        // Down to a memoised cell or the source.
        let (stamp, epoch, stack) = (&self.stamp, self.epoch, &mut self.stack);
        let c = field.descend_while(
            goal,
            |c| stamp[g.index(c)] != epoch,
            // The move from the next cell into `c` is move k reversed.
            |c, k| stack.push((c, (DIRECTION_OCTANT[k] + 4) % 8)),
        )?;
        let i = g.index(c);
        if self.stamp[i] != self.epoch {
            // The source.
            self.stamp[i] = self.epoch;
            self.turning[i] = 0.0;
            self.last_move[i] = NO_MOVE;
        }
        // Back up to the goal, adding the turns from the robot's side.
        let mut below = g.index(c);
        while let Some((x, d)) = self.stack.pop() {
            let t = match self.last_move[below] {
                NO_MOVE => first_turn(self.theta, d),
                p => self.turning[below] + turn(p, d),
            };
            let i = g.index(x);
            self.stamp[i] = self.epoch;
            self.turning[i] = t;
            self.last_move[i] = d;
            below = i;
        }
        let turning = self.turning[g.index(goal)];
        Some(length_m / spec.max_linear_mps + turning / spec.max_angular_radps)
    }
}

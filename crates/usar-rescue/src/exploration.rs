//! Direction-based exploration (paper 000 §V, eq. 7–10, Fig. 5–6, Table II).
//!
//! The map around the robot is split into four regions North, East, South, West by the
//! diagonals through the robot's cell; each region owns the diagonal boundary cells
//! counter-clockwise from it (North owns the north-west diagonal, West the south-west, South the
//! south-east, East the north-east). The utility of region j is (eq. 7)
//!
//! ```text
//! u_j = Σ_x ω_xj · λ_xj · δ_xj      over the cells of interest x of region j
//! ```
//!
//! with the terrain coefficient ω (eq. 8), the neighbouring-cells coefficient λ (eq. 9) and the
//! travel coefficient δ (eq. 10) of [`ExplorationWeights`]. d_x is the robot's *travel*
//! distance to x in cells: the shortest path through cells its map knows it can cross (to the
//! cell from which it faces x, plus one, when x is not classified yet); a cell of interest
//! the robot can neither reach nor face has no travel distance and δ = 1 ("elsewhere"). The
//! region with the largest utility among those holding a reachable cell of interest is the
//! exploration direction D_E. The travel distances are kept per source cell and updated as the
//! map grows ([`crate::travel`]): a step costs look-ups, not a search.
//!
//! **From D_E to a heading.** The paper hands D_E to the navigation subtask and lets it learn to
//! move that way through the rubble. Here the navigation subtask is given, besides D_E, the
//! *first step* of the shortest path (through cells the robot knows it can cross) to the cell
//! of interest of region D_E nearest to it by path (ties: the largest ω·λ·δ), so that NG
//! explores locally in direction D_E. Only cells of interest the robot can reach or face from
//! its known free cells count as targets; a region without such a target is skipped (its unknown cells lie behind
//! obstacles). This keeps the direction-based choice of the paper and removes the local minima
//! of following a compass direction through rubble (the paper's 1 786–2 026 steps per scene).
//!
//! **Local exploration first** (§IV-A-4: NG "performs local exploration ... utilizing the
//! information of the eight adjacent cells C₁…C₈"; it is rewarded for "moving to adjacent
//! unvisited areas in a local environment"). While one of the eight cells around the robot is
//! a cell of interest, the heading goes there before D_E's target: to a cell of interest among
//! the four neighbours (to enter it, or to face it when it is unclassified), else through a
//! known free neighbour to a diagonal cell of interest, each in the order ahead, left, right,
//! behind (the fewest turns first). The target of D_E is kept meanwhile. Leaving such a cell
//! behind costs a return trip later: on its own this ordering took the mean steps of the
//! evaluation (scenes A, B, C; policy of `usar maxq train --trials 1800 --seed 1`) from 1 359,
//! 1 247, 1 130 to 1 087, 960, 994, the travel-weighted case staying the fastest.
//!
//! **Then the cells within d₁.** Failing those eight, the nearest cell of interest the robot
//! reaches, or faces from a cell it reaches, in at most d₁ moves (the first distance threshold
//! of eq. 10: 3 cells in simulation, 1.5 in the experiments) comes before D_E's target, kept or
//! new. Within d₁ the travel coefficient δ is the same for every cell, so eq. 7 does not order
//! them; taking them nearest first, before leaving for D_E, spares the return trips to cells
//! left behind a few moves from the robot's path. This took the
//! evaluation from 1 036, 921, 946 to 889, 762, 838 steps (same command, together with the
//! apprentice fix of `usar_maxq`: the navigation subtask now learns from the operator's moves
//! as a subtask that ends after them). It also shrinks the differences between the weight
//! cases: the travel-weighted case stays faster than the equal- and neighbour-weighted cases
//! (paired t-tests p = 0.001, 0.003), but the terrain-weighted case is now the fastest (872,
//! 765, 800 steps against travel's 880, 762, 822) and the ANOVA across cases weakens to
//! p = 0.04.
//!
//! **Ties between shortest paths.** When several neighbours of the robot lie on shortest paths
//! to the target, the first step is the one ahead, else the one behind, else left, else right:
//! the fewest turns.

use crate::cell_map::{CellMap, MapCell};
use crate::marks::Marks;
use crate::travel::{TravelDistances, UNREACHED};
use serde::{Deserialize, Serialize};

/// A search direction / region (paper 000 Fig. 5), also a grid heading.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    East,
    North,
    West,
    South,
}

impl Direction {
    /// Counter-clockwise from east, as the cell robot's quarter headings.
    pub const ALL: [Direction; 4] = [
        Direction::East,
        Direction::North,
        Direction::West,
        Direction::South,
    ];

    /// Index 0..4, counter-clockwise from east (the cell robot's heading).
    pub fn index(self) -> usize {
        self as usize
    }

    pub fn from_index(i: usize) -> Direction {
        Self::ALL[i % 4]
    }

    /// (dcol, drow) of one step.
    pub fn step(self) -> (i32, i32) {
        match self {
            Direction::East => (1, 0),
            Direction::North => (0, 1),
            Direction::West => (-1, 0),
            Direction::South => (0, -1),
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Direction::East => "east",
            Direction::North => "north",
            Direction::West => "west",
            Direction::South => "south",
        }
    }
}

/// The region of a cell at (dx, dy) cells from the robot (Fig. 5); `None` for the robot's cell.
/// Each region owns the diagonal counter-clockwise from it.
#[inline]
pub fn region_of(dx: i32, dy: i32) -> Option<Direction> {
    if dx == 0 && dy == 0 {
        None
    } else if dy > 0 && -dy <= dx && dx < dy {
        Some(Direction::North)
    } else if dx > 0 && -dx < dy && dy <= dx {
        Some(Direction::East)
    } else if dy < 0 && dy < dx && dx <= -dy {
        Some(Direction::South)
    } else {
        Some(Direction::West)
    }
}

/// The coefficients of eq. 8–10 with their weights (Table II).
///
/// Table II's cases: name and (w_l, w_p, w_q).
const TABLE_II: [(&str, [f64; 3]); 4] = [
    ("terrain", [HIGH_WEIGHT, 1.0, 1.0]),
    ("neighbour", [1.0, HIGH_WEIGHT, 1.0]),
    ("travel", [1.0, 1.0, HIGH_WEIGHT]),
    ("equal", [1.0, 1.0, 1.0]),
];

/// `terrain` = w_l·(l₁, l₂, l₃) for an open unvisited cell, an unvisited climbable obstacle and
/// an unknown obstacle (1 elsewhere); `neighbour` = w_p·(p₁, p₂, p₃, p₄) for a neighbouring
/// cell that is unknown, open unvisited, unvisited climbable, an unknown obstacle (0 elsewhere;
/// λ = 1 when the sum is 0); `travel` = w_q·(q₁…q₄) for d_x ≤ d₁, ≤ d₂, ≤ d₃, ≤ d₄ (1 beyond);
/// `distance_cells` = (d₁…d₄), cells.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExplorationWeights {
    pub name: String,
    pub terrain: [f64; 3],
    pub neighbour: [f64; 4],
    pub travel: [f64; 4],
    pub distance_cells: [f64; 4],
}

/// Base values of Table II with all weights 1: l = (10, 5, 2), p = (3, 2, 1.5, 1),
/// q = (10, 5, 2, 1.5); d = (3, 6, 9, 12) cells in simulation (§VI-B).
const L: [f64; 3] = [10.0, 5.0, 2.0];
const P: [f64; 4] = [3.0, 2.0, 1.5, 1.0];
const Q: [f64; 4] = [10.0, 5.0, 2.0, 1.5];
/// Distance thresholds of the simulations (§VI-B).
pub const SIMULATION_DISTANCES: [f64; 4] = [3.0, 6.0, 9.0, 12.0];
/// Distance thresholds of the physical experiments (§VII-A).
pub const EXPERIMENT_DISTANCES: [f64; 4] = [1.5, 3.0, 6.0, 12.0];
/// The higher weighting of §VI-B ("w_i = 20").
pub const HIGH_WEIGHT: f64 = 20.0;

impl ExplorationWeights {
    /// Coefficients with weights (w_l, w_p, w_q).
    pub fn weighted(name: &str, w_l: f64, w_p: f64, w_q: f64) -> Self {
        Self {
            name: name.into(),
            terrain: L.map(|l| w_l * l),
            neighbour: P.map(|p| w_p * p),
            travel: Q.map(|q| w_q * q),
            distance_cells: SIMULATION_DISTANCES,
        }
    }

    /// Table II, simulations 1–4: terrain-, neighbour-, travel-weighted and equal weights.
    pub fn table_ii() -> [ExplorationWeights; 4] {
        TABLE_II.map(|(name, [w_l, w_p, w_q])| Self::weighted(name, w_l, w_p, w_q))
    }

    /// A Table II case by name (`terrain`, `neighbour`, `travel`, `equal`).
    pub fn named(name: &str) -> Option<ExplorationWeights> {
        Self::table_ii().into_iter().find(|w| w.name == name)
    }

    /// The weights (w_l, w_p, w_q) of a Table II case by name.
    pub fn named_factors(name: &str) -> Option<[f64; 3]> {
        TABLE_II.iter().find(|(n, _)| *n == name).map(|&(_, w)| w)
    }

    /// ω (eq. 8).
    #[inline]
    pub fn terrain_coefficient(&self, cell: MapCell) -> f64 {
        match cell {
            MapCell::OpenUnvisited => self.terrain[0],
            MapCell::ClimbableUnvisited => self.terrain[1],
            MapCell::UnknownObstacle => self.terrain[2],
            _ => 1.0,
        }
    }

    /// v_x^k of eq. 9.
    #[inline]
    pub fn neighbour_value(&self, cell: MapCell) -> f64 {
        match cell {
            MapCell::Unknown => self.neighbour[0],
            MapCell::OpenUnvisited => self.neighbour[1],
            MapCell::ClimbableUnvisited => self.neighbour[2],
            MapCell::UnknownObstacle => self.neighbour[3],
            _ => 0.0,
        }
    }

    /// δ (eq. 10) at squared distance `d2` (cells²).
    #[inline]
    pub fn travel_coefficient(&self, d2: f64) -> f64 {
        self.travel_coefficient_at(d2.max(0.0).sqrt())
    }

    /// δ (eq. 10) at distance `d` (cells).
    #[inline]
    pub fn travel_coefficient_at(&self, d: f64) -> f64 {
        let t = &self.distance_cells;
        if d <= t[0] {
            self.travel[0]
        } else if d <= t[1] {
            self.travel[1]
        } else if d <= t[2] {
            self.travel[2]
        } else if d <= t[3] {
            self.travel[3]
        } else {
            1.0
        }
    }
}

/// What the exploration tells the navigation subtask.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Guidance {
    /// D_E: the region with the largest utility among those with a reachable target.
    pub direction: Option<Direction>,
    /// The cell of interest chosen in region D_E (or the victim to approach).
    pub target: Option<(i32, i32)>,
    /// The first step toward the target: a move to a neighbour, or the turn to face the target
    /// when it is adjacent. `None` when there is nothing left to explore or reach.
    pub heading: Option<Direction>,
    /// Utilities u_j of eq. 7, by [`Direction::index`].
    pub utility: [f64; 4],
}

/// The exploration state over a robot's map: ω·λ per cell kept up to date as the map changes,
/// and the travel distances of eq. 10 ([`TravelDistances`]), so that choosing a direction
/// allocates nothing.
#[derive(Clone, Debug)]
pub struct Explorer {
    pub weights: ExplorationWeights,
    cols: i32,
    /// ω_x·λ_x of every cell of interest, 0 for the other cells.
    omega_lambda: Vec<f64>,
    /// Path distances through known passable cells from every cell the robot stood on.
    travel: TravelDistances,
    /// The four neighbours of each cell by [`Direction::index`], [`NONE`] outside the map.
    neighbours: Vec<[u32; 4]>,
    /// The eight neighbours of each cell in [`usar_world::NEIGHBORS8`] order, [`NONE`]
    /// outside the map (for λ, eq. 9).
    neighbours8: Vec<[u32; 8]>,
    /// δ (eq. 10) by travel distance in cells (the last entry for every longer distance).
    delta: Vec<f64>,
    /// The last [`Explorer::guide`] followed its kept target and no
    /// [`Explorer::several_victims_pending`] came since: a possible victim lying in the robot's own cell
    /// is then not approached ([`Explorer::toward_victim`]), as when the distances came from
    /// a search that stopped at the kept target (kept so that results stay identical).
    partial: bool,
    /// The robot's heading at the last [`Explorer::guide`] / [`Explorer::toward_victim`] (ties
    /// between first steps prefer no turn).
    heading: Direction,
    /// The search of [`Explorer::nearby_step`]: (cell, travel distance, first step) in
    /// breadth-first order, and the cells it reached.
    nearby: Vec<(u32, u8, u8)>,
    reached: Marks,
}

/// No cell.
const NONE: u32 = u32::MAX;

impl Explorer {
    pub fn new(weights: ExplorationWeights, map: &CellMap) -> Self {
        let n = map.cells.len();
        let mut neighbours = vec![[NONE; 4]; n];
        for (i, nb) in neighbours.iter_mut().enumerate() {
            let (col, row) = map.col_row(i);
            for dir in Direction::ALL {
                let (dc, dr) = dir.step();
                if let Some(k) = map.index(col + dc, row + dr) {
                    nb[dir.index()] = k as u32;
                }
            }
        }
        let neighbours8 = (0..n)
            .map(|i| {
                let (col, row) = map.col_row(i);
                usar_world::NEIGHBORS8
                    .map(|(dc, dr)| map.index(col + dc, row + dr).map_or(NONE, |k| k as u32))
            })
            .collect();
        let delta = (0..=n)
            .map(|d| weights.travel_coefficient_at(d as f64))
            .collect();
        let mut e = Self {
            weights,
            cols: map.cols,
            omega_lambda: vec![0.0; n],
            travel: TravelDistances::new(&neighbours),
            neighbours,
            neighbours8,
            delta,
            partial: false,
            heading: Direction::East,
            nearby: Vec::new(),
            reached: Marks::new(n),
        };
        for i in 0..n {
            e.refresh(map, i);
            e.travel.set_passable(i, map.cells[i].is_known_passable());
        }
        e
    }

    /// ω·λ of cell `i` from the map (eq. 8, 9).
    fn refresh(&mut self, map: &CellMap, i: usize) {
        let cell = map.cells[i];
        if !cell.is_of_interest() {
            self.omega_lambda[i] = 0.0;
            return;
        }
        let mut sum = 0.0;
        for &k in &self.neighbours8[i] {
            if k != NONE {
                sum += self.weights.neighbour_value(map.cells[k as usize]);
            }
        }
        let lambda = if sum != 0.0 { sum } else { 1.0 };
        self.omega_lambda[i] = self.weights.terrain_coefficient(cell) * lambda;
    }

    /// Call after cell (col, row) of `map` changed: updates it and its eight neighbours.
    pub fn cell_changed(&mut self, map: &CellMap, col: i32, row: i32) {
        if let Some(i) = map.index(col, row) {
            self.travel
                .set_passable(i, map.cells[i].is_known_passable());
            self.refresh(map, i);
            for k in self.neighbours8[i] {
                if k != NONE {
                    self.refresh(map, k as usize);
                }
            }
        }
    }

    /// ω·λ of a cell (0 when it is not of interest).
    pub fn omega_lambda(&self, col: i32, row: i32) -> f64 {
        let i = (row * self.cols + col) as usize;
        self.omega_lambda[i]
    }

    /// Several possible victims are pending: [`Explorer::toward_victim`] then approaches one
    /// lying in the robot's own cell too (the distances it needs are kept per cell; see
    /// `partial`).
    pub fn several_victims_pending(&mut self) {
        self.partial = false;
    }

    /// Path distance from the robot's cell to reached cell `s` and the first step toward it
    /// (`None` when the robot is in `s`); `None` when `s` cannot be reached.
    ///
    /// Read from the distances *from `s`* (the graph is undirected): the first step is a
    /// neighbour of the robot one step nearer to `s`: ahead, else behind, else left, else right
    /// of the robot's heading (the fewest turns; [`crate::travel`]). A target's distances stay
    /// valid while the robot follows it, so a step costs a few look-ups instead of a search.
    fn toward(&mut self, robot: usize, s: usize) -> Option<(u32, Option<Direction>)> {
        if s == robot {
            return Some((0, None));
        }
        if !self.travel.is_passable(robot) {
            // (Never on a map built by the domain: the robot stands on a visited cell.)
            self.travel.update(robot);
            let d = self.travel.row(robot)[s];
            let step = self.travel.first_step(robot, s);
            return (d < UNREACHED).then(|| {
                (
                    u32::from(d),
                    step.map(|k| Direction::from_index(usize::from(k))),
                )
            });
        }
        self.travel.update(s);
        let row = self.travel.row(s);
        let d = row[robot];
        if d >= UNREACHED {
            return None;
        }
        let on_path = |k: usize| {
            let nb = self.neighbours[robot][k];
            nb != NONE && row[nb as usize] == d - 1
        };
        let step = self
            .fewest_turns()
            .into_iter()
            .find(|&k| on_path(k))
            .map(Direction::from_index);
        Some((u32::from(d), step))
    }

    /// Direction indices of the robot's first moves in the order of the fewest turns: ahead,
    /// behind (reversing), left, right.
    fn fewest_turns(&self) -> [usize; 4] {
        let h = self.heading.index();
        [h, (h + 2) % 4, (h + 1) % 4, (h + 3) % 4]
    }

    /// The reached neighbour from which the robot can face unclassified cell `i`: the nearest
    /// one by path (ties: the first facing direction in E N W S order), with its distance, the
    /// direction it faces and the first step toward it.
    fn stand_for(
        &mut self,
        i: usize,
        robot: usize,
    ) -> Option<(u32, usize, Direction, Option<Direction>)> {
        let mut best: Option<(u32, usize, Direction, Option<Direction>)> = None;
        for dir in Direction::ALL {
            // The stand cell lies opposite to the direction it faces.
            let s = self.neighbours[i][(dir.index() + 2) % 4];
            if s == NONE || (s as usize != robot && !self.travel.is_passable(s as usize)) {
                continue;
            }
            let s = s as usize;
            if let Some((d, step)) = self.toward(robot, s)
                && best.is_none_or(|(bd, ..)| d < bd)
            {
                best = Some((d, s, dir, step));
            }
        }
        best
    }

    /// The heading toward cell of interest `i` (through its stand cell when unclassified:
    /// the turn to face it once there), or `None` when the robot can neither reach nor face
    /// it.
    fn heading_to(&mut self, map: &CellMap, i: usize, robot: usize) -> Option<Option<Direction>> {
        if map.cells[i].is_unclassified() {
            let (_, _, face, step) = self.stand_for(i, robot)?;
            Some(step.or(Some(face)))
        } else {
            self.toward(robot, i).map(|(_, step)| step)
        }
    }

    /// The heading toward a cell of interest among the eight around the robot (C₁…C₈), if
    /// any: a neighbour of interest (entered, or faced when unclassified), else a known free
    /// neighbour next to a diagonal cell of interest (from which the robot enters or faces it);
    /// each in the order ahead, left, right, behind.
    fn local_step(&self, map: &CellMap, robot: usize) -> Option<Direction> {
        const ORDER: [usize; 4] = [0, 1, 3, 2];
        let h = self.heading.index();
        let around = |k: usize| {
            let dir = Direction::from_index(h + k);
            (dir, self.neighbours[robot][dir.index()])
        };
        let of_interest = |i: u32| i != NONE && map.cells[i as usize].is_of_interest();
        if let Some((dir, _)) = ORDER.map(around).into_iter().find(|&(_, n)| of_interest(n)) {
            return Some(dir);
        }
        ORDER.map(around).into_iter().find_map(|(dir, n)| {
            let free = n != NONE && map.cells[n as usize].is_known_passable();
            // The two diagonal cells beside neighbour n: left and right of the direction.
            let side = |s: usize| self.neighbours[n as usize][(dir.index() + s) % 4];
            (free && (of_interest(side(1)) || of_interest(side(3)))).then_some(dir)
        })
    }

    /// Local exploration within d₁ (see the [module documentation](self)): the nearest cell
    /// of interest the robot reaches, or faces from a cell it reaches, in at most d₁ moves
    /// through known passable cells, with the heading toward it (the first move, or the turn
    /// to face an unclassified neighbour). A breadth-first search from the robot whose first
    /// moves are tried ahead, behind, left, right (the fewest turns, as in
    /// [`Explorer::toward`]); at equal distance the cell found first wins.
    fn nearby_step(&mut self, map: &CellMap, robot: usize) -> Option<(usize, Direction)> {
        let reach = self.local_reach();
        self.reached.clear();
        let order = self.fewest_turns();
        self.nearby.clear();
        self.nearby.push((robot as u32, 0, 0));
        self.reached.mark(robot);
        // (distance, cell, heading) of the best cell so far.
        let mut best: Option<(u8, usize, u8)> = None;
        let mut head = 0;
        while let Some(&(i, d, step)) = self.nearby.get(head) {
            head += 1;
            if best.is_some_and(|(bd, ..)| d >= bd) {
                break;
            }
            let i = i as usize;
            if i != robot && map.cells[i].is_of_interest() {
                best = Some((d, i, step));
                break;
            }
            // From the robot's cell each neighbour is its own first move (or turn).
            let first = |k: usize| if i == robot { k as u8 } else { step };
            for k in order {
                let nb = self.neighbours[i][k];
                if nb == NONE || self.reached.is_marked(nb as usize) {
                    continue;
                }
                let nb = nb as usize;
                let cell = map.cells[nb];
                if cell.is_unclassified() {
                    // Faced from i.
                    if best.is_none_or(|(bd, ..)| d + 1 < bd) {
                        best = Some((d + 1, nb, first(k)));
                    }
                } else if cell.is_known_passable() && u32::from(d) < reach {
                    self.reached.mark(nb);
                    self.nearby.push((nb as u32, d + 1, first(k)));
                }
            }
        }
        best.map(|(_, i, step)| (i, Direction::from_index(usize::from(step))))
    }

    /// d₁ of eq. 10 in whole cells: the reach of local exploration (δ is the same for every
    /// cell within it).
    fn local_reach(&self) -> u32 {
        self.weights.distance_cells[0].clamp(0.0, 200.0) as u32
    }

    /// D_E and the heading toward its best reachable cell of interest, for the robot at
    /// (rc, rr) facing `heading`. Targets are unvisited passable cells it can reach and
    /// unclassified cells it can face from a reached cell. The direction is updated "as
    /// necessary" (§V): a target `kept` from the previous call is followed until it is explored
    /// or cannot be reached, so that the regions, which move with the robot, do not make it turn
    /// back and forth. A cell of interest among the eight around the robot comes first, then
    /// the nearest within d₁ moves (local exploration, see the [module documentation](self)).
    pub fn guide(
        &mut self,
        map: &CellMap,
        rc: i32,
        rr: i32,
        heading: Direction,
        kept: Option<Guidance>,
    ) -> Guidance {
        let Some(robot) = map.index(rc, rr) else {
            return Guidance::default();
        };
        self.heading = heading;
        let kept_target = kept.and_then(|g| {
            let (tc, tr) = g.target?;
            map.index(tc, tr)
                .filter(|&t| t != robot && map.cells[t].is_of_interest())
        });
        self.partial = false;
        if let Some(step) = self.local_step(map, robot) {
            let mut g = kept.unwrap_or_default();
            if kept_target.is_none() {
                g.target = None;
            }
            return Guidance {
                heading: Some(step),
                ..g
            };
        }
        if let Some((t, step)) = self.nearby_step(map, robot) {
            return Guidance {
                target: Some(map.col_row(t)),
                heading: Some(step),
                ..kept.unwrap_or_default()
            };
        }
        if let (Some(g), Some(t)) = (kept, kept_target)
            && let Some(heading) = self.heading_to(map, t, robot)
        {
            self.partial = true;
            return Guidance { heading, ..g };
        }
        self.travel.update(robot);
        // One pass over the cells of interest: eq. 7 per region and the best target per
        // region: the nearest by path, then the largest ω·λ·δ, then the lowest index.
        let mut utility = [0.0; 4];
        let mut best: [Option<(f64, u32, usize)>; 4] = [None; 4];
        let cols = self.cols as usize;
        let last = self.delta.len() - 1;
        let dist = self.travel.row(robot);
        for (row, cells) in self.omega_lambda.chunks_exact(cols).enumerate() {
            let dy = row as i32 - rr;
            for (col, &ol) in cells.iter().enumerate() {
                if ol == 0.0 {
                    continue;
                }
                let i = row * cols + col;
                let dx = col as i32 - rc;
                let Some(region) = region_of(dx, dy) else {
                    continue;
                };
                // Through the nearest stand cell when the cell is unclassified.
                let d = if map.cells[i].is_unclassified() {
                    self.neighbours[i]
                        .iter()
                        .map(|&s| {
                            if s == NONE {
                                UNREACHED
                            } else {
                                dist[s as usize]
                            }
                        })
                        .min()
                        .unwrap_or(UNREACHED)
                        .min(UNREACHED)
                        .saturating_add(1)
                } else {
                    dist[i]
                };
                let d = (d < UNREACHED).then_some(u32::from(d));
                let delta = d.map_or(1.0, |d| self.delta[(d as usize).min(last)]);
                let value = ol * delta;
                utility[region.index()] += value;
                let Some(d) = d else { continue };
                let slot = &mut best[region.index()];
                if slot.is_none_or(|(v, bd, _)| d < bd || (d == bd && value > v)) {
                    *slot = Some((value, d, i));
                }
            }
        }
        let chosen = Direction::ALL
            .into_iter()
            .filter(|dir| best[dir.index()].is_some())
            .fold(None::<Direction>, |acc, dir| match acc {
                Some(a) if utility[a.index()] >= utility[dir.index()] => Some(a),
                _ => Some(dir),
            });
        let Some(direction) = chosen else {
            return Guidance {
                utility,
                ..Guidance::default()
            };
        };
        let (_, _, target) = best[direction.index()].expect("chosen region has a target");
        let heading = self.heading_to(map, target, robot).flatten();
        Guidance {
            direction: Some(direction),
            target: Some(map.col_row(target)),
            heading,
            utility,
        }
    }

    /// The heading toward the nearest cell from which the robot faces victim cell (vc, vr), and
    /// that path's length; `None` when no such cell is reachable.
    pub fn toward_victim(
        &mut self,
        map: &CellMap,
        rc: i32,
        rr: i32,
        heading: Direction,
        vc: i32,
        vr: i32,
    ) -> Option<(Direction, u32)> {
        let robot = map.index(rc, rr)?;
        self.heading = heading;
        // (A victim in the robot's own cell: the robot drove onto a warm object it took for
        // a possible victim; see `partial`.)
        if self.partial && map.index(vc, vr) == Some(robot) {
            return None;
        }
        let (d, _, face, step) = self.stand_for(map.index(vc, vr)?, robot)?;
        Some((step.unwrap_or(face), d))
    }
}

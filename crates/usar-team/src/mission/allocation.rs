//! Allocation: which robot goes where, behind the [`Allocate`] trait — the nearest-frontier
//! baseline here, paper 002's auction in `auction.rs` — with what both share: going idle
//! (retracing once) and planning the path driven on the map.

use super::discs::RobotDiscs;
use super::driving::retrace;
use super::*;

/// How a team decides which robot goes where, for the robots in `who` that need a target
/// (all of them at a periodic allocation; otherwise those that arrived, got stuck or
/// recovered).
pub trait Allocate {
    fn allocate(&self, team: &mut TeamController, who: &[usize]);
}

/// Each robot to its nearest frontier candidate, one robot per candidate (the baseline
/// explorer, [`Strategy::Nearest`]).
pub struct NearestFrontier;

/// Paper 002's auction (§3.3), every other [`Strategy`].
pub struct Auction;

impl Allocate for NearestFrontier {
    fn allocate(&self, team: &mut TeamController, who: &[usize]) {
        team.assign_nearest(who);
    }
}

impl Allocate for Auction {
    fn allocate(&self, team: &mut TeamController, who: &[usize]) {
        team.auction(who);
    }
}

impl TeamController {
    /// Reassigns targets to the robots in `who` by the configured strategy's allocation.
    pub(super) fn assign(&mut self, who: &[usize]) {
        let allocation: &dyn Allocate = if self.config.exploration.strategy == Strategy::Nearest {
            &NearestFrontier
        } else {
            &Auction
        };
        allocation.allocate(self, who);
    }

    /// The nearest-frontier assignment: path costs from each robot to every candidate, one
    /// robot per candidate, nearest first.
    fn assign_nearest(&mut self, who: &[usize]) {
        let cands = self.candidate_locations();
        let g = *self.base.merged.geometry();
        let now = self.now;
        // Targets of robots that keep theirs are taken (one robot per candidate).
        let keep: Vec<Cell> = (0..self.agents.len())
            .filter(|i| !who.contains(i))
            .filter_map(|i| self.agents[i].target)
            .collect();
        let clearance = self.config.robot.circumscribed_radius_m() * 2.0;
        // The alive robots' discs, closed once for the round on both grids.
        let alive: Vec<Point2> = self
            .agents
            .iter()
            .filter(|a| a.alive)
            .map(|a| a.pose.position())
            .collect();
        let discs = [0, 1].map(|k| {
            let cover = std::mem::take(&mut self.disc_cover[k]);
            RobotDiscs::close(&mut self.base.nav_grids[k], &alive, clearance, cover)
        });
        let mut costs = Vec::with_capacity(who.len());
        for &i in who {
            let pose = self.agents[i].pose;
            let is_alive = self.agents[i].alive;
            self.agents[i].blacklist.retain(|&(_, until)| until > now);
            let mut row = Vec::new();
            // Plan with the full radius from the nearest navigable cell; if nothing is reachable,
            // squeeze with the tight radius; last, start from every navigable cell nearby.
            for (k, all_sources) in [(0, false), (1, false), (1, true)] {
                let grid = &mut self.base.nav_grids[k];
                // Every other robot's disc stays closed; its own is open.
                let own = if is_alive {
                    discs[k].open_own(grid, pose.position())
                } else {
                    Vec::new()
                };
                let sources = source_cells(&self.base.merged, grid, pose.position(), all_sources);
                let was_passable: Vec<bool> =
                    sources.iter().map(|&c| grid.is_passable(c)).collect();
                for &c in &sources {
                    grid.set_passable(c, true);
                }
                let agent = &mut self.agents[i];
                row = path_costs(&mut agent.field, grid, &sources, &cands);
                for (&c, &passable) in sources.iter().zip(&was_passable) {
                    grid.set_passable(c, passable);
                }
                RobotDiscs::close_own(grid, &own);
                for (k, c) in cands.iter().enumerate() {
                    if keep.contains(&c.cell)
                        || agent
                            .blacklist
                            .iter()
                            .any(|&(b, _)| b.chebyshev(c.cell) <= 3)
                    {
                        row[k] = None;
                    } else if let (Some(cost), Some(t)) = (row[k], agent.target)
                        && t.chebyshev(c.cell) <= self.config.tuning.commitment_cells
                    {
                        row[k] = Some(cost * self.config.tuning.commitment_factor);
                    }
                }
                if row.iter().any(Option::is_some) {
                    break;
                }
            }
            costs.push(row);
        }
        for (k, d) in discs.into_iter().enumerate() {
            self.disc_cover[k] = d.open_all(&mut self.base.nav_grids[k]);
        }
        let chosen = assign_nearest(&costs);
        for (k, &i) in who.iter().enumerate() {
            let agent = &mut self.agents[i];
            match chosen[k] {
                Some(c) => {
                    let target = cands[c].cell;
                    if agent.target == Some(target) && !agent.follower.is_empty() {
                        continue;
                    }
                    let path = agent
                        .field
                        .path_to_source(target)
                        .map(|p| p.cells)
                        .unwrap_or_default();
                    let waypoints: Vec<Point2> =
                        path.iter().rev().map(|&c| g.cell_center(c)).collect();
                    agent.head_for(target, waypoints);
                }
                None => self.idle(i),
            }
            let agent = &mut self.agents[i];
            agent.progress_mark = (agent.pose, now);
        }
    }

    /// Robot `i` got nothing: it stops, retracing its way once if it may.
    pub(super) fn idle(&mut self, i: usize) {
        let agent = &mut self.agents[i];
        agent.target = None;
        agent.follower = PathFollower::default();
        if std::mem::take(&mut agent.may_retrace) {
            agent.follower = PathFollower::new(retrace(
                &self.config.tuning,
                &agent.trajectory,
                agent.pose.position(),
            ));
        }
        agent.escaping = !agent.follower.is_empty();
    }

    /// A path on the map from robot `i` to `goal`: with the full radius if possible, else with
    /// the tight one. Waypoints from the robot to the goal.
    pub(super) fn plan_path(&mut self, i: usize, goal: Cell) -> Option<Vec<Point2>> {
        let g = *self.base.merged.geometry();
        let here = self.agents[i].pose.position();
        let mut found = None;
        for radius in 0..2 {
            // The base station's grid (start and goal opened for the query, then closed again).
            let grid = &mut self.base.nav_grids[radius];
            let start = source_cells(&self.base.merged, grid, here, false)[0];
            let was = (grid.is_passable(start), grid.is_passable(goal));
            grid.set_passable(start, true);
            grid.set_passable(goal, true);
            let path =
                self.planner
                    .plan(grid, start, goal, usar_map::planning::Connectivity::Eight);
            grid.set_passable(start, was.0);
            grid.set_passable(goal, was.1);
            if let Some(p) = path {
                found = Some(p.cells.iter().map(|&c| g.cell_center(c)).collect());
                break;
            }
        }
        found
    }

    /// The room of a map cell, or of the nearest cell within two cells that has one.
    pub(super) fn room_near(&self, cell: Cell) -> Option<usize> {
        self.semantic.room_near(self.base.merged.geometry(), cell)
    }
}

//! Allocation: which robot goes where. Nearest-frontier assignment, and paper 002's auction
//! (candidates, perceived labels, bids, SR / MRv1 / MRv2 allocation, paths) with the room
//! grouping, commitment and blacklists around it.

use super::driving::retrace;
use super::*;

impl TeamController {
    /// Reassigns targets to the robots in `who` (all robots at a periodic auction, or those
    /// that reached their target or got stuck).
    pub(super) fn assign(&mut self, who: &[usize]) {
        if self.config.exploration.strategy != Strategy::Nearest {
            self.auction(who);
            return;
        }
        let clusters = self.base.clusters(self.config.min_cluster_cells);
        let g = *self.base.merged.geometry();
        let merged = &self.base.merged;
        let navigable = |nav: &usar_map::NavigableMap, c: Cell| {
            g.checked_index(c)
                .is_some_and(|i| nav.is_navigable(merged, i))
        };
        let cands: Vec<Candidate> =
            candidates(&clusters, |c| navigable(&self.base.navigable_tight, c), &g);
        let now = self.now;
        // Targets of robots that keep theirs are taken (one robot per candidate).
        let keep: Vec<Cell> = (0..self.agents.len())
            .filter(|i| !who.contains(i))
            .filter_map(|i| self.agents[i].target)
            .collect();
        let clearance = self.config.robot.circumscribed_radius_m() * 2.0;
        let mut costs = Vec::with_capacity(who.len());
        for &i in who {
            let pose = self.agents[i].pose;
            let others: Vec<Point2> = self
                .agents
                .iter()
                .enumerate()
                .filter(|&(j, a)| j != i && a.alive)
                .map(|(_, a)| a.pose.position())
                .collect();
            self.agents[i].blacklist.retain(|&(_, until)| until > now);
            let mut row = Vec::new();
            // Plan with the full radius from the nearest navigable cell; if nothing is reachable,
            // squeeze with the tight radius; last, start from every navigable cell nearby.
            for (grid, all_sources) in [(0, false), (1, false), (1, true)] {
                let grid = &mut self.base.nav_grids[grid];
                let mut closed = Vec::new();
                for &p in &others {
                    block_disc(grid, p, clearance, &mut closed);
                }
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
                for c in closed {
                    grid.set_passable(c, true);
                }
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
                    agent.follower = PathFollower::new(waypoints);
                    agent.target = Some(target);
                    agent.recoveries = 0;
                    agent.escaping = false;
                    agent.may_retrace = true;
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

    /// Paper 002's auction (§3.3) for the robots in `who`: candidates from the frontier
    /// clusters, each bidding robot's path lengths and times on the coarse bid grid, one
    /// candidate per room ([`CandidateGrouping::Room`]), bids by the strategy, allocation by the
    /// coordination method (robots not bidding keep their targets and count towards i(p)), then
    /// a path on the map to each new target.
    pub(super) fn auction(&mut self, who: &[usize]) {
        self.refresh_semantics();
        let now = self.now;
        let clusters = self.base.clusters(self.config.min_cluster_cells);
        let g = *self.base.merged.geometry();
        let mut cands: Vec<Candidate> = {
            let merged = &self.base.merged;
            let nav = &self.base.navigable_tight;
            candidates(
                &clusters,
                |c| {
                    g.checked_index(c)
                        .is_some_and(|i| nav.is_navigable(merged, i))
                },
                &g,
            )
        };
        // Robots that bid: working and linked. Unlinked robots keep what they do.
        let bidders: Vec<usize> = who
            .iter()
            .copied()
            .filter(|&i| self.agents[i].linked && self.agents[i].alive)
            .collect();
        if bidders.is_empty() {
            return;
        }
        self.visited.retain(|&(_, until)| until > now);
        let visited: Vec<bool> = cands
            .iter()
            .map(|c| {
                self.visited
                    .iter()
                    .any(|&(v, _)| v.chebyshev(c.cell) <= self.config.tuning.visited_cells)
            })
            .collect();
        // What is known of each candidate: room, perceived label, i(p).
        let mut rooms: Vec<Option<usize>> = cands.iter().map(|c| self.room_near(c.cell)).collect();
        let labels: Vec<Option<RoomLabel>> = rooms
            .iter()
            .map(|r| r.map(|k| self.semantic.perceived_label(k)))
            .collect();
        let mut infos: Vec<crate::criteria::CandidateInfo> = cands
            .iter()
            .zip(&rooms)
            .zip(&labels)
            .map(|((c, r), &label)| crate::criteria::CandidateInfo {
                position: g.cell_center(c.cell),
                frontier_cells: c.frontier_cells,
                label,
                doors: r.map_or(0, |k| self.semantic.rooms()[k].doors),
            })
            .collect();
        let sr = self.config.exploration.coordination == crate::coordination::Coordination::Sr;
        // i(p) depends on the room, its perceived label and how much of it is known: inferred
        // again only when the label or the known fraction changed since the room's last one.
        let mut ideal: Vec<usize> = rooms
            .iter()
            .zip(&labels)
            .map(|(&r, &label)| {
                let Some(k) = r.filter(|_| !sr) else {
                    return 1;
                };
                let perceived = self.semantic.perceived_fraction(k);
                match self.team_sizes[k] {
                    Some((l, f, n)) if l == label && f == perceived => n,
                    _ => {
                        let n = self
                            .sizer
                            .ideal(Some(&self.semantic.rooms()[k]), label, perceived);
                        self.team_sizes[k] = Some((label, perceived, n));
                        n
                    }
                }
            })
            .collect();
        // Path lengths and times from each bidder, on the coarse grid.
        let grid = &self.base.bid_grid;
        let cg = *grid.geometry();
        let needs_time = matches!(
            self.config.exploration.strategy,
            Strategy::DMcdm | Strategy::SMcdm
        );
        let spec = self.config.robot.clone();
        let mut travel = Vec::with_capacity(bidders.len());
        let mut positions = Vec::with_capacity(bidders.len());
        // The bid grid cells of the candidates: a bidder's search stops once those it prices
        // are settled.
        let goals: Vec<Cell> = cands
            .iter()
            .map(|c| cg.world_to_cell(g.cell_center(c.cell)))
            .collect();
        let mut live = vec![false; cands.len()];
        let mut targets = Vec::with_capacity(cands.len());
        for &i in &bidders {
            let pose = self.agents[i].pose;
            positions.push(pose.position());
            let agent = &mut self.agents[i];
            agent.blacklist.retain(|&(_, until)| until > now);
            // Candidates this bidder prices: not visited, not near its blacklisted targets.
            targets.clear();
            for (k, (c, &visited)) in cands.iter().zip(&visited).enumerate() {
                live[k] = !visited
                    && !agent
                        .blacklist
                        .iter()
                        .any(|&(b, _)| b.chebyshev(c.cell) <= 3);
                if live[k] {
                    targets.push(goals[k]);
                }
            }
            let source = nearest_passable(grid, cg.world_to_cell(pose.position()), 4);
            let field = &mut self.bid_field;
            field.compute_until_settled(
                grid,
                &source.into_iter().collect::<Vec<_>>(),
                usar_map::planning::Connectivity::Eight,
                &targets,
            );
            let travel_times = &mut self.travel_times;
            travel_times.reset(field, pose.theta);
            let row: Vec<Option<crate::bids::Travel>> = (0..cands.len())
                .map(|k| {
                    if !live[k] {
                        return None;
                    }
                    let goal = goals[k];
                    let cells = field.distance_cells(goal)?;
                    let length_m = cells * cg.resolution_m;
                    let time_s = if needs_time {
                        travel_times.time_s(field, goal, length_m, &spec)?
                    } else {
                        length_m / spec.max_linear_mps
                    };
                    Some(crate::bids::Travel { length_m, time_s })
                })
                .collect();
            travel.push(row);
        }
        // One candidate per room (`room_candidates`): from here on, each group's representative
        // stands for its room's whole frontier. A robot's target still belongs to the group of
        // the cluster candidate it was (`candidate_of`), wherever the group's representative is.
        let ungrouped = cands.clone();
        let mut group_of: Vec<usize> = (0..cands.len()).collect();
        if self.config.exploration.candidates == CandidateGrouping::Room {
            let members: Vec<ClusterCandidate> = (0..cands.len())
                .map(|c| ClusterCandidate {
                    position: infos[c].position,
                    frontier_cells: cands[c].frontier_cells,
                    room: rooms[c]
                        .filter(|&k| self.semantic.rooms()[k].label != RoomLabel::Corridor),
                    reachable_by: travel.iter().filter(|row| row[c].is_some()).count(),
                })
                .collect();
            let groups = group_by_room(&members);
            for (k, g) in groups.iter().enumerate() {
                for &m in &g.members {
                    group_of[m] = k;
                }
            }
            let keep: Vec<usize> = groups.iter().map(|g| g.representative).collect();
            cands = pick(&cands, &keep);
            infos = pick(&infos, &keep);
            for ((c, info), g) in cands.iter_mut().zip(&mut infos).zip(&groups) {
                c.frontier_cells = g.frontier_cells;
                info.frontier_cells = g.frontier_cells;
            }
            rooms = pick(&rooms, &keep);
            ideal = pick(&ideal, &keep);
            for row in &mut travel {
                *row = pick(row, &keep);
            }
        }
        let tuning = self.config.tuning;
        let candidate_of =
            |t: Cell| nearest_candidate(&tuning, &ungrouped, t).map(|(k, _)| group_of[k]);
        let mut bids = crate::bids::bids(
            self.config.exploration.strategy,
            &self.measures,
            &self.config.exploration.hypothesis,
            &positions,
            &infos,
            &travel,
            &mut self.strategy_rng,
        );
        let bonus = self.config.exploration.commitment_bonus;
        for (row, &i) in bids.iter_mut().zip(&bidders) {
            if let Some(t) = self.agents[i].target
                && let Some(k) = candidate_of(t)
                && let Some(u) = row[k].as_mut()
            {
                *u += bonus;
            }
        }
        // Robots keeping their targets occupy the candidate nearest to each target.
        let mut already = vec![0usize; cands.len()];
        for (j, a) in self.agents.iter().enumerate() {
            if who.contains(&j) || !a.alive {
                continue;
            }
            if let Some(t) = a.target
                && let Some(k) = candidate_of(t)
            {
                already[k] += 1;
            }
        }
        let x = &self.config.exploration;
        let chosen = crate::coordination::allocate_among(
            &bids,
            &ideal,
            &already,
            x.coordination,
            x.discount,
        );
        for (k, &i) in bidders.iter().enumerate() {
            match chosen[k] {
                Some(c) => {
                    let target = cands[c].cell;
                    let agent = &self.agents[i];
                    // Allocated what it is heading for (the same spot, or its target's room):
                    // it keeps its path.
                    if agent.target.is_some_and(|t| {
                        t.chebyshev(target) <= self.config.tuning.kept_target_cells
                            || candidate_of(t) == Some(c)
                    }) && !agent.follower.is_empty()
                    {
                        continue;
                    }
                    match self.plan_path(i, target) {
                        Some(waypoints) => {
                            let info = &infos[c];
                            self.allocations.push(crate::outcome::Allocation {
                                time_s: now,
                                robot: i,
                                x_m: info.position.x,
                                y_m: info.position.y,
                                label: info.label,
                                relevance: self.config.exploration.hypothesis.relevance(info.label),
                                frontier_cells: info.frontier_cells,
                                path_m: travel[k][c].map_or(f64::NAN, |t| t.length_m),
                                utility: bids[k][c].unwrap_or(f64::NAN),
                                ideal_robots: ideal[c],
                                room_known: rooms[c].map(|k| self.semantic.perceived_fraction(k)),
                            });
                            self.assignments.push(Assignment {
                                target,
                                candidate: cands[c].cell,
                            });
                            let agent = &mut self.agents[i];
                            agent.follower = PathFollower::new(waypoints);
                            agent.target = Some(target);
                            agent.recoveries = 0;
                            agent.escaping = false;
                            agent.may_retrace = true;
                        }
                        None => {
                            self.agents[i]
                                .blacklist
                                .push((target, now + self.config.tuning.blacklist_s));
                            self.idle(i);
                        }
                    }
                }
                None => self.idle(i),
            }
            let agent = &mut self.agents[i];
            agent.progress_mark = (agent.pose, now);
        }
    }

    /// The room of a map cell, or of the nearest cell within two cells that has one.
    pub(super) fn room_near(&self, cell: Cell) -> Option<usize> {
        self.semantic.room_near(self.base.merged.geometry(), cell)
    }
}

/// The elements of `v` at `keep`, in that order.
fn pick<T: Clone>(v: &[T], keep: &[usize]) -> Vec<T> {
    keep.iter().map(|&k| v[k].clone()).collect()
}

/// The candidate nearest a robot's target, within [`Tuning::kept_target_cells`]: (index, distance).
fn nearest_candidate(tuning: &Tuning, cands: &[Candidate], target: Cell) -> Option<(usize, i32)> {
    cands
        .iter()
        .enumerate()
        .map(|(k, c)| (k, c.cell.chebyshev(target)))
        .filter(|&(_, d)| d <= tuning.kept_target_cells)
        .min_by_key(|&(k, d)| (d, k))
}

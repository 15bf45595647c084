//! Paper 002's auction (§3.3) as named stages, from the frontier to the paths driven:
//!
//! 1. [`TeamController::offer`]: candidate locations from the frontier clusters, and what the
//!    team knows of each — its room, the perceived label (one classification per auction),
//!    doors, i(p) for MRv1 / MRv2 (visited candidates are marked);
//! 2. [`TeamController::price`]: each bidder's path lengths and times on the coarse bid grid;
//! 3. [`TeamController::group_rooms`]: one candidate per room
//!    ([`CandidateGrouping::Room`]), its representative standing for the room's frontier;
//! 4. [`TeamController::bid`]: u(p, r) by the strategy, plus the commitment bonus;
//! 5. [`TeamController::coordinate`]: SR / MRv1 / MRv2 among the bidders, robots keeping their
//!    targets counting towards i(p);
//! 6. [`TeamController::award`]: a path on the map to each new target (or a blacklist entry
//!    when there is none), and the records of the allocation.

use super::*;
use crate::bids::Travel;
use crate::criteria::CandidateInfo;

/// The candidates of one auction and what the team knows of them, row-aligned.
pub(super) struct Offer {
    cands: Vec<Candidate>,
    infos: Vec<CandidateInfo>,
    rooms: Vec<Option<usize>>,
    /// i(p) (1 under SR).
    ideal: Vec<usize>,
    /// Reached by some robot lately: priced by nobody.
    visited: Vec<bool>,
    /// Before grouping: every cluster candidate and the group it went to.
    ungrouped: Vec<Candidate>,
    group_of: Vec<usize>,
}

impl Offer {
    /// The candidate (after grouping) that target `t` belongs to, if any.
    fn candidate_of(&self, tuning: &Tuning, t: Cell) -> Option<usize> {
        nearest_candidate(tuning, &self.ungrouped, t).map(|(k, _)| self.group_of[k])
    }
}

/// The bidders' positions and their travel to every candidate (row per bidder).
pub(super) struct Pricing {
    positions: Vec<Point2>,
    travel: Vec<Vec<Option<Travel>>>,
}

impl TeamController {
    /// Paper 002's auction for the robots in `who` (see the module's stages). Robots that are
    /// not linked to the base station or have failed do not bid and keep what they do.
    pub(super) fn auction(&mut self, who: &[usize]) {
        self.refresh_semantics();
        let cands = self.candidate_locations();
        let bidders: Vec<usize> = who
            .iter()
            .copied()
            .filter(|&i| self.agents[i].linked && self.agents[i].alive)
            .collect();
        if bidders.is_empty() {
            return;
        }
        let mut offer = self.offer(cands);
        let mut pricing = self.price(&bidders, &offer);
        self.group_rooms(&mut offer, &mut pricing);
        let bids = self.bid(&bidders, &offer, &pricing);
        let chosen = self.coordinate(&bidders, &offer, &bids);
        self.award(&bidders, &chosen, &offer, &pricing, &bids);
    }

    /// The frontier clusters' candidate locations: cells the tight radius can stand on, outside
    /// the keep-out zones.
    pub(super) fn candidate_locations(&mut self) -> Vec<Candidate> {
        let clusters = self.base.clusters(self.config.min_cluster_cells);
        let g = *self.base.merged.geometry();
        let base = &self.base;
        candidates(
            &clusters,
            |c| {
                g.checked_index(c)
                    .is_some_and(|i| base.navigable_tight.is_navigable(&base.merged, i))
                    && !base.is_kept_out(c)
            },
            &g,
        )
    }

    /// Stage 1: what is known of each candidate — visited lately, room, perceived label (a
    /// classification of its own at every auction), doors, i(p).
    fn offer(&mut self, cands: Vec<Candidate>) -> Offer {
        let now = self.now;
        let g = *self.base.merged.geometry();
        self.visited.retain(|&(_, until)| until > now);
        let visited: Vec<bool> = cands
            .iter()
            .map(|c| {
                self.visited
                    .iter()
                    .any(|&(v, _)| v.chebyshev(c.cell) <= self.config.tuning.visited_cells)
            })
            .collect();
        let rooms: Vec<Option<usize>> = cands.iter().map(|c| self.room_near(c.cell)).collect();
        let labels: Vec<Option<RoomLabel>> = rooms
            .iter()
            .map(|r| r.map(|k| self.semantic.perceived_label(k)))
            .collect();
        let infos: Vec<CandidateInfo> = cands
            .iter()
            .zip(&rooms)
            .zip(&labels)
            .map(|((c, r), &label)| CandidateInfo {
                position: g.cell_center(c.cell),
                frontier_cells: c.frontier_cells,
                label,
                doors: r.map_or(0, |k| self.semantic.rooms()[k].doors),
            })
            .collect();
        let sr = self.config.exploration.coordination == crate::coordination::Coordination::Sr;
        // i(p) depends on the room, its perceived label and how much of it is known: inferred
        // again only when the label or the known fraction changed since the room's last one.
        let ideal: Vec<usize> = rooms
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
        let group_of = (0..cands.len()).collect();
        Offer {
            ungrouped: cands.clone(),
            cands,
            infos,
            rooms,
            ideal,
            visited,
            group_of,
        }
    }

    /// Stage 2: path lengths and times from each bidder on the coarse bid grid, to the
    /// candidates it prices (not visited, not near its blacklisted targets).
    fn price(&mut self, bidders: &[usize], offer: &Offer) -> Pricing {
        let now = self.now;
        let g = *self.base.merged.geometry();
        let grid = &self.base.bid_grid;
        let cg = *grid.geometry();
        let needs_time = matches!(
            self.config.exploration.strategy,
            Strategy::DMcdm | Strategy::SMcdm
        );
        let spec = self.config.robot.clone();
        let cands = &offer.cands;
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
        for &i in bidders {
            let pose = self.agents[i].pose;
            positions.push(pose.position());
            let agent = &mut self.agents[i];
            agent.blacklist.retain(|&(_, until)| until > now);
            targets.clear();
            for (k, (c, &visited)) in cands.iter().zip(&offer.visited).enumerate() {
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
            let row: Vec<Option<Travel>> = (0..cands.len())
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
                    Some(Travel { length_m, time_s })
                })
                .collect();
            travel.push(row);
        }
        Pricing { positions, travel }
    }

    /// Stage 3: one candidate per room (`room_candidates`): from here on each group's
    /// representative stands for its room's whole frontier. A robot's target still belongs to
    /// the group of the cluster candidate it was ([`Offer::candidate_of`]), wherever the
    /// group's representative is.
    fn group_rooms(&self, offer: &mut Offer, pricing: &mut Pricing) {
        if self.config.exploration.candidates != CandidateGrouping::Room {
            return;
        }
        let members: Vec<ClusterCandidate> = (0..offer.cands.len())
            .map(|c| ClusterCandidate {
                position: offer.infos[c].position,
                frontier_cells: offer.cands[c].frontier_cells,
                room: offer.rooms[c]
                    .filter(|&k| self.semantic.rooms()[k].label != RoomLabel::Corridor),
                reachable_by: pricing.travel.iter().filter(|row| row[c].is_some()).count(),
            })
            .collect();
        let groups = group_by_room(&members);
        for (k, g) in groups.iter().enumerate() {
            for &m in &g.members {
                offer.group_of[m] = k;
            }
        }
        let keep: Vec<usize> = groups.iter().map(|g| g.representative).collect();
        offer.cands = pick(&offer.cands, &keep);
        offer.infos = pick(&offer.infos, &keep);
        for ((c, info), g) in offer.cands.iter_mut().zip(&mut offer.infos).zip(&groups) {
            c.frontier_cells = g.frontier_cells;
            info.frontier_cells = g.frontier_cells;
        }
        offer.rooms = pick(&offer.rooms, &keep);
        offer.ideal = pick(&offer.ideal, &keep);
        for row in &mut pricing.travel {
            *row = pick(row, &keep);
        }
    }

    /// Stage 4: every bidder's utility for every candidate by the strategy, and the
    /// commitment bonus for the candidate its target belongs to.
    fn bid(
        &mut self,
        bidders: &[usize],
        offer: &Offer,
        pricing: &Pricing,
    ) -> Vec<Vec<Option<f64>>> {
        let mut bids = crate::bids::bids(
            self.config.exploration.strategy,
            &self.measures,
            &self.config.exploration.hypothesis,
            &pricing.positions,
            &offer.infos,
            &pricing.travel,
            &mut self.strategy_rng,
        );
        let bonus = self.config.exploration.commitment_bonus;
        let tuning = self.config.tuning;
        for (row, &i) in bids.iter_mut().zip(bidders) {
            if let Some(t) = self.agents[i].target
                && let Some(k) = offer.candidate_of(&tuning, t)
                && let Some(u) = row[k].as_mut()
            {
                *u += bonus;
            }
        }
        bids
    }

    /// Stage 5: the coordination method allocates candidates to bidders; robots keeping their
    /// targets (every working robot that does not bid) occupy the candidate nearest to each
    /// target.
    fn coordinate(
        &self,
        bidders: &[usize],
        offer: &Offer,
        bids: &[Vec<Option<f64>>],
    ) -> Vec<Option<usize>> {
        let tuning = self.config.tuning;
        let mut already = vec![0usize; offer.cands.len()];
        for (j, a) in self.agents.iter().enumerate() {
            if bidders.contains(&j) || !a.alive {
                continue;
            }
            if let Some(t) = a.target
                && let Some(k) = offer.candidate_of(&tuning, t)
            {
                already[k] += 1;
            }
        }
        let x = &self.config.exploration;
        crate::coordination::allocate_among(
            bids,
            &offer.ideal,
            &already,
            x.coordination,
            x.discount,
        )
    }

    /// Stage 6: each bidder's new target gets a path on the map; one allocated what it is
    /// heading for keeps its path; one whose target has no path blacklists it and idles.
    fn award(
        &mut self,
        bidders: &[usize],
        chosen: &[Option<usize>],
        offer: &Offer,
        pricing: &Pricing,
        bids: &[Vec<Option<f64>>],
    ) {
        let now = self.now;
        let tuning = self.config.tuning;
        for (k, &i) in bidders.iter().enumerate() {
            match chosen[k] {
                Some(c) => {
                    let target = offer.cands[c].cell;
                    let agent = &self.agents[i];
                    // Allocated what it is heading for (the same spot, or its target's room):
                    // it keeps its path.
                    if agent.target.is_some_and(|t| {
                        t.chebyshev(target) <= tuning.kept_target_cells
                            || offer.candidate_of(&tuning, t) == Some(c)
                    }) && !agent.follower.is_empty()
                    {
                        continue;
                    }
                    match self.plan_path(i, target) {
                        Some(waypoints) => {
                            let info = &offer.infos[c];
                            self.allocations.push(crate::outcome::Allocation {
                                time_s: now,
                                robot: i,
                                x_m: info.position.x,
                                y_m: info.position.y,
                                label: info.label,
                                relevance: self.config.exploration.hypothesis.relevance(info.label),
                                frontier_cells: info.frontier_cells,
                                path_m: pricing.travel[k][c].map_or(f64::NAN, |t| t.length_m),
                                utility: bids[k][c].unwrap_or(f64::NAN),
                                ideal_robots: offer.ideal[c],
                                room_known: offer.rooms[c]
                                    .map(|r| self.semantic.perceived_fraction(r)),
                            });
                            self.assignments.push(Assignment { target });
                            self.agents[i].head_for(target, waypoints);
                        }
                        None => {
                            self.agents[i]
                                .blacklist
                                .push((target, now + tuning.blacklist_s));
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

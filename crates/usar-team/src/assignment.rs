//! Assigning frontier candidates to robots. The baseline is paper 002's *Distance* strategy with
//! single-robot coordination (SR): repeatedly give the closest (robot, candidate) pair, one robot
//! per candidate, path costs from one distance field per robot.

use usar_map::FrontierCluster;
use usar_map::planning::{Connectivity, DistanceField, NavGrid};
use usar_world::Cell;

/// A candidate location a robot can be sent to.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// The navigable cell the robot drives to.
    pub cell: Cell,
    /// Frontier cells of its cluster (of its room's clusters, once grouped by room).
    pub frontier_cells: usize,
}

/// Candidate locations from frontier clusters: the cluster's candidate cell if the robot can
/// stand there, else the navigable cluster cell closest to the centroid; clusters without a
/// navigable cell are dropped.
pub fn candidates(
    clusters: &[FrontierCluster],
    is_navigable: impl Fn(Cell) -> bool,
    geometry: &usar_world::GridGeometry,
) -> Vec<Candidate> {
    clusters
        .iter()
        .filter_map(|cluster| {
            let cell = if is_navigable(cluster.candidate) {
                Some(cluster.candidate)
            } else {
                cluster
                    .cells
                    .iter()
                    .copied()
                    .filter(|&c| is_navigable(c))
                    .min_by(|a, b| {
                        let (da, db) = (
                            geometry.cell_center(*a).distance_squared(cluster.centroid),
                            geometry.cell_center(*b).distance_squared(cluster.centroid),
                        );
                        da.total_cmp(&db).then(a.cmp(b))
                    })
            }?;
            Some(Candidate {
                cell,
                frontier_cells: cluster.len(),
            })
        })
        .collect()
}

/// Path costs (cells) from one robot — its start cells `sources` — to every candidate; `None` =
/// unreachable.
pub fn path_costs(
    field: &mut DistanceField,
    grid: &NavGrid,
    sources: &[Cell],
    candidates: &[Candidate],
) -> Vec<Option<f64>> {
    field.compute(grid, sources, Connectivity::Eight);
    candidates
        .iter()
        .map(|c| field.distance_cells(c.cell))
        .collect()
}

/// Greedy single-robot assignment on a cost matrix `costs[robot][candidate]`: repeatedly the
/// cheapest unassigned pair (ties: lower robot, then lower candidate index). Robots left over
/// when candidates run out get their cheapest candidate even if it is taken, so nobody idles
/// while something is left to explore.
pub fn assign_nearest(costs: &[Vec<Option<f64>>]) -> Vec<Option<usize>> {
    let mut pairs: Vec<(f64, usize, usize)> = costs
        .iter()
        .enumerate()
        .flat_map(|(r, row)| {
            row.iter()
                .enumerate()
                .filter_map(move |(c, cost)| cost.map(|d| (d, r, c)))
        })
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut robot_target = vec![None; costs.len()];
    let mut taken = vec![false; costs.first().map_or(0, Vec::len)];
    for &(_, r, c) in &pairs {
        if robot_target[r].is_none() && !taken[c] {
            robot_target[r] = Some(c);
            taken[c] = true;
        }
    }
    for &(_, r, c) in &pairs {
        if robot_target[r].is_none() {
            robot_target[r] = Some(c);
        }
    }
    robot_target
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_pairs_first_one_robot_per_candidate() {
        let costs = vec![
            vec![Some(5.0), Some(1.0)],
            vec![Some(2.0), Some(0.5)],
            vec![None, Some(9.0)],
        ];
        // Robot 1 takes candidate 1 (0.5), robot 0 then takes candidate 0 (5.0), robot 2 can only
        // reach the taken candidate 1.
        assert_eq!(assign_nearest(&costs), vec![Some(0), Some(1), Some(1)]);
        assert_eq!(assign_nearest(&[vec![None]]), vec![None]);
    }
}

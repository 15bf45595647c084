//! Candidate locations per room (paper 002 §3.1 and §3.3).
//!
//! §3.1 takes one candidate location per frontier cluster. A furnished room seen from its door
//! has many clusters, one behind each piece of furniture. Each of them is then a separate
//! candidate. SR sends a robot to each, and several robots end up in every room a strategy
//! favours. ST-MR's i(p) is a number of robots *for a room*: its inputs are the room's size,
//! doors, visibility and perceived area (Fig. 1). It has no meaning when SR already floods
//! the room.
//!
//! With [`CandidateGrouping::Room`], the clusters of one room form one candidate:
//! - A(p) is the room's whole frontier;
//! - the location is the cluster candidate nearest the frontier's centroid, weighted by
//!   cluster length, among the candidates the most bidders can reach.
//!
//! Corridors keep one candidate per cluster. Their frontiers lie far apart, at the ends and
//! at doorways, and a corridor is a way to rooms, not a place to cover.
//!
//! Which rooms are corridors comes from the room layer's own split (the scene's, or the room
//! segmentation's), not from the perceived labels. Under §4.4's label errors, a corridor perceived
//! as a room would otherwise merge its far-apart frontiers into one candidate. S(p) still uses
//! the perceived label.

use serde::{Deserialize, Serialize};
use usar_world::Point2;

/// How frontier clusters become candidate locations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CandidateGrouping {
    /// One candidate per frontier cluster (paper 002 §3.1 as written).
    Cluster,
    /// One candidate per room; corridors, and cells outside every room, keep one per cluster.
    #[default]
    Room,
}

impl CandidateGrouping {
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "cluster" => Some(Self::Cluster),
            "room" => Some(Self::Room),
            _ => None,
        }
    }
}

/// What grouping needs to know of a cluster candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterCandidate {
    pub position: Point2,
    pub frontier_cells: usize,
    /// The room it lies in, unless that is a corridor (or it lies in no room).
    pub room: Option<usize>,
    /// How many bidders can reach it.
    pub reachable_by: usize,
}

/// The cluster candidates of one room (or one candidate alone), as one candidate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RoomGroup {
    /// The member that stands for the group.
    pub representative: usize,
    /// Frontier cells of all members: A(p) of the group.
    pub frontier_cells: usize,
    /// Indices of the members, ascending.
    pub members: Vec<usize>,
}

/// One candidate per room: the groups, in order of their first member.
///
/// The representative is the member most bidders can reach. Ties go to the member nearest the
/// group's centroid, weighted by frontier length, then to the lower index.
pub fn group_by_room(clusters: &[ClusterCandidate]) -> Vec<RoomGroup> {
    let mut groups: Vec<(Option<usize>, Vec<usize>)> = Vec::new();
    for (k, c) in clusters.iter().enumerate() {
        match c
            .room
            .and_then(|room| groups.iter().position(|(r, _)| *r == Some(room)))
        {
            Some(g) => groups[g].1.push(k),
            None => groups.push((c.room, vec![k])),
        }
    }
    groups
        .into_iter()
        .map(|(_, members)| {
            let cells: usize = members.iter().map(|&m| clusters[m].frontier_cells).sum();
            let weight = cells.max(1) as f64;
            let (sx, sy) = members.iter().fold((0.0, 0.0), |(x, y), &m| {
                let c = &clusters[m];
                let w = c.frontier_cells as f64;
                (x + w * c.position.x, y + w * c.position.y)
            });
            let centroid = Point2::new(sx / weight, sy / weight);
            let off = |m: usize| clusters[m].position.distance_squared(centroid);
            let representative = members
                .iter()
                .copied()
                .min_by(|&a, &b| {
                    clusters[b]
                        .reachable_by
                        .cmp(&clusters[a].reachable_by)
                        .then(off(a).total_cmp(&off(b)))
                        .then(a.cmp(&b))
                })
                .expect("a group has a member");
            RoomGroup {
                representative,
                frontier_cells: cells,
                members,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cand(x: f64, cells: usize, room: Option<usize>, reach: usize) -> ClusterCandidate {
        ClusterCandidate {
            position: Point2::new(x, 0.0),
            frontier_cells: cells,
            room,
            reachable_by: reach,
        }
    }

    #[test]
    fn a_rooms_clusters_become_one_candidate_with_the_rooms_whole_frontier() {
        let c = [
            cand(0.0, 10, Some(3), 4),
            cand(50.0, 7, None, 4),
            cand(4.0, 10, Some(3), 4),
            cand(60.0, 9, None, 4),
            cand(1.0, 20, Some(3), 4),
        ];
        // Room 3's centroid lies at x = (0·10 + 4·10 + 1·20) / 40 = 1.5: the member at x = 1.
        // The two clusters outside rooms (or in corridors) stay apart.
        let groups: Vec<(usize, usize, Vec<usize>)> = group_by_room(&c)
            .into_iter()
            .map(|g| (g.representative, g.frontier_cells, g.members))
            .collect();
        assert_eq!(
            groups,
            vec![(4, 40, vec![0, 2, 4]), (1, 7, vec![1]), (3, 9, vec![3])]
        );
    }

    #[test]
    fn the_representative_is_the_member_most_bidders_can_reach() {
        let c = [
            cand(0.0, 10, Some(1), 2),
            cand(5.0, 10, Some(1), 6),
            cand(10.0, 10, Some(1), 6),
        ];
        // The centroid (x = 5) is on the middle one, and so is the best reach.
        assert_eq!(group_by_room(&c)[0].representative, 1);
        let c = [
            cand(0.0, 10, Some(1), 6),
            cand(5.0, 10, Some(1), 2),
            cand(10.0, 10, Some(1), 6),
        ];
        // Centred but reachable by fewer: the nearest of the best reached, ties to the lower.
        assert_eq!(group_by_room(&c)[0].representative, 0);
    }
}

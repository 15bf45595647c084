//! Frontiers (Yamauchi 1998; paper 002 §3.1): free cells with an unknown 4-neighbour, kept up to
//! date incrementally from an occupancy grid's log of class changes, grouped into 8-connected
//! frontier clusters, each with its candidate location — the cluster's cell closest to the
//! cluster's centroid.

use crate::occupancy::{CellClass, OccupancyGrid};
use serde::Serialize;
use usar_world::{Cell, Point2};

const ABSENT: u32 = u32::MAX;

/// The set of frontier cells of one occupancy grid.
#[derive(Clone, Debug)]
pub struct FrontierTracker {
    width: i32,
    height: i32,
    /// Frontier cells (row-major indices), in no particular order.
    cells: Vec<u32>,
    /// Position of each cell in `cells`, or ABSENT.
    slot: Vec<u32>,
    changed: Vec<u32>,
    visit_mark: Vec<u32>,
    visit_epoch: u32,
    /// Cells left out of the clusters ([`FrontierTracker::retire_near`]).
    retired: Vec<bool>,
}

/// A group of 8-connected frontier cells.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrontierCluster {
    /// Cells of the cluster, sorted row-major.
    pub cells: Vec<Cell>,
    /// Mean position of the cells' centres.
    pub centroid: Point2,
    /// The cluster cell closest to the centroid (ties: lowest row-major index).
    pub candidate: Cell,
}

impl FrontierCluster {
    /// Frontier length in cells (A(p) of paper 002 counts these).
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }
}

impl FrontierTracker {
    pub fn new(grid: &OccupancyGrid) -> Self {
        let g = grid.geometry();
        let n = g.len();
        let mut tracker = Self {
            width: g.width as i32,
            height: g.height as i32,
            cells: Vec::new(),
            slot: vec![ABSENT; n],
            changed: Vec::new(),
            visit_mark: vec![0; n],
            visit_epoch: 0,
            retired: vec![false; n],
        };
        for i in 0..n {
            tracker.refresh(grid, i);
        }
        tracker
    }

    /// Number of frontier cells.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    #[inline]
    pub fn is_frontier(&self, index: usize) -> bool {
        self.slot[index] != ABSENT
    }

    /// Takes the frontier cells within `radius_cells` (Euclidean, centre to centre) of `center`
    /// out of the clusters for the rest of the tracker's life. For an
    /// explorer that stood there and scanned: what it still could not see from so near lies
    /// where its sensor cannot look (behind furniture, or inside a wall that the map's cells
    /// straddle), and would draw robot after robot.
    pub fn retire_near(&mut self, center: Cell, radius_cells: i32) {
        let r2 = radius_cells * radius_cells;
        for dr in -radius_cells..=radius_cells {
            for dc in -radius_cells..=radius_cells {
                let (c, r) = (center.col + dc, center.row + dr);
                if dc * dc + dr * dr > r2 || c < 0 || r < 0 || c >= self.width || r >= self.height {
                    continue;
                }
                let i = r as usize * self.width as usize + c as usize;
                if self.slot[i] != ABSENT {
                    self.retired[i] = true;
                }
            }
        }
    }

    /// Frontier cell indices, sorted.
    pub fn sorted_indices(&self) -> Vec<u32> {
        let mut v = self.cells.clone();
        v.sort_unstable();
        v
    }

    fn is_frontier_cell(&self, grid: &OccupancyGrid, i: usize) -> bool {
        if grid.class_at_index(i) != CellClass::Free {
            return false;
        }
        let (c, r) = (
            (i % self.width as usize) as i32,
            (i / self.width as usize) as i32,
        );
        [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|&(dc, dr)| {
            let (cc, rr) = (c + dc, r + dr);
            cc >= 0
                && rr >= 0
                && cc < self.width
                && rr < self.height
                && grid.class_at_index(rr as usize * self.width as usize + cc as usize)
                    == CellClass::Unknown
        })
    }

    fn refresh(&mut self, grid: &OccupancyGrid, i: usize) {
        let now = self.is_frontier_cell(grid, i);
        let slot = self.slot[i];
        if now && slot == ABSENT {
            self.slot[i] = self.cells.len() as u32;
            self.cells.push(i as u32);
        } else if !now && slot != ABSENT {
            let last = *self.cells.last().expect("non-empty");
            self.cells.swap_remove(slot as usize);
            if last as usize != i {
                self.slot[last as usize] = slot;
            }
            self.slot[i] = ABSENT;
        }
    }

    /// Brings the frontier up to date with the cells whose class changed in `grid` since the
    /// last update (drains the grid's change log).
    pub fn update(&mut self, grid: &mut OccupancyGrid) {
        let mut changed = std::mem::take(&mut self.changed);
        changed.clear();
        grid.drain_changed(&mut changed);
        self.update_from(grid, &changed);
        self.changed = changed;
    }

    /// Brings the frontier up to date given the cells whose class changed (for callers that
    /// share one change log between several consumers): each changed cell and its
    /// 4-neighbours are re-examined.
    pub fn update_from(&mut self, grid: &OccupancyGrid, changed: &[u32]) {
        let w = self.width as usize;
        for &i in changed {
            let i = i as usize;
            let (c, r) = ((i % w) as i32, (i / w) as i32);
            self.refresh(grid, i);
            for (dc, dr) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (cc, rr) = (c + dc, r + dr);
                if cc >= 0 && rr >= 0 && cc < self.width && rr < self.height {
                    self.refresh(grid, rr as usize * w + cc as usize);
                }
            }
        }
    }

    /// Groups frontier cells into 8-connected clusters of at least `min_cells` cells, in order
    /// of their lowest cell index (deterministic).
    pub fn clusters(&mut self, grid: &OccupancyGrid, min_cells: usize) -> Vec<FrontierCluster> {
        let g = *grid.geometry();
        self.visit_epoch = self.visit_epoch.wrapping_add(1);
        if self.visit_epoch == 0 {
            self.visit_mark.fill(0);
            self.visit_epoch = 1;
        }
        let epoch = self.visit_epoch;
        let w = self.width as usize;
        let mut out = Vec::new();
        let mut stack = Vec::new();
        let mut members: Vec<u32> = Vec::new();
        for seed in self.sorted_indices() {
            if self.visit_mark[seed as usize] == epoch || self.retired[seed as usize] {
                continue;
            }
            members.clear();
            self.visit_mark[seed as usize] = epoch;
            stack.push(seed);
            while let Some(i) = stack.pop() {
                members.push(i);
                let (c, r) = ((i as usize % w) as i32, (i as usize / w) as i32);
                for (dc, dr) in usar_world::NEIGHBORS8 {
                    let (cc, rr) = (c + dc, r + dr);
                    if cc < 0 || rr < 0 || cc >= self.width || rr >= self.height {
                        continue;
                    }
                    let j = rr as usize * w + cc as usize;
                    if self.slot[j] != ABSENT && self.visit_mark[j] != epoch && !self.retired[j] {
                        self.visit_mark[j] = epoch;
                        stack.push(j as u32);
                    }
                }
            }
            if members.len() < min_cells {
                continue;
            }
            members.sort_unstable();
            let cells: Vec<Cell> = members
                .iter()
                .map(|&i| g.cell_of_index(i as usize))
                .collect();
            let n = cells.len() as f64;
            let (sx, sy) = cells.iter().fold((0.0, 0.0), |(sx, sy), &c| {
                let p = g.cell_center(c);
                (sx + p.x, sy + p.y)
            });
            let centroid = Point2::new(sx / n, sy / n);
            let candidate = *cells
                .iter()
                .min_by(|a, b| {
                    g.cell_center(**a)
                        .distance_squared(centroid)
                        .total_cmp(&g.cell_center(**b).distance_squared(centroid))
                })
                .expect("non-empty cluster");
            out.push(FrontierCluster {
                cells,
                centroid,
                candidate,
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::occupancy::OccupancyParams;
    use usar_readings::LaserScan;
    use usar_world::{GridGeometry, Pose2};

    #[test]
    fn incremental_frontier_matches_a_full_recomputation() {
        let g = GridGeometry::new(80, 60, 0.1, Point2::new(0.0, 0.0));
        let mut grid = OccupancyGrid::new(g, OccupancyParams::default());
        let mut tracker = FrontierTracker::new(&grid);
        for (k, x) in [1.0, 3.0, 5.5].into_iter().enumerate() {
            let ranges = (0..90)
                .map(|i| {
                    if (i + k) % 7 == 0 {
                        f32::INFINITY
                    } else {
                        1.0 + (i % 5) as f32 * 0.3
                    }
                })
                .collect();
            let scan = LaserScan {
                pose: Pose2::new(x, 3.0, 0.0),
                angle_min_rad: -3.1,
                angle_increment_rad: 0.07,
                max_range_m: 2.5,
                ranges_m: ranges,
            };
            grid.integrate_scan(&scan);
            tracker.update(&mut grid);
            let fresh = FrontierTracker::new(&grid);
            assert_eq!(tracker.sorted_indices(), fresh.sorted_indices());
        }
        let clusters = tracker.clusters(&grid, 1);
        assert!(!clusters.is_empty());
        let total: usize = clusters.iter().map(FrontierCluster::len).sum();
        assert_eq!(total, tracker.len());
        for c in &clusters {
            assert!(c.cells.contains(&c.candidate));
        }
    }
}

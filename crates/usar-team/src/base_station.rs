//! The base station (paper 002 §4.1): merges the robots' occupancy grids every few seconds and
//! keeps, on the merged map, the frontier and the navigable space for the team's robot size,
//! both updated from one log of class changes (which an evaluator may follow too, e.g. for
//! coverage).

use usar_map::occupancy::MergeSums;
use usar_map::planning::NavGrid;
use usar_map::{FrontierCluster, FrontierTracker, NavigableMap, OccupancyGrid, OccupancyParams};
use usar_world::{Cell, GridGeometry, Point2};

pub struct BaseStation {
    pub merged: OccupancyGrid,
    pub frontiers: FrontierTracker,
    /// Navigable space for paths the robot can turn anywhere on (circumscribed radius).
    pub navigable: NavigableMap,
    /// Navigable space for squeezing through (half the robot's width plus a margin): used when
    /// nothing is reachable with the full radius, e.g. a doorway narrowed by sensor noise.
    pub navigable_tight: NavigableMap,
    /// The planners' view of `navigable` and `navigable_tight` (passable = navigable), kept in
    /// step at every merge from the cells whose navigability may have changed.
    pub nav_grids: [NavGrid; 2],
    /// The coarse grid paper 002's bids are priced on (`bid_grid_factor` map cells a side): a
    /// cell is passable when any map cell inside it is navigable with the tight radius
    /// (optimistic, so no doorway closes; the path driven is planned on the map itself).
    pub bid_grid: NavGrid,
    bid_grid_factor: u32,
    changed: Vec<u32>,
    /// Cells whose tight navigability may have changed at the last merge.
    touched_tight: Vec<u32>,
    touched: Vec<u32>,
    /// Running sums of the robots' maps (the merge visits only what changed).
    sums: MergeSums,
    /// Places the team must not plan through (e.g. slopes and stairs another robot recorded),
    /// as segments with a clearance: (from, to, radius), metres.
    keep_out: Vec<(Point2, Point2, f64)>,
}

impl BaseStation {
    /// A base station whose map has `geometry` (the robots' maps must share it).
    pub fn new(
        geometry: GridGeometry,
        params: OccupancyParams,
        radius_m: f64,
        tight_radius_m: f64,
        bid_grid_factor: usize,
    ) -> Self {
        let merged = OccupancyGrid::new(geometry, params);
        let k = bid_grid_factor.max(1) as u32;
        Self {
            frontiers: FrontierTracker::new(&merged),
            navigable: NavigableMap::new(&merged, radius_m),
            navigable_tight: NavigableMap::new(&merged, tight_radius_m),
            // Nothing is known yet, so nothing is navigable.
            nav_grids: [
                NavGrid::all_blocked(geometry),
                NavGrid::all_blocked(geometry),
            ],
            bid_grid: NavGrid::all_blocked(GridGeometry::new(
                geometry.width.div_ceil(k),
                geometry.height.div_ceil(k),
                geometry.resolution_m * f64::from(k),
                geometry.origin,
            )),
            bid_grid_factor: k,
            merged,
            changed: Vec::new(),
            touched_tight: Vec::new(),
            touched: Vec::new(),
            sums: MergeSums::default(),
            keep_out: Vec::new(),
        }
    }

    /// Keeps the team's planners off every cell within `radius_m` of the segment `a`–`b`,
    /// now and after every merge.
    pub fn keep_out(&mut self, a: Point2, b: Point2, radius_m: f64) {
        if self.keep_out.contains(&(a, b, radius_m)) {
            return;
        }
        self.keep_out.push((a, b, radius_m));
        let g = *self.merged.geometry();
        let (lo, hi) = (
            g.world_to_cell(Point2::new(
                a.x.min(b.x) - radius_m,
                a.y.min(b.y) - radius_m,
            )),
            g.world_to_cell(Point2::new(
                a.x.max(b.x) + radius_m,
                a.y.max(b.y) + radius_m,
            )),
        );
        for row in lo.row..=hi.row {
            for col in lo.col..=hi.col {
                let c = Cell::new(col, row);
                if g.contains(c) && segment_distance(g.cell_center(c), a, b) <= radius_m {
                    self.close(c);
                }
            }
        }
    }

    /// Whether map cell `c` lies in a keep-out zone.
    pub fn is_kept_out(&self, c: Cell) -> bool {
        !self.keep_out.is_empty() && kept_out(&self.keep_out, self.merged.geometry().cell_center(c))
    }

    /// The keep-out segments given so far.
    pub fn keep_outs(&self) -> &[(Point2, Point2, f64)] {
        &self.keep_out
    }

    /// Makes map cell `c` impassable on both planning grids, and its coarse cell on the bid
    /// grid when no map cell inside it stays passable.
    fn close(&mut self, c: Cell) {
        for grid in &mut self.nav_grids {
            grid.set_passable(c, false);
        }
        self.refresh_coarse(c);
    }

    /// The bid grid's cell over map cell `fine`: passable when any map cell inside it is
    /// passable with the tight radius (optimistic, so that no doorway closes).
    fn refresh_coarse(&mut self, fine: Cell) {
        let k = self.bid_grid_factor as i32;
        let coarse = Cell::new(fine.col / k, fine.row / k);
        let tight = &self.nav_grids[1];
        let passable = (0..k).any(|dr| {
            (0..k).any(|dc| tight.is_passable(Cell::new(coarse.col * k + dc, coarse.row * k + dr)))
        });
        self.bid_grid.set_passable(coarse, passable);
    }

    /// Merges the robots' grids into the team map and updates everything derived from it.
    pub fn merge(&mut self, robot_maps: &mut [&mut OccupancyGrid]) {
        self.merged.merge_tracked(robot_maps, &mut self.sums);
        self.changed.clear();
        self.merged.drain_changed(&mut self.changed);
        self.frontiers.update_from(&self.merged, &self.changed);
        self.touched.clear();
        self.navigable
            .update_from_logged(&self.merged, &self.changed, &mut self.touched);
        self.touched_tight.clear();
        self.navigable_tight.update_from_logged(
            &self.merged,
            &self.changed,
            &mut self.touched_tight,
        );
        let g = *self.merged.geometry();
        for (k, (nav, touched)) in [
            (&self.navigable, &self.touched),
            (&self.navigable_tight, &self.touched_tight),
        ]
        .into_iter()
        .enumerate()
        {
            for &i in touched {
                let i = i as usize;
                let c = g.cell_of_index(i);
                let open = nav.is_navigable(&self.merged, i) && !self.is_kept_out(c);
                self.nav_grids[k].set_passable(c, open);
            }
        }
        // The bid grid: only the coarse cells over map cells whose tight navigability may have
        // changed are looked at again.
        let touched = std::mem::take(&mut self.touched_tight);
        for &i in &touched {
            self.refresh_coarse(g.cell_of_index(i as usize));
        }
        self.touched_tight = touched;
    }

    /// The cells whose class changed at the last merge.
    pub fn last_changes(&self) -> &[u32] {
        &self.changed
    }

    pub fn clusters(&mut self, min_cells: usize) -> Vec<FrontierCluster> {
        self.frontiers.clusters(&self.merged, min_cells)
    }
}

/// Whether `p` lies in one of the keep-out segments `keep_out` ((from, to, radius), as
/// [`BaseStation::keep_outs`] gives them).
pub fn kept_out(keep_out: &[(Point2, Point2, f64)], p: Point2) -> bool {
    keep_out
        .iter()
        .any(|&(a, b, r)| segment_distance(p, a, b) <= r)
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: Point2, a: Point2, b: Point2) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(Point2::new(a.x + t * dx, a.y + t * dy))
}

//! Where a robot of a given radius may drive on a map it is building: free cells with no
//! occupied cell within the radius. Kept up to date incrementally from the occupancy grid's
//! class changes by counting, for every cell, the occupied cells inside the disc around it.

use crate::occupancy::{CellClass, OccupancyGrid};
use usar_world::{Grid, GridGeometry};

#[derive(Clone, Debug)]
pub struct NavigableMap {
    geometry: GridGeometry,
    radius_m: f64,
    /// Offsets (dcol, drow) of the disc of cells within the radius (centre to centre).
    disc: Vec<(i32, i32)>,
    near_occupied: Vec<u16>,
    is_occupied: Vec<bool>,
}

impl NavigableMap {
    pub fn new(grid: &OccupancyGrid, radius_m: f64) -> Self {
        let geometry = *grid.geometry();
        let r = radius_m / geometry.resolution_m;
        let k = r.ceil() as i32;
        let disc = (-k..=k)
            .flat_map(|dr| (-k..=k).map(move |dc| (dc, dr)))
            .filter(|&(dc, dr)| f64::from(dc * dc + dr * dr) <= r * r + 1e-9)
            .collect();
        let n = geometry.len();
        let mut map = Self {
            geometry,
            radius_m,
            disc,
            near_occupied: vec![0; n],
            is_occupied: vec![false; n],
        };
        let all: Vec<u32> = (0..n as u32)
            .filter(|&i| grid.class_at_index(i as usize) == CellClass::Occupied)
            .collect();
        map.update_from(grid, &all);
        map
    }

    pub fn radius_m(&self) -> f64 {
        self.radius_m
    }

    /// Applies the class changes of `changed` cells.
    pub fn update_from(&mut self, grid: &OccupancyGrid, changed: &[u32]) {
        self.update(grid, changed, None);
    }

    /// Applies the class changes of `changed` cells and appends to `touched` every cell whose
    /// [`NavigableMap::is_navigable`] may have changed: the changed cells themselves and the
    /// cells that got their first occupied neighbour within the radius or lost their last one
    /// (a cell may appear more than once). Keeps a planner's grid in step without a rebuild.
    pub fn update_from_logged(
        &mut self,
        grid: &OccupancyGrid,
        changed: &[u32],
        touched: &mut Vec<u32>,
    ) {
        touched.extend_from_slice(changed);
        self.update(grid, changed, Some(touched));
    }

    fn update(
        &mut self,
        grid: &OccupancyGrid,
        changed: &[u32],
        mut touched: Option<&mut Vec<u32>>,
    ) {
        let (w, h) = (self.geometry.width as i32, self.geometry.height as i32);
        for &i in changed {
            let i = i as usize;
            let now = grid.class_at_index(i) == CellClass::Occupied;
            if now == self.is_occupied[i] {
                continue;
            }
            self.is_occupied[i] = now;
            let (c, r) = ((i % w as usize) as i32, (i / w as usize) as i32);
            for &(dc, dr) in &self.disc {
                let (cc, rr) = (c + dc, r + dr);
                if cc >= 0 && rr >= 0 && cc < w && rr < h {
                    let j = rr as usize * w as usize + cc as usize;
                    let count = &mut self.near_occupied[j];
                    if now {
                        *count += 1;
                    } else {
                        *count -= 1;
                    }
                    // 0 → 1 or 1 → 0: the cell's navigability may flip.
                    if *count == u16::from(now)
                        && let Some(t) = touched.as_deref_mut()
                    {
                        t.push(j as u32);
                    }
                }
            }
        }
    }

    /// Free and away from every occupied cell.
    #[inline]
    pub fn is_navigable(&self, grid: &OccupancyGrid, index: usize) -> bool {
        self.near_occupied[index] == 0 && grid.class_at_index(index) == CellClass::Free
    }

    /// Whether an occupied cell lies within the radius of a cell.
    #[inline]
    pub fn is_near_obstacle(&self, index: usize) -> bool {
        self.near_occupied[index] != 0
    }

    /// The blocked mask (`true` = not navigable) for planners.
    pub fn blocked_grid(&self, grid: &OccupancyGrid) -> Grid<bool> {
        Grid::from_vec(
            self.geometry,
            (0..self.geometry.len())
                .map(|i| !self.is_navigable(grid, i))
                .collect(),
        )
        .expect("same geometry")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::occupancy::OccupancyParams;
    use usar_readings::LaserScan;
    use usar_world::{Point2, Pose2};

    #[test]
    fn incremental_inflation_equals_a_fresh_one_and_keeps_the_radius() {
        let g = GridGeometry::new(60, 40, 0.1, Point2::new(0.0, 0.0));
        let mut grid = OccupancyGrid::new(g, OccupancyParams::default());
        let mut nav = NavigableMap::new(&grid, 0.3);
        let mut changed = Vec::new();
        for (x, r) in [(1.0, 2.0f32), (2.0, 1.5), (1.5, 0.4)] {
            let ranges = (0..72)
                .map(|i| if i % 9 == 0 { f32::INFINITY } else { r })
                .collect();
            grid.integrate_scan(&LaserScan {
                pose: Pose2::new(x, 2.0, 0.0),
                angle_min_rad: -3.1,
                angle_increment_rad: 0.087,
                max_range_m: 2.5,
                ranges_m: ranges,
            });
            changed.clear();
            grid.drain_changed(&mut changed);
            nav.update_from(&grid, &changed);
            let fresh = NavigableMap::new(&grid, 0.3);
            assert_eq!(nav.near_occupied, fresh.near_occupied);
        }
        let mut touched = Vec::new();
        let mut logged = NavigableMap::new(&OccupancyGrid::new(g, OccupancyParams::default()), 0.3);
        let mut planner_view: Vec<bool> = vec![false; g.len()];
        let mut fresh_grid = OccupancyGrid::new(g, OccupancyParams::default());
        for (x, r) in [(1.0, 2.0f32), (3.0, 1.0), (2.0, 0.6), (4.5, 2.2)] {
            let ranges = (0..90)
                .map(|i| if i % 7 == 0 { f32::INFINITY } else { r })
                .collect();
            fresh_grid.integrate_scan(&LaserScan {
                pose: Pose2::new(x, 2.0, 0.3),
                angle_min_rad: -3.1,
                angle_increment_rad: 0.07,
                max_range_m: 2.5,
                ranges_m: ranges,
            });
            changed.clear();
            fresh_grid.drain_changed(&mut changed);
            touched.clear();
            logged.update_from_logged(&fresh_grid, &changed, &mut touched);
            for &j in &touched {
                planner_view[j as usize] = logged.is_navigable(&fresh_grid, j as usize);
            }
            let expected: Vec<bool> = (0..g.len())
                .map(|j| logged.is_navigable(&fresh_grid, j))
                .collect();
            assert_eq!(planner_view, expected);
        }
        for i in 0..g.len() {
            if nav.is_navigable(&grid, i) {
                let p = g.cell_center(g.cell_of_index(i));
                for j in 0..g.len() {
                    if grid.class_at_index(j) == CellClass::Occupied {
                        assert!(g.cell_center(g.cell_of_index(j)).distance(p) > 0.3 - 1e-9);
                    }
                }
            }
        }
    }
}

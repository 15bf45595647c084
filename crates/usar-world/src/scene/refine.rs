//! A scene on a finer grid: each cell split into `factor` × `factor` cells that keep its
//! obstacle, floor height and room. Nothing else changes (victims, poses, rooms are in metres).

use super::Scene;
use crate::{Cell, Grid, GridGeometry};

impl Scene {
    /// This scene with each grid cell split into `factor` × `factor` (`factor` ≥ 1), for
    /// painting detail finer than its grid (a rubble zone) onto it.
    pub fn refined(&self, factor: u32) -> Scene {
        let factor = factor.max(1);
        if factor == 1 {
            return self.clone();
        }
        let g = *self.geometry();
        let fine = GridGeometry::new(
            g.width * factor,
            g.height * factor,
            g.resolution_m / f64::from(factor),
            g.origin,
        );
        let f = factor as i32;
        let split = |c: Cell| Cell::new(c.col / f, c.row / f);
        fn refine<T: Clone>(
            grid: &Grid<T>,
            fine: GridGeometry,
            split: impl Fn(Cell) -> Cell,
        ) -> Grid<T> {
            let data = (0..fine.len())
                .map(|i| grid[split(fine.cell_of_index(i))].clone())
                .collect();
            Grid::from_vec(fine, data).expect("one value per cell")
        }
        Scene {
            name: self.name.clone(),
            provenance: self.provenance.clone(),
            obstacle: refine(&self.obstacle, fine, split),
            floor_height_m: refine(&self.floor_height_m, fine, split),
            room_id: refine(&self.room_id, fine, split),
            rooms: self.rooms.clone(),
            doors: self.doors.clone(),
            victims: self.victims.clone(),
            heat_sources: self.heat_sources.clone(),
            start_poses: self.start_poses.clone(),
            coarse_cell_m: self.coarse_cell_m,
            ground_truth: self.ground_truth.clone(),
        }
    }
}

//! Coverage: the part of the scene's reachable area that the base station's map knows.

use usar_map::{CellClass, OccupancyGrid};
use usar_world::{Grid, GridGeometry, Scene};

/// Counts known cells among the reachable ones, incrementally.
#[derive(Clone, Debug)]
pub struct CoverageCounter {
    reachable: Grid<bool>,
    reachable_cells: usize,
    known_reachable: usize,
    counted: Vec<bool>,
}

impl CoverageCounter {
    /// Reachable area: obstacle-free cells 4-connected to the first start pose, on the map
    /// `geometry` (a map cell is reachable when the scene cell at its centre is).
    pub fn new(scene: &Scene, start: usar_world::Point2, geometry: &GridGeometry) -> Self {
        let sg = *scene.geometry();
        let fine = scene.reachable_mask(sg.world_to_cell(start));
        let reachable = if sg == *geometry {
            fine
        } else {
            let cells = (0..geometry.len())
                .map(|i| {
                    let c = sg.world_to_cell(geometry.cell_center(geometry.cell_of_index(i)));
                    fine.get(c).copied().unwrap_or(false)
                })
                .collect();
            Grid::from_vec(*geometry, cells).expect("one value per cell")
        };
        let reachable_cells = reachable.as_slice().iter().filter(|&&r| r).count();
        let n = reachable.as_slice().len();
        Self {
            reachable,
            reachable_cells,
            known_reachable: 0,
            counted: vec![false; n],
        }
    }

    pub fn update_from(&mut self, grid: &OccupancyGrid, changed: &[u32]) {
        let reachable = self.reachable.as_slice();
        for &i in changed {
            let i = i as usize;
            let known = grid.class_at_index(i) != CellClass::Unknown;
            if reachable[i] && known != self.counted[i] {
                self.counted[i] = known;
                if known {
                    self.known_reachable += 1;
                } else {
                    self.known_reachable -= 1;
                }
            }
        }
    }

    /// Explored ÷ reachable area, in [0, 1].
    pub fn coverage(&self) -> f64 {
        if self.reachable_cells == 0 {
            0.0
        } else {
            self.known_reachable as f64 / self.reachable_cells as f64
        }
    }

    pub fn reachable_cells(&self) -> usize {
        self.reachable_cells
    }

    pub fn known_reachable_cells(&self) -> usize {
        self.known_reachable
    }
}

//! The other robots as obstacles when a robot plans: each alive robot's disc closed once per
//! allocation round on a navigable grid, every closed cell with the number of discs covering
//! it, so that a robot plans with its own disc open where no other disc covers it. The same
//! grid as closing every other robot's disc for each planning robot, in O(robots) disc cells
//! per round rather than O(robots²). The cover counts live in a buffer the team keeps from
//! round to round (only the cells a round touched are cleared).

use super::*;

/// Calls `f` with every grid cell whose centre lies within `radius_m` of `p`.
fn for_disc(g: &GridGeometry, p: Point2, radius_m: f64, mut f: impl FnMut(Cell)) {
    let c = g.world_to_cell(p);
    let k = (radius_m / g.resolution_m).ceil() as i32;
    for dr in -k..=k {
        for dc in -k..=k {
            let n = Cell::new(c.col + dc, c.row + dr);
            if g.contains(n) && g.cell_center(n).distance(p) <= radius_m {
                f(n);
            }
        }
    }
}

/// See the [module documentation](self).
pub(super) struct RobotDiscs {
    radius_m: f64,
    /// Per grid cell: how many discs cover it (only cells that were passable are counted).
    cover: Vec<u16>,
    closed: Vec<Cell>,
}

impl RobotDiscs {
    /// Closes the discs of radius `radius_m` around `robots` on `grid`, counting in `cover`
    /// (all zero, or empty: it is sized to the grid).
    pub(super) fn close(
        grid: &mut NavGrid,
        robots: &[Point2],
        radius_m: f64,
        mut cover: Vec<u16>,
    ) -> Self {
        let g = *grid.geometry();
        cover.resize(g.len(), 0);
        let mut closed = Vec::new();
        for &p in robots {
            for_disc(&g, p, radius_m, |n| {
                let i = g.index(n);
                if cover[i] > 0 {
                    cover[i] = cover[i].saturating_add(1);
                } else if grid.is_passable(n) {
                    grid.set_passable(n, false);
                    cover[i] = 1;
                    closed.push(n);
                }
            });
        }
        Self {
            radius_m,
            cover,
            closed,
        }
    }

    /// Opens the cells of the disc around `p` (a robot among those closed) that no other disc
    /// covers; returns them, to close again with [`Self::close_own`].
    pub(super) fn open_own(&self, grid: &mut NavGrid, p: Point2) -> Vec<Cell> {
        let g = *grid.geometry();
        let mut opened = Vec::new();
        for_disc(&g, p, self.radius_m, |n| {
            if self.cover[g.index(n)] == 1 {
                grid.set_passable(n, true);
                opened.push(n);
            }
        });
        opened
    }

    pub(super) fn close_own(grid: &mut NavGrid, opened: &[Cell]) {
        for &n in opened {
            grid.set_passable(n, false);
        }
    }

    /// Opens every cell the discs closed: the grid as it was. Returns the cover buffer, all
    /// zero again, for the next round.
    pub(super) fn open_all(mut self, grid: &mut NavGrid) -> Vec<u16> {
        let g = *grid.geometry();
        for n in self.closed {
            grid.set_passable(n, true);
            self.cover[g.index(n)] = 0;
        }
        self.cover
    }
}

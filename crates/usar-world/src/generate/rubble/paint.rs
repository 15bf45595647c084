//! Step 3 of the rubble generator: floor heights and slabs of the fine grid for every coarse cell,
//! and the ground-truth feature that records the intention (see [`RubbleTerrain`] for the shapes
//! and why the cell view classifies them as intended).

use super::RubbleTerrain;
use super::layout::Layout;
use crate::cellview::CellClass;
use crate::geometry::Rect;
use crate::grid::Cell;
use crate::scene::{Scene, TerrainFeature, obstacle};
use rand::Rng;
use rand_pcg::Pcg64Mcg;
use std::ops::RangeInclusive;

pub(super) struct Painter<'a> {
    pub fine_per_side: u32,
    pub side_m: f64,
    pub terrain: &'a RubbleTerrain,
}

/// Uniform draw from a range that may be given backwards or empty.
fn draw(rng: &mut Pcg64Mcg, r: &RangeInclusive<f64>) -> f64 {
    let (lo, hi) = (r.start().min(*r.end()), r.start().max(*r.end()));
    if lo < hi {
        rng.random_range(lo..=hi)
    } else {
        lo
    }
}

/// Uniform noise in ±half_width (0 for a non-positive width).
fn noise(rng: &mut Pcg64Mcg, half_width: f64) -> f64 {
    if half_width > 0.0 {
        rng.random_range(-half_width..=half_width)
    } else {
        0.0
    }
}

impl Painter<'_> {
    /// Paints every coarse cell of `layout` into `scene` (whose fine grid has one cell of wall
    /// around the arena) and returns one feature per rubble or drop cell.
    pub fn paint(
        &self,
        rng: &mut Pcg64Mcg,
        scene: &mut Scene,
        layout: &Layout,
    ) -> Vec<TerrainFeature> {
        let mut features = Vec::new();
        for row in 0..layout.rows {
            for col in 0..layout.cols {
                let cell = Cell::new(col, row);
                let i = (row * layout.cols + col) as usize;
                let s = self.side_m;
                let region = Rect::new(
                    f64::from(col) * s,
                    f64::from(row) * s,
                    f64::from(col + 1) * s,
                    f64::from(row + 1) * s,
                );
                match layout.classes[i] {
                    CellClass::Open | CellClass::Victim => {
                        self.open(rng, scene, cell);
                    }
                    CellClass::Climbable => {
                        let peak = if rng.random_bool(self.terrain.ramp_share.clamp(0.0, 1.0)) {
                            self.ramp(rng, scene, layout, cell)
                        } else {
                            self.layer(rng, scene, cell)
                        };
                        features.push(TerrainFeature::Rubble {
                            region,
                            peak_height_m: peak,
                            climbable: true,
                        });
                    }
                    CellClass::NonClimbable => {
                        let peak = if layout.slab[i] {
                            self.slab(rng, scene, cell);
                            self.terrain.slab_height_m
                        } else {
                            self.pile(rng, scene, cell)
                        };
                        features.push(TerrainFeature::Rubble {
                            region,
                            peak_height_m: peak,
                            climbable: false,
                        });
                    }
                    CellClass::Drop => {
                        let depth_m = self.drop(rng, scene, cell);
                        features.push(TerrainFeature::Drop { region, depth_m });
                    }
                }
            }
        }
        features
    }

    /// Sets the height of every fine cell of a coarse cell from its offset (x, y) from the coarse
    /// centre, metres; returns the highest height set.
    fn shape(&self, scene: &mut Scene, cell: Cell, mut height: impl FnMut(f64, f64) -> f64) -> f64 {
        let n = self.fine_per_side as i32;
        let res = self.side_m / f64::from(n);
        let half = self.side_m / 2.0;
        let mut peak = f64::NEG_INFINITY;
        for v in 0..n {
            for u in 0..n {
                let x = (f64::from(u) + 0.5) * res - half;
                let y = (f64::from(v) + 0.5) * res - half;
                let z = height(x, y) as f32;
                scene.floor_height_m[Cell::new(1 + cell.col * n + u, 1 + cell.row * n + v)] = z;
                peak = peak.max(f64::from(z));
            }
        }
        peak
    }

    fn open(&self, rng: &mut Pcg64Mcg, scene: &mut Scene, cell: Cell) -> f64 {
        let e = self.terrain.open_noise_m;
        self.shape(scene, cell, |_, _| noise(rng, e))
    }

    /// A rough ramp rising along an axis, its foot toward an open neighbour if there is one.
    fn ramp(&self, rng: &mut Pcg64Mcg, scene: &mut Scene, layout: &Layout, cell: Cell) -> f64 {
        const AXES: [(i32, i32); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
        let open = |dc: i32, dr: i32| {
            layout.class(Cell::new(cell.col + dc, cell.row + dr)) == CellClass::Open
        };
        let mut options: Vec<(i32, i32)> = AXES
            .iter()
            .copied()
            .filter(|&(dc, dr)| open(-dc, -dr) && !open(dc, dr))
            .collect();
        if options.is_empty() {
            options = AXES
                .iter()
                .copied()
                .filter(|&(dc, dr)| open(-dc, -dr))
                .collect();
        }
        if options.is_empty() {
            options = AXES.to_vec();
        }
        let (ux, uy) = options[rng.random_range(0..options.len())];
        let foot = draw(rng, &self.terrain.ramp_foot_m);
        let flattest = ((self.terrain.ramp_top_m - foot) / self.side_m).max(0.0);
        let gradient = draw(rng, &self.terrain.climbable_slope_rad)
            .tan()
            .min(flattest);
        let e = self.terrain.climbable_noise_m;
        let half = self.side_m / 2.0;
        self.shape(scene, cell, |x, y| {
            let along = f64::from(ux) * x + f64::from(uy) * y + half;
            foot + gradient * along + noise(rng, e)
        })
    }

    /// A level layer of loose rubble.
    fn layer(&self, rng: &mut Pcg64Mcg, scene: &mut Scene, cell: Cell) -> f64 {
        let base = draw(rng, &self.terrain.layer_height_m);
        let e = self.terrain.climbable_noise_m;
        self.shape(scene, cell, |_, _| base + noise(rng, e))
    }

    /// A rough cone of rubble, apex near the cell centre.
    fn pile(&self, rng: &mut Pcg64Mcg, scene: &mut Scene, cell: Cell) -> f64 {
        let s = self.side_m;
        let peak = draw(rng, &self.terrain.pile_peak_m);
        let (ax, ay) = (
            rng.random_range(-0.15..=0.15) * s,
            rng.random_range(-0.15..=0.15) * s,
        );
        let radius = rng.random_range(0.5..=0.7) * s;
        let e = self.terrain.pile_noise_m.max(0.0);
        self.shape(scene, cell, |x, y| {
            let d = (x - ax).hypot(y - ay);
            let rubble = if e > 0.0 {
                rng.random_range(0.0..=e)
            } else {
                0.0
            };
            peak * (1.0 - d / radius).max(0.0) + rubble
        })
    }

    /// A furniture-like slab over part of the cell, on open floor.
    fn slab(&self, rng: &mut Pcg64Mcg, scene: &mut Scene, cell: Cell) {
        self.open(rng, scene, cell);
        let n = self.fine_per_side as i32;
        let cover = draw(rng, &self.terrain.slab_cover).clamp(0.0, 1.0);
        let area = (cover * f64::from(n * n)).ceil() as i32;
        let min_w = ((f64::from(area) / f64::from(n)).ceil() as i32).clamp(1, n);
        let w = rng.random_range(min_w..=n);
        let h = ((area + w - 1) / w).clamp(1, n);
        let (u0, v0) = (rng.random_range(0..=n - w), rng.random_range(0..=n - h));
        for v in v0..v0 + h {
            for u in u0..u0 + w {
                scene.obstacle[Cell::new(1 + cell.col * n + u, 1 + cell.row * n + v)] =
                    obstacle::FURNITURE;
            }
        }
    }

    /// A hole over the whole cell with a rough floor; returns its depth.
    fn drop(&self, rng: &mut Pcg64Mcg, scene: &mut Scene, cell: Cell) -> f64 {
        let depth = draw(rng, &self.terrain.drop_depth_m);
        let e = self.terrain.drop_noise_m;
        self.shape(scene, cell, |_, _| -depth + noise(rng, e));
        depth
    }
}

//! Splitting the free space at door-like narrowings: a watershed of the clearance (distance
//! transform), flooded from the widest places down, in which two basins that meet stay apart
//! only where the meeting point is a doorway.
//!
//! Cells are visited in order of decreasing clearance d (ties: lower index first). A cell with no
//! visited 8-neighbour starts a basin whose *peak* is its clearance; a cell touching one basin
//! joins it; a cell touching several is a *saddle* at level s = d(cell). Two basins a, b meeting
//! at level s are kept apart (Bormann et al. 2016's "critical points" of the generalised Voronoi
//! graph: local minima of the clearance along the medial axis) when
//!
//! ```text
//! s ≤ κ · min(peak_a, peak_b)            the passage is much narrower than both spaces
//! 2 s ≤ w_door                           and no wider than a doorway
//! min(peak_a, peak_b) − s ≥ h            both spaces rise clearly above the passage
//! min(area_a, area_b) ≥ A_core           both cores (cells above s) are room-sized
//! ```
//!
//! and merged otherwise (the small bumps of the clearance along a corridor, the wide junctions
//! of corridors, alcoves). Every later cell takes the basin of its highest visited neighbour,
//! which grows the rooms back down to the walls like a wavefront.

use super::SegmentationParams;
use std::cmp::Reverse;

/// Union-find over basins: parent, peak clearance (m), cells.
struct Basins {
    parent: Vec<u32>,
    peak: Vec<f32>,
    cells: Vec<u32>,
}

impl Basins {
    fn find(&mut self, mut b: u32) -> u32 {
        while self.parent[b as usize] != b {
            let p = self.parent[b as usize];
            self.parent[b as usize] = self.parent[p as usize];
            b = p;
        }
        b
    }

    fn new_basin(&mut self, peak: f32) -> u32 {
        let id = self.parent.len() as u32;
        self.parent.push(id);
        self.peak.push(peak);
        self.cells.push(1);
        id
    }

    fn union(&mut self, a: u32, b: u32) -> u32 {
        let (keep, gone) = if self.peak[a as usize] >= self.peak[b as usize] {
            (a, b)
        } else {
            (b, a)
        };
        self.parent[gone as usize] = keep;
        self.cells[keep as usize] += self.cells[gone as usize];
        keep
    }
}

/// Basin of every cell of `mask` (0 outside the mask, otherwise 1 + a basin number in order of
/// first cell index), clearance `d` in metres.
pub(super) fn flood(
    mask: &[bool],
    d: &[f32],
    width: usize,
    height: usize,
    cell_area_m2: f64,
    p: &SegmentationParams,
) -> Vec<u32> {
    const NONE: u32 = u32::MAX;
    let mut order: Vec<u32> = (0..mask.len() as u32)
        .filter(|&i| mask[i as usize])
        .collect();
    // Non-negative f32 order as their bit patterns do.
    order.sort_unstable_by_key(|&i| (Reverse(d[i as usize].to_bits()), i));
    let mut basin_of = vec![NONE; mask.len()];
    let mut b = Basins {
        parent: Vec::new(),
        peak: Vec::new(),
        cells: Vec::new(),
    };
    let min_core_cells = (p.min_core_area_m2 / cell_area_m2).ceil() as u32;
    let kappa = p.door_ratio as f32;
    let max_half_door = (p.max_door_width_m / 2.0) as f32;
    let min_depth = p.min_depth_m as f32;
    let mut roots = [0u32; 8];
    for &i in &order {
        let i = i as usize;
        let (col, row) = ((i % width) as i64, (i / width) as i64);
        let s = d[i];
        let mut n_roots = 0usize;
        let mut best: Option<(f32, u32)> = None;
        for (dc, dr) in usar_world::NEIGHBORS8 {
            let (c, r) = (col + i64::from(dc), row + i64::from(dr));
            if c < 0 || r < 0 || c >= width as i64 || r >= height as i64 {
                continue;
            }
            let j = r as usize * width + c as usize;
            if basin_of[j] == NONE {
                continue;
            }
            let root = b.find(basin_of[j]);
            if best.is_none_or(|(bd, _)| d[j] > bd) {
                best = Some((d[j], root));
            }
            if !roots[..n_roots].contains(&root) {
                roots[n_roots] = root;
                n_roots += 1;
            }
        }
        let Some((_, primary)) = best else {
            basin_of[i] = b.new_basin(s);
            continue;
        };
        basin_of[i] = primary;
        b.cells[primary as usize] += 1;
        for &other in &roots[..n_roots] {
            let a = b.find(primary);
            let o = b.find(other);
            if a == o {
                continue;
            }
            let lo = b.peak[a as usize].min(b.peak[o as usize]);
            let small = b.cells[a as usize].min(b.cells[o as usize]);
            let door = s <= kappa * lo
                && s <= max_half_door
                && lo - s >= min_depth
                && small >= min_core_cells;
            if !door {
                b.union(a, o);
            }
        }
    }
    // Compact numbering in order of first cell.
    let mut number = vec![0u32; b.parent.len()];
    let mut next = 0u32;
    let mut out = vec![0u32; mask.len()];
    for i in 0..mask.len() {
        if basin_of[i] == NONE {
            continue;
        }
        let r = b.find(basin_of[i]) as usize;
        if number[r] == 0 {
            next += 1;
            number[r] = next;
        }
        out[i] = number[r];
    }
    out
}

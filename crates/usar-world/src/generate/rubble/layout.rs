//! Step 1 of the rubble generator: the intended class of every coarse cell.
//!
//! Recursive division splits the arena by barriers of non-climbable rubble (one to three cells
//! thick) into the style's number of regions; every barrier gets one gate, a single open cell
//! (a line of them through a thick barrier) or a climbable crossing, so the regions form a tree.
//! Then blobs of non-climbable rubble (piles or slabs), climbable rubble and drops are added at
//! random until the style's class shares are met; a blob cell that would cut the passable cells
//! (open or climbable) apart is not placed.

use super::RubbleTerrain;
use super::style::StyleConfig;
use crate::cellview::CellClass;
use crate::grid::{Cell, NEIGHBORS8};
use rand::Rng;
use rand_pcg::Pcg64Mcg;
use std::ops::RangeInclusive;

/// Smallest side of a region between barriers, coarse cells.
const MIN_REGION_SIDE: i32 = 3;
/// Clutter blobs tried before a layout gives up on its class shares.
const CLUTTER_TRIES: u32 = 4000;

/// The intended classes of the arena's coarse cells, row-major, row 0 south.
#[derive(Clone, Debug)]
pub(super) struct Layout {
    pub cols: i32,
    pub rows: i32,
    pub classes: Vec<CellClass>,
    /// Non-climbable cells painted as furniture-like slabs rather than rubble piles.
    pub slab: Vec<bool>,
    /// Cells of the barriers' gates.
    pub gate: Vec<bool>,
    /// Cells on either side of a gate: kept open so that the gate stays usable.
    pub protected: Vec<bool>,
    pub climbable_gates: usize,
    counts: [usize; 4],
}

#[derive(Clone, Copy, Debug)]
struct Region {
    c0: i32,
    r0: i32,
    c1: i32,
    r1: i32,
}

impl Region {
    fn area(&self) -> i64 {
        i64::from(self.c1 - self.c0) * i64::from(self.r1 - self.r0)
    }
}

/// One way to split a region: a barrier `thickness` cells thick starting at column (vertical
/// barrier) or row `at`.
#[derive(Clone, Copy, Debug)]
struct Split {
    region: usize,
    vertical: bool,
    at: i32,
    thickness: i32,
}

fn class_slot(class: CellClass) -> usize {
    match class {
        CellClass::Open | CellClass::Victim => 0,
        CellClass::Climbable => 1,
        CellClass::NonClimbable => 2,
        CellClass::Drop => 3,
    }
}

impl Layout {
    fn new(cols: i32, rows: i32) -> Self {
        let n = (cols * rows) as usize;
        Self {
            cols,
            rows,
            classes: vec![CellClass::Open; n],
            slab: vec![false; n],
            gate: vec![false; n],
            protected: vec![false; n],
            climbable_gates: 0,
            counts: [n, 0, 0, 0],
        }
    }

    pub fn len(&self) -> usize {
        self.classes.len()
    }

    pub fn index(&self, c: Cell) -> Option<usize> {
        (c.col >= 0 && c.row >= 0 && c.col < self.cols && c.row < self.rows)
            .then(|| (c.row * self.cols + c.col) as usize)
    }

    pub fn cell(&self, i: usize) -> Cell {
        Cell::new(i as i32 % self.cols, i as i32 / self.cols)
    }

    /// Intended class; outside the arena everything is non-climbable (the boundary wall).
    pub fn class(&self, c: Cell) -> CellClass {
        self.index(c)
            .map_or(CellClass::NonClimbable, |i| self.classes[i])
    }

    pub fn is_passable(&self, c: Cell, can_climb: bool) -> bool {
        self.class(c).is_passable_terrain(can_climb)
    }

    pub fn count(&self, class: CellClass) -> usize {
        self.counts[class_slot(class)]
    }

    fn set(&mut self, i: usize, class: CellClass) {
        self.counts[class_slot(self.classes[i])] -= 1;
        self.counts[class_slot(class)] += 1;
        self.classes[i] = class;
    }

    /// The 4-neighbours of a cell inside the arena.
    pub fn neighbours(&self, c: Cell) -> impl Iterator<Item = (Cell, usize)> + '_ {
        NEIGHBORS8[..4].iter().filter_map(move |&(dc, dr)| {
            let n = Cell::new(c.col + dc, c.row + dr);
            self.index(n).map(|i| (n, i))
        })
    }

    /// Breadth-first distances (4-connected steps) from `start` through passable cells not in
    /// `blocked`; `None` where unreachable.
    pub fn distances(&self, start: Cell, can_climb: bool, blocked: &[bool]) -> Vec<Option<u32>> {
        let mut dist = vec![None; self.len()];
        let Some(s) = self.index(start) else {
            return dist;
        };
        if !self.is_passable(start, can_climb) || blocked[s] {
            return dist;
        }
        dist[s] = Some(0);
        let mut queue = std::collections::VecDeque::from([s]);
        while let Some(k) = queue.pop_front() {
            let d = dist[k].unwrap_or(0);
            for (_, i) in self.neighbours(self.cell(k)) {
                if dist[i].is_none()
                    && !blocked[i]
                    && self.classes[i].is_passable_terrain(can_climb)
                {
                    dist[i] = Some(d + 1);
                    queue.push_back(i);
                }
            }
        }
        dist
    }

    /// Cells reachable from `start` (see [`Layout::distances`]).
    pub fn reach(&self, start: Cell, can_climb: bool, blocked: &[bool]) -> Vec<bool> {
        self.distances(start, can_climb, blocked)
            .iter()
            .map(Option::is_some)
            .collect()
    }

    /// Whether all cells that are passable with climbing and not `blocked` form one component.
    pub fn passable_connected(&self, blocked: &[bool]) -> bool {
        let passable = |i: usize| !blocked[i] && self.classes[i].is_passable_terrain(true);
        let total = (0..self.len()).filter(|&i| passable(i)).count();
        let Some(first) = (0..self.len()).find(|&i| passable(i)) else {
            return true;
        };
        let reached = self
            .reach(self.cell(first), true, blocked)
            .iter()
            .filter(|&&r| r)
            .count();
        reached == total
    }
}

/// A layout that meets the style's class shares and needs, or `None`.
pub(super) fn build(
    rng: &mut Pcg64Mcg,
    config: &StyleConfig,
    cols: i32,
    rows: i32,
    terrain: &RubbleTerrain,
) -> Option<Layout> {
    let layout = build_unchecked(rng, config, cols, rows, terrain);
    let n = layout.len() as f64;
    let share = |class| layout.count(class) as f64 / n;
    let shares = &config.shares;
    let meets = shares
        .non_climbable
        .contains(&share(CellClass::NonClimbable))
        && shares.climbable.contains(&share(CellClass::Climbable))
        && shares.drop.contains(&share(CellClass::Drop))
        && layout.passable_connected(&vec![false; layout.len()])
        && (!config.needs_climb_only_victim || layout.climbable_gates > 0);
    meets.then_some(layout)
}

/// A layout built as well as the style allows, without checking the result.
pub(super) fn build_unchecked(
    rng: &mut Pcg64Mcg,
    config: &StyleConfig,
    cols: i32,
    rows: i32,
    terrain: &RubbleTerrain,
) -> Layout {
    let mut layout = Layout::new(cols, rows);
    divide(rng, config, &mut layout);
    clutter(rng, config, terrain, &mut layout);
    layout
}

/// Recursive division into `config.regions` regions, keeping the barrier cells within the
/// smallest non-climbable share.
fn divide(rng: &mut Pcg64Mcg, config: &StyleConfig, layout: &mut Layout) {
    let budget = (config.shares.non_climbable.start() * layout.len() as f64).floor() as usize;
    let target = rng.random_range(ordered_u32(&config.regions)) as usize;
    let mut regions = vec![Region {
        c0: 0,
        r0: 0,
        c1: layout.cols,
        r1: layout.rows,
    }];
    let mut barrier_cells = 0usize;
    let mut gates: Vec<Vec<usize>> = Vec::new();
    while regions.len() < target {
        let thickness = rng
            .random_range(ordered_i32(&config.barrier_thickness))
            .max(1);
        let options = split_options(
            layout,
            &regions,
            thickness,
            budget.saturating_sub(barrier_cells),
        );
        if options.is_empty() {
            break;
        }
        let split = choose_split(rng, &regions, &options);
        let region = regions[split.region];
        let (cells, gate) = apply_split(rng, layout, region, split);
        barrier_cells += cells;
        let climbable = rng.random_bool(config.climbable_gate_probability.clamp(0.0, 1.0));
        if climbable {
            for &i in &gate {
                layout.set(i, CellClass::Climbable);
            }
            layout.climbable_gates += 1;
        }
        gates.push(gate);
        let (a, b) = if split.vertical {
            (
                Region {
                    c1: split.at,
                    ..region
                },
                Region {
                    c0: split.at + split.thickness,
                    ..region
                },
            )
        } else {
            (
                Region {
                    r1: split.at,
                    ..region
                },
                Region {
                    r0: split.at + split.thickness,
                    ..region
                },
            )
        };
        regions[split.region] = a;
        regions.push(b);
    }
    if config.needs_climb_only_victim && layout.climbable_gates == 0 && !gates.is_empty() {
        let k = rng.random_range(0..gates.len());
        for &i in &gates[k] {
            layout.set(i, CellClass::Climbable);
        }
        layout.climbable_gates += 1;
    }
}

fn split_options(layout: &Layout, regions: &[Region], thickness: i32, budget: usize) -> Vec<Split> {
    let mut options = Vec::new();
    for (ri, r) in regions.iter().enumerate() {
        let (w, h) = (r.c1 - r.c0, r.r1 - r.r0);
        // Split across the longer side; across the other one only if that is impossible.
        let preferred: &[bool] = match w.cmp(&h) {
            std::cmp::Ordering::Greater => &[true],
            std::cmp::Ordering::Less => &[false],
            std::cmp::Ordering::Equal => &[true, false],
        };
        let before = options.len();
        for pass in 0..2 {
            for vertical in [true, false] {
                if preferred.contains(&vertical) != (pass == 0) {
                    continue;
                }
                let (lo, hi, span) = if vertical {
                    (r.c0, r.c1, h)
                } else {
                    (r.r0, r.r1, w)
                };
                let cost = ((span - 1) * thickness) as usize;
                if cost > budget {
                    continue;
                }
                for at in lo + MIN_REGION_SIDE..=hi - MIN_REGION_SIDE - thickness {
                    if !barrier_ends_block_gate(layout, r, vertical, at, thickness) {
                        options.push(Split {
                            region: ri,
                            vertical,
                            at,
                            thickness,
                        });
                    }
                }
            }
            if options.len() > before {
                break;
            }
        }
    }
    options
}

/// Whether a barrier would end right in front of a gate of the surrounding barriers.
fn barrier_ends_block_gate(layout: &Layout, r: &Region, vertical: bool, at: i32, t: i32) -> bool {
    let ends: Vec<Cell> = if vertical {
        (at..at + t)
            .flat_map(|c| [Cell::new(c, r.r0 - 1), Cell::new(c, r.r1)])
            .collect()
    } else {
        (at..at + t)
            .flat_map(|row| [Cell::new(r.c0 - 1, row), Cell::new(r.c1, row)])
            .collect()
    };
    ends.into_iter()
        .any(|c| layout.index(c).is_some_and(|i| layout.gate[i]))
}

/// Picks a region with probability ∝ area², then one of its splits uniformly.
fn choose_split(rng: &mut Pcg64Mcg, regions: &[Region], options: &[Split]) -> Split {
    let mut weights = vec![0f64; regions.len()];
    for o in options {
        weights[o.region] = (regions[o.region].area() as f64).powi(2);
    }
    let total: f64 = weights.iter().sum();
    let mut pick = rng.random_range(0.0..total);
    let mut region = options[0].region;
    for (ri, &w) in weights.iter().enumerate() {
        if w > 0.0 {
            region = ri;
            if pick < w {
                break;
            }
            pick -= w;
        }
    }
    let own: Vec<&Split> = options.iter().filter(|o| o.region == region).collect();
    *own[rng.random_range(0..own.len())]
}

/// Draws the barrier and its gate; returns the number of barrier cells and the gate's cells.
fn apply_split(
    rng: &mut Pcg64Mcg,
    layout: &mut Layout,
    r: Region,
    s: Split,
) -> (usize, Vec<usize>) {
    let (span_lo, span_hi) = if s.vertical {
        (r.r0, r.r1)
    } else {
        (r.c0, r.c1)
    };
    let gate_at = rng.random_range(span_lo..span_hi);
    let mut gate = Vec::new();
    let mut cells = 0;
    for across in s.at..s.at + s.thickness {
        for along in span_lo..span_hi {
            let c = if s.vertical {
                Cell::new(across, along)
            } else {
                Cell::new(along, across)
            };
            let Some(i) = layout.index(c) else { continue };
            if along == gate_at {
                layout.gate[i] = true;
                gate.push(i);
            } else {
                layout.set(i, CellClass::NonClimbable);
                cells += 1;
            }
        }
    }
    let exits = if s.vertical {
        [
            Cell::new(s.at - 1, gate_at),
            Cell::new(s.at + s.thickness, gate_at),
        ]
    } else {
        [
            Cell::new(gate_at, s.at - 1),
            Cell::new(gate_at, s.at + s.thickness),
        ]
    };
    for c in exits {
        if let Some(i) = layout.index(c) {
            layout.protected[i] = true;
        }
    }
    (cells, gate)
}

/// Adds blobs until the drawn class counts are met or the tries run out.
fn clutter(rng: &mut Pcg64Mcg, config: &StyleConfig, terrain: &RubbleTerrain, layout: &mut Layout) {
    let n = layout.len() as f64;
    let mut goal = |r: &RangeInclusive<f64>| {
        let lo = (r.start() * n).ceil().max(0.0) as usize;
        let hi = (r.end() * n).floor().max(0.0) as usize;
        if lo >= hi {
            lo
        } else {
            rng.random_range(lo..=hi)
        }
    };
    let kinds = [
        CellClass::NonClimbable,
        CellClass::Climbable,
        CellClass::Drop,
    ];
    let goals = [
        goal(&config.shares.non_climbable),
        goal(&config.shares.climbable),
        goal(&config.shares.drop),
    ];
    let slab_share = terrain.slab_share.clamp(0.0, 1.0);
    for _ in 0..CLUTTER_TRIES {
        let deficits: Vec<usize> = kinds
            .iter()
            .zip(goals)
            .map(|(&k, g)| g.saturating_sub(layout.count(k)))
            .collect();
        let total: usize = deficits.iter().sum();
        if total == 0 {
            break;
        }
        let mut pick = rng.random_range(0..total);
        let mut k = 0;
        while pick >= deficits[k] {
            pick -= deficits[k];
            k += 1;
        }
        let max_blob = match kinds[k] {
            CellClass::NonClimbable => 5,
            CellClass::Climbable => 4,
            _ => 2,
        };
        let size = rng.random_range(1..=max_blob.min(deficits[k]));
        let slab = kinds[k] == CellClass::NonClimbable && rng.random_bool(slab_share);
        grow_blob(rng, layout, kinds[k], size, slab);
    }
}

fn grow_blob(rng: &mut Pcg64Mcg, layout: &mut Layout, class: CellClass, size: usize, slab: bool) {
    let eligible =
        |l: &Layout, i: usize| l.classes[i] == CellClass::Open && !l.gate[i] && !l.protected[i];
    let mut next = Some(rng.random_range(0..layout.len()));
    let mut blob: Vec<usize> = Vec::with_capacity(size);
    let no_blocked = vec![false; layout.len()];
    while blob.len() < size {
        let Some(i) = next.filter(|&i| eligible(layout, i)) else {
            break;
        };
        layout.set(i, class);
        if !class.is_passable_terrain(true) && !layout.passable_connected(&no_blocked) {
            layout.set(i, CellClass::Open);
            break;
        }
        layout.slab[i] = slab;
        blob.push(i);
        let candidates: Vec<usize> = blob
            .iter()
            .flat_map(|&b| {
                layout
                    .neighbours(layout.cell(b))
                    .map(|(_, j)| j)
                    .collect::<Vec<_>>()
            })
            .filter(|&j| eligible(layout, j))
            .collect();
        next = (!candidates.is_empty()).then(|| candidates[rng.random_range(0..candidates.len())]);
    }
}

fn ordered_u32(r: &RangeInclusive<u32>) -> RangeInclusive<u32> {
    *r.start().min(r.end())..=*r.start().max(r.end())
}

fn ordered_i32(r: &RangeInclusive<i32>) -> RangeInclusive<i32> {
    *r.start().min(r.end())..=*r.start().max(r.end())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::rubble::RubbleStyle;
    use rand::SeedableRng;

    #[test]
    fn division_gives_one_gate_per_barrier_and_keeps_cells_connected() {
        for style in RubbleStyle::ALL {
            let config = style.config();
            let mut rng = Pcg64Mcg::seed_from_u64(3);
            let mut layout = Layout::new(20, 20);
            divide(&mut rng, &config, &mut layout);
            assert!(layout.passable_connected(&vec![false; 400]), "{style:?}");
            assert!(
                layout.gate.iter().any(|&g| g),
                "{style:?}: no barrier drawn"
            );
        }
    }
}

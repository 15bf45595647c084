//! Step 2 of the rubble generator: start poses, victims and heat sources on the coarse layout.
//!
//! Paper 000 §VI: "7–8 victims were placed strategically in corners and hard to reach regions of
//! the scene", and each scene is explored from three start positions and headings (Fig. 8(b)).
//! A victim cell is scored by
//!
//! ```text
//! score = 1.5·(blocked 4-neighbours) + 2·(steps from start 0 / farthest steps)
//!       + 1.5·[reachable only over climbable rubble] + U(0, 1)
//! ```
//!
//! and the best cells are taken greedily, never two victims side by side (Chebyshev distance
//! ≥ 2), never in a gate, and never where the victim would cut the arena apart for a robot that
//! does not enter victim cells (the paper's robot does not).

use super::layout::Layout;
use super::style::StyleConfig;
use crate::cellview::CellClass;
use crate::geometry::Point2;
use crate::grid::Cell;
use rand::Rng;
use rand_pcg::Pcg64Mcg;
use std::f64::consts::{FRAC_PI_2, PI};

/// A victim's coarse cell.
#[derive(Clone, Copy, Debug)]
pub(super) struct PlacedVictim {
    pub cell: Cell,
    /// Reachable from start 0 only over climbable rubble.
    pub climb_only: bool,
}

#[derive(Clone, Debug, Default)]
pub(super) struct Placement {
    /// Start cells with headings (multiples of 90°); start 0 first.
    pub starts: Vec<(Cell, f64)>,
    /// Victims, hardest to reach first.
    pub victims: Vec<PlacedVictim>,
    pub heat_sources: Vec<Cell>,
    /// Whether every count and need was met.
    pub complete: bool,
}

/// Start poses per arena (paper 000 Fig. 8(b)).
const START_POSES: usize = 3;

pub(super) fn place(
    rng: &mut Pcg64Mcg,
    layout: &Layout,
    config: &StyleConfig,
    victims_wanted: u32,
    heat_wanted: u32,
) -> Placement {
    let n = layout.len();
    let none = vec![false; n];
    let open: Vec<usize> = (0..n)
        .filter(|&i| layout.classes[i] == CellClass::Open && !layout.gate[i])
        .collect();
    let mut candidates = open.clone();
    if config.needs_climb_only_victim {
        candidates.retain(|&i| {
            let walk = layout.reach(layout.cell(i), false, &none);
            let climb = layout.reach(layout.cell(i), true, &none);
            (0..n).any(|j| climb[j] && !walk[j] && !layout.gate[j])
        });
    }
    if candidates.is_empty() {
        candidates = open;
    }
    if candidates.is_empty() {
        return Placement::default();
    }
    let s0 = candidates[rng.random_range(0..candidates.len())];
    let start0 = layout.cell(s0);
    let walk = layout.reach(start0, false, &none);
    let dist0 = layout.distances(start0, true, &none);
    let reach_count = dist0.iter().filter(|d| d.is_some()).count();

    let victims = choose_victims(
        rng,
        layout,
        config,
        s0,
        &walk,
        &dist0,
        reach_count,
        victims_wanted,
    );
    let mut taken = vec![false; n];
    for v in &victims {
        if let Some(i) = layout.index(v.cell) {
            taken[i] = true;
        }
    }

    // Starts 1 and 2: open cells far (in steps) from the starts already chosen, not next to a
    // victim.
    let mut starts = vec![s0];
    let mut nearest: Vec<u32> = dist0.iter().map(|d| d.unwrap_or(0)).collect();
    while starts.len() < START_POSES {
        let mut best: Option<(f64, usize)> = None;
        for i in 0..n {
            let free =
                layout.classes[i] == CellClass::Open && !layout.gate[i] && dist0[i].is_some();
            let near_victim = victims
                .iter()
                .any(|v| v.cell.chebyshev(layout.cell(i)) <= 1);
            if !free || near_victim || starts.contains(&i) {
                continue;
            }
            let score = f64::from(nearest[i]) + rng.random_range(0.0..2.0);
            if best.is_none_or(|(b, _)| score > b) {
                best = Some((score, i));
            }
        }
        let Some((_, s)) = best else { break };
        starts.push(s);
        for (k, d) in layout
            .distances(layout.cell(s), true, &none)
            .iter()
            .enumerate()
        {
            if let Some(d) = *d {
                nearest[k] = nearest[k].min(d);
            }
        }
    }
    for &s in &starts {
        taken[s] = true;
    }

    let mut heat_candidates: Vec<usize> = (0..n)
        .filter(|&i| dist0[i].is_some() && !taken[i] && !layout.gate[i])
        .collect();
    let mut heat_sources = Vec::new();
    while heat_sources.len() < heat_wanted as usize && !heat_candidates.is_empty() {
        let k = rng.random_range(0..heat_candidates.len());
        heat_sources.push(layout.cell(heat_candidates.swap_remove(k)));
    }

    let complete = starts.len() == START_POSES
        && victims.len() == victims_wanted as usize
        && heat_sources.len() == heat_wanted as usize
        && (!config.needs_climb_only_victim || victims.iter().any(|v| v.climb_only));
    Placement {
        starts: starts
            .iter()
            .map(|&s| (layout.cell(s), heading(rng, layout, layout.cell(s))))
            .collect(),
        victims,
        heat_sources,
        complete,
    }
}

#[allow(clippy::too_many_arguments)]
fn choose_victims(
    rng: &mut Pcg64Mcg,
    layout: &Layout,
    config: &StyleConfig,
    s0: usize,
    walk: &[bool],
    dist0: &[Option<u32>],
    reach_count: usize,
    wanted: u32,
) -> Vec<PlacedVictim> {
    let start0 = layout.cell(s0);
    let farthest = dist0.iter().flatten().copied().max().unwrap_or(1).max(1);
    let mut scored: Vec<(f64, usize)> = Vec::new();
    for (i, d) in dist0.iter().enumerate() {
        let Some(d) = *d else { continue };
        let c = layout.cell(i);
        if layout.gate[i] || c.chebyshev(start0) <= 1 {
            continue;
        }
        let blocked = layout
            .neighbours(c)
            .filter(|&(n, _)| !layout.is_passable(n, true))
            .count()
            + (4 - layout.neighbours(c).count());
        let climb_only = if walk[i] { 0.0 } else { 1.5 };
        let score = 1.5 * blocked as f64
            + 2.0 * f64::from(d) / f64::from(farthest)
            + climb_only
            + rng.random_range(0.0..1.0);
        scored.push((score, i));
    }
    scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));

    let mut chosen: Vec<usize> = Vec::new();
    let mut blocked = vec![false; layout.len()];
    let mut try_take = |i: usize, chosen: &mut Vec<usize>| {
        if chosen.contains(&i)
            || chosen
                .iter()
                .any(|&j| layout.cell(j).chebyshev(layout.cell(i)) < 2)
        {
            return false;
        }
        // The rest of the arena must stay reachable from start 0 around the victims.
        blocked[i] = true;
        let reached = layout
            .reach(start0, true, &blocked)
            .iter()
            .filter(|&&r| r)
            .count();
        if reached + chosen.len() + 1 == reach_count {
            chosen.push(i);
            true
        } else {
            blocked[i] = false;
            false
        }
    };
    if config.needs_climb_only_victim && wanted > 0 {
        for &(_, i) in &scored {
            if !walk[i] && try_take(i, &mut chosen) {
                break;
            }
        }
    }
    for &(_, i) in &scored {
        if chosen.len() >= wanted as usize {
            break;
        }
        try_take(i, &mut chosen);
    }
    chosen
        .iter()
        .map(|&i| PlacedVictim {
            cell: layout.cell(i),
            climb_only: !walk[i],
        })
        .collect()
}

/// A heading (multiple of 90°) facing an open neighbour, else a passable one, else any.
fn heading(rng: &mut Pcg64Mcg, layout: &Layout, c: Cell) -> f64 {
    const DIRECTIONS: [(f64, i32, i32); 4] = [
        (0.0, 1, 0),
        (FRAC_PI_2, 0, 1),
        (PI, -1, 0),
        (-FRAC_PI_2, 0, -1),
    ];
    let facing = |ok: &dyn Fn(CellClass) -> bool| -> Vec<f64> {
        DIRECTIONS
            .iter()
            .filter(|&&(_, dc, dr)| ok(layout.class(Cell::new(c.col + dc, c.row + dr))))
            .map(|&(theta, _, _)| theta)
            .collect()
    };
    let mut options = facing(&|k| k == CellClass::Open);
    if options.is_empty() {
        options = facing(&|k| k.is_passable_terrain(true));
    }
    if options.is_empty() {
        options = DIRECTIONS.iter().map(|d| d.0).collect();
    }
    options[rng.random_range(0..options.len())]
}

/// Offset from a cell's centre toward its blocked sides (a victim lies against the rubble),
/// `magnitude` metres per blocked axis side.
pub(super) fn corner_offset(layout: &Layout, c: Cell, magnitude: f64) -> Point2 {
    let blocked = |dc: i32, dr: i32| !layout.is_passable(Cell::new(c.col + dc, c.row + dr), true);
    let axis = |plus: bool, minus: bool| f64::from(i32::from(plus) - i32::from(minus)) * magnitude;
    Point2::new(
        axis(blocked(1, 0), blocked(-1, 0)),
        axis(blocked(0, 1), blocked(0, -1)),
    )
}

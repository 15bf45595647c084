//! Room segmentation of an unlabelled map: splits the free space into rooms and corridors at
//! door-like narrowings and labels rooms by area, giving a scene the room layer that paper 002's
//! semantic map needs (§3.1) when the map is a real one without labels.
//!
//! 1. [`edt`]: clearance of every free cell (exact Euclidean distance transform).
//! 2. [`watershed`]: basins of the clearance, kept apart only at doorways (see there).
//! 3. Segments smaller than [`SegmentationParams::min_room_area_m2`] join the neighbour they
//!    share the longest border with.
//! 4. [`layer`]: corridor or room by elongation and connections, room labels by area
//!    ([`usar_world::RoomLabel::for_room_area`], the thresholds the generators use), doors
//!    between neighbouring segments, intersecting corridors.
//!
//! [`evaluate`] scores a segmentation against a ground truth (Bormann et al. 2016's per-room
//! recall and precision, best-match Jaccard, room-vs-corridor pixel accuracy).

mod draw;
pub mod edt;
pub mod evaluate;
mod layer;
mod watershed;

pub use self::layer::Segmentation;

use serde::{Deserialize, Serialize};
use std::cmp::Reverse;
use std::collections::BTreeMap;
use usar_world::{Grid, RoomSizeThresholds, Scene, obstacle};

/// Parameters of the segmentation, in metres so that they do not depend on the resolution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SegmentationParams {
    /// Free islands (4-connected) smaller than this are noise and stay outside every room, m².
    pub min_region_area_m2: f64,
    /// κ: a passage separates two spaces only if its half-width is at most κ times the smaller
    /// space's largest clearance.
    pub door_ratio: f64,
    /// Widest passage that still counts as a doorway, m.
    pub max_door_width_m: f64,
    /// h: both spaces' largest clearance must exceed the passage's half-width by this much, m.
    pub min_depth_m: f64,
    /// Both spaces must have at least this much floor wider than the passage, m².
    pub min_core_area_m2: f64,
    /// Segments smaller than this join a neighbour, m².
    pub min_room_area_m2: f64,
    /// A segment is a corridor when area / width² reaches this, the width being 4 × its mean
    /// clearance (exact for a long strip: its mean clearance is a quarter of its width).
    pub corridor_elongation: f64,
    /// ... and when it borders at least this many segments: corridors join spaces, while a
    /// long room (a lab, a row of desks) is mostly a dead end.
    pub corridor_min_neighbours: usize,
    /// Room labels by free floor area, as the generators label their rooms.
    pub thresholds: RoomSizeThresholds,
}

impl Default for SegmentationParams {
    fn default() -> Self {
        Self {
            min_region_area_m2: 1.0,
            door_ratio: 0.7,
            max_door_width_m: 3.0,
            min_depth_m: 0.3,
            min_core_area_m2: 0.5,
            min_room_area_m2: 2.0,
            corridor_elongation: 4.0,
            corridor_min_neighbours: 4,
            thresholds: RoomSizeThresholds::default(),
        }
    }
}

/// A segmentation parameter out of range: which, what it held, what it takes.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field}: found {found}, expected {expected}")]
pub struct ParamError {
    pub field: &'static str,
    pub found: String,
    pub expected: &'static str,
}

impl SegmentationParams {
    /// Every length and area positive and finite, κ in (0, 1], at least one neighbour.
    pub fn check(&self) -> Result<(), ParamError> {
        let positive = [
            ("min_region_area_m2", self.min_region_area_m2),
            ("max_door_width_m", self.max_door_width_m),
            ("min_depth_m", self.min_depth_m),
            ("min_core_area_m2", self.min_core_area_m2),
            ("min_room_area_m2", self.min_room_area_m2),
            ("corridor_elongation", self.corridor_elongation),
            ("thresholds.small_below_m2", self.thresholds.small_below_m2),
            (
                "thresholds.medium_below_m2",
                self.thresholds.medium_below_m2,
            ),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(ParamError {
                    field: name,
                    found: v.to_string(),
                    expected: "a positive number",
                });
            }
        }
        if !(self.door_ratio > 0.0 && self.door_ratio <= 1.0) {
            return Err(ParamError {
                field: "door_ratio",
                found: self.door_ratio.to_string(),
                expected: "a fraction in (0, 1]",
            });
        }
        if self.corridor_min_neighbours == 0 {
            return Err(ParamError {
                field: "corridor_min_neighbours",
                found: "0".into(),
                expected: "at least 1",
            });
        }
        Ok(())
    }
}

/// Segments the free cells (obstacle layer [`obstacle::NONE`]) of `scene`.
pub fn segment_scene(scene: &Scene, params: &SegmentationParams) -> Segmentation {
    let free = scene.obstacle.map(|&o| o == obstacle::NONE);
    segment_free_space(&free, params)
}

/// Segments the `true` cells of `free`.
pub fn segment_free_space(free: &Grid<bool>, params: &SegmentationParams) -> Segmentation {
    let g = *free.geometry();
    let (w, h) = (g.width as usize, g.height as usize);
    let res = g.resolution_m as f32;
    let clearance: Vec<f32> = edt::squared_edt(free.as_slice(), w, h)
        .into_iter()
        .map(|d2| d2.sqrt() * res)
        .collect();
    let cell_area = g.cell_area_m2();
    let mask = large_regions(
        free.as_slice(),
        w,
        h,
        (params.min_region_area_m2 / cell_area).ceil() as usize,
    );
    let mut labels = watershed::flood(&mask, &clearance, w, h, cell_area, params);
    absorb_small(
        &mut labels,
        w,
        (params.min_room_area_m2 / cell_area).ceil() as u32,
    );
    layer::build(g, labels, &clearance, params)
}

/// The cells of 4-connected `free` regions of at least `min_cells` cells.
fn large_regions(free: &[bool], w: usize, h: usize, min_cells: usize) -> Vec<bool> {
    let mut mask = vec![false; free.len()];
    let mut seen = vec![false; free.len()];
    let mut stack = Vec::new();
    let mut region = Vec::new();
    for seed in 0..free.len() {
        if !free[seed] || seen[seed] {
            continue;
        }
        seen[seed] = true;
        stack.push(seed);
        region.clear();
        while let Some(i) = stack.pop() {
            region.push(i);
            for j in neighbours4(i, w, h) {
                if free[j] && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        if region.len() >= min_cells {
            for &i in &region {
                mask[i] = true;
            }
        }
    }
    mask
}

/// The 4-neighbours of cell `i` inside a `w` × `h` grid.
fn neighbours4(i: usize, w: usize, h: usize) -> impl Iterator<Item = usize> {
    let (c, r) = (i % w, i / w);
    [
        (c > 0).then(|| i - 1),
        (c + 1 < w).then(|| i + 1),
        (r > 0).then(|| i - w),
        (r + 1 < h).then(|| i + w),
    ]
    .into_iter()
    .flatten()
}

/// Repeatedly merges the smallest segment under `min_cells` into the neighbour it shares the
/// most 4-adjacent cell pairs with (ties: the lower number), then renumbers 1.. in order of first
/// cell. A segment without neighbours stays.
fn absorb_small(labels: &mut [u32], w: usize, min_cells: u32) {
    let n = labels.iter().copied().max().unwrap_or(0) as usize;
    let mut size = vec![0u32; n + 1];
    for &l in labels.iter() {
        size[l as usize] += 1;
    }
    // Border lengths between segments, (low, high) → pairs.
    let mut border: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for i in 0..labels.len() {
        let a = labels[i];
        if a == 0 {
            continue;
        }
        for j in [i + 1, i + w] {
            let same_row = j != i + 1 || (i + 1) % w != 0;
            if j < labels.len() && same_row {
                let b = labels[j];
                if b != 0 && b != a {
                    *border.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                }
            }
        }
    }
    let mut into: Vec<u32> = (0..=n as u32).collect();
    loop {
        let small = (1..=n)
            .filter(|&s| into[s] == s as u32 && size[s] > 0 && size[s] < min_cells)
            .min_by_key(|&s| (size[s], s));
        let Some(s) = small else { break };
        let s = s as u32;
        let target = border
            .iter()
            .filter(|((a, b), _)| *a == s || *b == s)
            .map(|(&(a, b), &len)| (if a == s { b } else { a }, len))
            .max_by_key(|&(other, len)| (len, Reverse(other)));
        let Some((t, _)) = target else {
            // Isolated: mark as done by giving it the threshold size (it keeps its cells).
            size[s as usize] = min_cells;
            continue;
        };
        into[s as usize] = t;
        size[t as usize] += size[s as usize];
        size[s as usize] = 0;
        let moved: Vec<((u32, u32), u32)> = border
            .iter()
            .filter(|((a, b), _)| *a == s || *b == s)
            .map(|(&k, &v)| (k, v))
            .collect();
        for (k, v) in moved {
            border.remove(&k);
            let other = if k.0 == s { k.1 } else { k.0 };
            if other != t {
                *border.entry((other.min(t), other.max(t))).or_insert(0) += v;
            }
        }
    }
    let resolve = |mut l: u32| {
        while into[l as usize] != l {
            l = into[l as usize];
        }
        l
    };
    let mut number = vec![0u32; n + 1];
    let mut next = 0;
    for l in labels.iter_mut() {
        if *l == 0 {
            continue;
        }
        let r = resolve(*l) as usize;
        if number[r] == 0 {
            next += 1;
            number[r] = next;
        }
        *l = number[r];
    }
}

//! Scoring a segmentation against a ground truth, with the measures of Bormann et al. 2016
//! ("Room segmentation: survey, implementation, and analysis", ICRA), and readers for the
//! ground-truth images of their data set (`../shared/maps/segmentation/`).
//!
//! For ground-truth rooms G_i and segments S_j (sets of cells):
//!
//! ```text
//! recall    = mean_i  max_j |G_i ∩ S_j| / |G_i|
//! precision = mean_j  max_i |G_i ∩ S_j| / |S_j|
//! jaccard   = mean_i  max_j |G_i ∩ S_j| / |G_i ∪ S_j|
//! ```
//!
//! Recall falls when a room is split (or left out), precision when a segment spans rooms.

use serde::Serialize;
use std::collections::BTreeMap;
use usar_world::io::image_map::DecodedImage;
use usar_world::{RoomLabel, Scene};

/// Scores of a segmentation against ground-truth rooms.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RoomScore {
    pub truth_rooms: usize,
    pub segments: usize,
    pub recall: f64,
    pub precision: f64,
    pub jaccard: f64,
}

/// Compares two room layers of the same grid (0 = no room in either).
pub fn score_rooms(segments: &[u32], truth: &[u32]) -> RoomScore {
    assert_eq!(segments.len(), truth.len(), "layers of one grid");
    let mut seg_size: BTreeMap<u32, u64> = BTreeMap::new();
    let mut truth_size: BTreeMap<u32, u64> = BTreeMap::new();
    let mut overlap: BTreeMap<(u32, u32), u64> = BTreeMap::new();
    for (&s, &t) in segments.iter().zip(truth) {
        if s != 0 {
            *seg_size.entry(s).or_insert(0) += 1;
        }
        if t != 0 {
            *truth_size.entry(t).or_insert(0) += 1;
        }
        if s != 0 && t != 0 {
            *overlap.entry((t, s)).or_insert(0) += 1;
        }
    }
    let mut best_recall: BTreeMap<u32, f64> = truth_size.keys().map(|&t| (t, 0.0)).collect();
    let mut best_jaccard = best_recall.clone();
    let mut best_precision: BTreeMap<u32, f64> = seg_size.keys().map(|&s| (s, 0.0)).collect();
    for (&(t, s), &o) in &overlap {
        let (gt, sg, o) = (truth_size[&t] as f64, seg_size[&s] as f64, o as f64);
        let r = best_recall.get_mut(&t).expect("truth room");
        *r = r.max(o / gt);
        let j = best_jaccard.get_mut(&t).expect("truth room");
        *j = j.max(o / (gt + sg - o));
        let p = best_precision.get_mut(&s).expect("segment");
        *p = p.max(o / sg);
    }
    let mean = |m: &BTreeMap<u32, f64>| {
        if m.is_empty() {
            0.0
        } else {
            m.values().sum::<f64>() / m.len() as f64
        }
    };
    RoomScore {
        truth_rooms: truth_size.len(),
        segments: seg_size.len(),
        recall: mean(&best_recall),
        precision: mean(&best_precision),
        jaccard: mean(&best_jaccard),
    }
}

/// Room-vs-corridor agreement on the cells both sides classify.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClassScore {
    /// Cells classified by both.
    pub cells: u64,
    /// Fraction of them on which both agree.
    pub accuracy: f64,
    /// Fraction of the true corridor cells called corridor.
    pub corridor_recall: f64,
    /// Fraction of the true room cells called room.
    pub room_recall: f64,
}

/// Compares per-cell classes (`Some(true)` corridor, `Some(false)` room, `None` unclassified).
pub fn score_classes(predicted: &[Option<bool>], truth: &[Option<bool>]) -> ClassScore {
    assert_eq!(predicted.len(), truth.len(), "layers of one grid");
    // [truth][predicted] counts, false = room, true = corridor.
    let mut m = [[0u64; 2]; 2];
    for (p, t) in predicted.iter().zip(truth) {
        if let (Some(p), Some(t)) = (p, t) {
            m[usize::from(*t)][usize::from(*p)] += 1;
        }
    }
    let cells = m.iter().flatten().sum::<u64>();
    let frac = |a: u64, b: u64| if b == 0 { 0.0 } else { a as f64 / b as f64 };
    ClassScore {
        cells,
        accuracy: frac(m[0][0] + m[1][1], cells),
        corridor_recall: frac(m[1][1], m[1][0] + m[1][1]),
        room_recall: frac(m[0][0], m[0][0] + m[0][1]),
    }
}

/// Mean of the colour channels of every pixel, rows flipped to the scene's order (row 0 south).
fn grey_rows_flipped(image: &DecodedImage) -> Vec<u32> {
    let (w, h) = (image.width as usize, image.height as usize);
    let n = image.colour_channels as usize;
    let spp = n + usize::from(image.has_alpha);
    let scale = 255.0 / image.maxval as f64;
    let mut out = vec![0u32; w * h];
    for (img_row, row) in image.samples.chunks_exact(w * spp).enumerate().take(h) {
        let dst = h - 1 - img_row;
        for (c, px) in row.chunks_exact(spp).enumerate() {
            let sum: u32 = px[..n].iter().map(|&v| u32::from(v)).sum();
            out[dst * w + c] = ((f64::from(sum) / n as f64) * scale).round() as u32;
        }
    }
    out
}

/// Ground-truth rooms of a Bormann et al. segmentation image: pixels brighter than 250 are room
/// floor, black lines separate the rooms; each 8-connected region of floor is one room, numbered
/// 1.. in scene order (row 0 south). Rows are flipped like the map loaders flip them.
pub fn truth_rooms_from_image(image: &DecodedImage) -> Vec<u32> {
    let (w, h) = (image.width as usize, image.height as usize);
    let floor: Vec<bool> = grey_rows_flipped(image)
        .into_iter()
        .map(|v| v > 250)
        .collect();
    let mut label = vec![0u32; w * h];
    let mut next = 0u32;
    let mut stack = Vec::new();
    for seed in 0..floor.len() {
        if !floor[seed] || label[seed] != 0 {
            continue;
        }
        next += 1;
        label[seed] = next;
        stack.push(seed);
        while let Some(i) = stack.pop() {
            let (c, r) = ((i % w) as i64, (i / w) as i64);
            for (dc, dr) in usar_world::NEIGHBORS8 {
                let (nc, nr) = (c + i64::from(dc), r + i64::from(dr));
                if nc < 0 || nr < 0 || nc >= w as i64 || nr >= h as i64 {
                    continue;
                }
                let j = nr as usize * w + nc as usize;
                if floor[j] && label[j] == 0 {
                    label[j] = next;
                    stack.push(j);
                }
            }
        }
    }
    label
}

/// Ground-truth classes of a Bormann et al. training image: 115 hallway → corridor, 77 room →
/// room, anything else (0 obstacle, 179 doorway) unclassified. Rows flipped to scene order.
pub fn truth_classes_from_image(image: &DecodedImage) -> Vec<Option<bool>> {
    grey_rows_flipped(image)
        .into_iter()
        .map(|v| match v {
            115 => Some(true),
            77 => Some(false),
            _ => None,
        })
        .collect()
}

/// A scene's own room layer as ground truth: the room of every free cell and whether it is a
/// corridor (0 / `None` on obstacles and outside rooms).
pub fn scene_truth(scene: &Scene) -> (Vec<u32>, Vec<Option<bool>>) {
    scene
        .room_id
        .as_slice()
        .iter()
        .zip(scene.obstacle.as_slice())
        .map(|(&id, &o)| {
            if o != usar_world::obstacle::NONE || id == 0 {
                return (0, None);
            }
            let corridor = scene.room(id).map(|r| r.label == RoomLabel::Corridor);
            (u32::from(id), corridor)
        })
        .unzip()
}

/// Why a ground-truth image could not be used.
#[derive(Debug, thiserror::Error)]
pub enum TruthImageError {
    /// The file could not be read or decoded.
    #[error(transparent)]
    Read(#[from] usar_world::WorldError),
    /// The image is not the map's size.
    #[error("{path}: {found_width}×{found_height} pixels, expected the map's {width}×{height}")]
    Size {
        path: String,
        found_width: u32,
        found_height: u32,
        width: u32,
        height: u32,
    },
}

/// Reads a ground-truth image ([`truth_rooms_from_image`], [`truth_classes_from_image`]) and
/// checks that it has one pixel per cell of `scene`'s grid.
pub fn truth_image(path: &std::path::Path, scene: &Scene) -> Result<DecodedImage, TruthImageError> {
    let bytes = usar_world::limits::read_file(path)?;
    let image = usar_world::io::image_map::decode_image(&bytes, path)?;
    let g = scene.geometry();
    if (image.width, image.height) != (g.width, g.height) {
        return Err(TruthImageError::Size {
            path: path.display().to_string(),
            found_width: image.width,
            found_height: image.height,
            width: g.width,
            height: g.height,
        });
    }
    Ok(image)
}

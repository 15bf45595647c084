//! From segment numbers to a scene's room layer: corridor or room, labels by area, doors and
//! intersecting corridors.

use super::SegmentationParams;
use serde::Serialize;
use std::collections::BTreeMap;
use usar_world::{Door, Grid, GridGeometry, Point2, Room, RoomId, RoomLabel, Scene};

/// One segment of the free space.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Segment {
    /// Room id in the layer (1..).
    pub id: RoomId,
    pub label: RoomLabel,
    /// Free floor area, m².
    pub area_m2: f64,
    /// Mean clearance (distance to the nearest obstacle) over its cells, m.
    pub mean_clearance_m: f64,
    /// area / (4 × mean clearance)²: ≈ length / width for a strip, ≈ 2.25 for a square.
    pub elongation: f64,
    /// Segments it borders.
    pub neighbours: usize,
    /// Centroid of its cells.
    pub centroid: Point2,
}

/// A segmentation: the room layer (0 outside every segment), the segments, the doors between
/// neighbouring segments (not both corridors) and the pairs of corridors that meet.
#[derive(Clone, Debug, PartialEq)]
pub struct Segmentation {
    pub room_id: Grid<RoomId>,
    pub segments: Vec<Segment>,
    pub doors: Vec<Door>,
    pub corridor_links: Vec<[RoomId; 2]>,
}

/// Border between two segments: 4-adjacent cell pairs, sum of their midpoints, largest
/// clearance on it.
#[derive(Default)]
struct Border {
    pairs: u32,
    sum_x: f64,
    sum_y: f64,
    max_clearance_m: f32,
}

pub(super) fn build(
    g: GridGeometry,
    labels: Vec<u32>,
    clearance: &[f32],
    p: &SegmentationParams,
) -> Segmentation {
    let w = g.width as usize;
    let n = labels.iter().copied().max().unwrap_or(0) as usize;
    assert!(n < usize::from(RoomId::MAX), "at most 65 534 segments");
    let mut cells = vec![0u64; n];
    let mut sum_d = vec![0f64; n];
    let mut sum_x = vec![0f64; n];
    let mut sum_y = vec![0f64; n];
    let mut borders: BTreeMap<(u32, u32), Border> = BTreeMap::new();
    for (i, &l) in labels.iter().enumerate() {
        if l == 0 {
            continue;
        }
        let k = l as usize - 1;
        let c = g.cell_center(g.cell_of_index(i));
        cells[k] += 1;
        sum_d[k] += f64::from(clearance[i]);
        sum_x[k] += c.x;
        sum_y[k] += c.y;
        for j in [i + 1, i + w] {
            if j >= labels.len() || (j == i + 1 && j % w == 0) {
                continue;
            }
            let m = labels[j];
            if m == 0 || m == l {
                continue;
            }
            let cj = g.cell_center(g.cell_of_index(j));
            let b = borders.entry((l.min(m), l.max(m))).or_default();
            b.pairs += 1;
            b.sum_x += (c.x + cj.x) / 2.0;
            b.sum_y += (c.y + cj.y) / 2.0;
            b.max_clearance_m = b.max_clearance_m.max(clearance[i]).max(clearance[j]);
        }
    }
    let mut neighbours = vec![0usize; n];
    for &(a, b) in borders.keys() {
        neighbours[a as usize - 1] += 1;
        neighbours[b as usize - 1] += 1;
    }
    let cell_area = g.cell_area_m2();
    let segments: Vec<Segment> = (0..n)
        .map(|k| {
            let count = cells[k].max(1) as f64;
            let area_m2 = cells[k] as f64 * cell_area;
            let mean_clearance_m = sum_d[k] / count;
            let width = 4.0 * mean_clearance_m;
            let elongation = area_m2 / (width * width).max(f64::MIN_POSITIVE);
            let label = if elongation >= p.corridor_elongation
                && neighbours[k] >= p.corridor_min_neighbours
            {
                RoomLabel::Corridor
            } else {
                RoomLabel::for_room_area(area_m2, p.thresholds)
            };
            Segment {
                id: (k + 1) as RoomId,
                label,
                area_m2,
                mean_clearance_m,
                elongation,
                neighbours: neighbours[k],
                centroid: Point2::new(sum_x[k] / count, sum_y[k] / count),
            }
        })
        .collect();
    let mut doors = Vec::new();
    let mut corridor_links = Vec::new();
    for (&(a, b), border) in &borders {
        let ids = [a as RoomId, b as RoomId];
        let corridor = |l: u32| segments[l as usize - 1].label == RoomLabel::Corridor;
        if corridor(a) && corridor(b) {
            corridor_links.push(ids);
            continue;
        }
        let pairs = f64::from(border.pairs);
        doors.push(Door {
            id: doors.len() as u32,
            position: Point2::new(border.sum_x / pairs, border.sum_y / pairs),
            width_m: 2.0 * f64::from(border.max_clearance_m),
            rooms: ids,
        });
    }
    let room_id = Grid::from_vec(g, labels.into_iter().map(|l| l as RoomId).collect())
        .expect("one label per cell");
    Segmentation {
        room_id,
        segments,
        doors,
        corridor_links,
    }
}

impl Segmentation {
    /// The segment of every cell as scored by [`super::evaluate::score_rooms`] (0: none).
    pub fn labels(&self) -> Vec<u32> {
        self.room_id
            .as_slice()
            .iter()
            .map(|&l| u32::from(l))
            .collect()
    }

    /// Whether every cell's segment is a corridor (`None` outside the segments), as scored by
    /// [`super::evaluate::score_classes`].
    pub fn corridor_classes(&self) -> Vec<Option<bool>> {
        self.room_id
            .as_slice()
            .iter()
            .map(|&l| {
                (l != 0).then(|| self.segments[usize::from(l) - 1].label == RoomLabel::Corridor)
            })
            .collect()
    }

    /// Replaces the scene's room layer, rooms and doors with this segmentation (which must have
    /// been computed on the scene's grid).
    pub fn apply_to(&self, scene: &mut Scene) {
        assert_eq!(
            scene.geometry(),
            self.room_id.geometry(),
            "segmentation of another grid"
        );
        scene.room_id = self.room_id.clone();
        scene.doors = self.doors.clone();
        scene.rooms = self
            .segments
            .iter()
            .map(|s| Room {
                id: s.id,
                label: s.label,
                door_ids: self
                    .doors
                    .iter()
                    .filter(|d| d.rooms.contains(&s.id))
                    .map(|d| d.id)
                    .collect(),
                intersecting_corridors: self
                    .corridor_links
                    .iter()
                    .filter(|l| l.contains(&s.id))
                    .map(|l| if l[0] == s.id { l[1] } else { l[0] })
                    .collect(),
            })
            .collect();
    }

    /// Free area per label, m² (corridor, small, medium, big).
    pub fn area_by_label(&self) -> [(RoomLabel, f64); 4] {
        RoomLabel::ALL.map(|l| {
            (
                l,
                self.segments
                    .iter()
                    .filter(|s| s.label == l)
                    .map(|s| s.area_m2)
                    .fold(0.0, |a, b| a + b),
            )
        })
    }
}

//! The team's semantic map (paper 002 §3.1, §4.4): the scene's room layer seen at the team map's
//! resolution, how much of each room the merged map knows, and the labels as the robots'
//! semantic mapping module perceives them — perfectly, or with one of the two error models of
//! §4.4.
//!
//! Two sources of the room layer, named where a mission is set up:
//! - the **semantic oracle** ([`SemanticMap::new`]): the scene's room layer (generated floors
//!   carry it; for real maps it is filled by a room segmentation before the mission starts), as
//!   paper 002 assumes its robots know it. A map cell takes the room of the scene cell at its
//!   centre.
//! - **segmented** ([`SemanticMap::segmented`], [`SemanticMap::resegment`]): the robots' own
//!   estimate, a room segmentation of the team's merged map as it grows — its known free cells
//!   split at doorways ([`usar_map::segmentation`]), labels by the known area, doors from the
//!   segmentation, visibility as the free share of the known cells in the room's bounding box,
//!   and the known fraction of a room as the share of its border that is not a frontier.

use crate::criteria::Hypothesis;
use rand::Rng;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use usar_map::segmentation::{Segmentation, SegmentationParams, segment_free_space};
use usar_map::{CellClass, OccupancyGrid};
use usar_world::{Grid, GridGeometry, RoomId, RoomLabel, Scene};

/// How the semantic mapping module labels a candidate location's room (paper 002 §4.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LabelErrors {
    /// Every label is the true one (the paper's main experiments).
    #[default]
    Perfect,
    /// Each classification is wrong with probability `rate` (paper: 0.1, 0.2, after Stachniss
    /// et al. 2008): the label is then drawn uniformly among the *other* labels.
    Random { rate: f64 },
    /// While less than `threshold` of a room is known (paper: 0.2, 0.4), its label is drawn
    /// uniformly over all labels; afterwards it is the true one.
    UntilKnown { threshold: f64 },
}

/// Why a semantic error model was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LabelErrorsError {
    #[error("label errors: found {0:?}, expected perfect, random:RATE or until-known:FRACTION")]
    Form(String),
    #[error("{name}: found {found}, expected a fraction in [0, 1]")]
    Fraction { name: &'static str, found: f64 },
}

impl LabelErrors {
    /// Reads `perfect`, `random:RATE` or `until-known:FRACTION`.
    pub fn parse(text: &str) -> Result<Self, LabelErrorsError> {
        let bad = || LabelErrorsError::Form(text.to_string());
        let errors = match text.split_once(':') {
            None if text == "perfect" => LabelErrors::Perfect,
            Some((kind, v)) => {
                let v: f64 = v.trim().parse().map_err(|_| bad())?;
                match kind {
                    "random" => LabelErrors::Random { rate: v },
                    "until-known" => LabelErrors::UntilKnown { threshold: v },
                    _ => return Err(bad()),
                }
            }
            None => return Err(bad()),
        };
        errors.check()?;
        Ok(errors)
    }

    pub fn check(&self) -> Result<(), LabelErrorsError> {
        let (name, v) = match *self {
            LabelErrors::Perfect => return Ok(()),
            LabelErrors::Random { rate } => ("label error rate", rate),
            LabelErrors::UntilKnown { threshold } => ("label threshold", threshold),
        };
        if (0.0..=1.0).contains(&v) {
            Ok(())
        } else {
            Err(LabelErrorsError::Fraction { name, found: v })
        }
    }
}

/// What the ideal team size i(p) and ND(p) need to know about a room (§3.3).
#[derive(Clone, Debug, PartialEq)]
pub struct RoomFacts {
    pub id: RoomId,
    pub label: RoomLabel,
    /// Floor area (free and furnished), m².
    pub area_m2: f64,
    /// Free fraction of the room's floor (the paper's "visibility").
    pub visibility: f64,
    pub doors: usize,
    pub intersecting_corridors: usize,
}

/// The scene's rooms at the team map's resolution, with what the merged map knows of them.
#[derive(Clone, Debug)]
pub struct SemanticMap {
    /// Per map cell: index into `rooms` + 1, 0 outside every room.
    slot: Vec<u16>,
    /// Per map cell: whether the scene cell at its centre is free (not wall or furniture).
    free: Vec<bool>,
    rooms: Vec<RoomFacts>,
    /// Per room: map cells, and how many of them the merged map knows.
    room_cells: Vec<u32>,
    room_known: Vec<u32>,
    /// Per map cell: counted as known.
    counted: Vec<bool>,
    /// Per room: whether its (free) cells count as relevant area.
    relevant_room: Vec<bool>,
    relevant_cells: u64,
    relevant_known: u64,
    cell_area_m2: f64,
    errors: LabelErrors,
    rng: Pcg64Mcg,
    /// Segmented maps: each room's known fraction as estimated from its border.
    estimated_known: Option<Vec<f64>>,
}

impl SemanticMap {
    /// The semantic map of `scene` on the map `geometry`, relevance from `hypothesis`, labels
    /// perceived with `errors` drawn from `rng`.
    pub fn new(
        scene: &Scene,
        geometry: &GridGeometry,
        hypothesis: &Hypothesis,
        errors: LabelErrors,
        rng: Pcg64Mcg,
    ) -> Self {
        let sg = scene.geometry();
        let mut ids: Vec<RoomId> = scene.rooms.iter().map(|r| r.id).collect();
        ids.sort_unstable();
        let slot_of_id = |id: RoomId| ids.binary_search(&id).ok().map(|k| k as u16 + 1);
        let n = geometry.len();
        let mut slot = vec![0u16; n];
        let mut free = vec![false; n];
        let mut room_cells = vec![0u32; ids.len()];
        let mut room_free = vec![0u32; ids.len()];
        for (i, (s, f)) in slot.iter_mut().zip(free.iter_mut()).enumerate() {
            let centre = geometry.cell_center(geometry.cell_of_index(i));
            let sc = sg.world_to_cell(centre);
            if !sg.contains(sc) {
                continue;
            }
            *f = !scene.is_obstacle(sc);
            if let Some(k) = slot_of_id(scene.room_id[sc]) {
                *s = k;
                room_cells[usize::from(k) - 1] += 1;
                if *f {
                    room_free[usize::from(k) - 1] += 1;
                }
            }
        }
        let cell_area_m2 = geometry.cell_area_m2();
        let rooms: Vec<RoomFacts> = ids
            .iter()
            .enumerate()
            .map(|(k, &id)| {
                let room = scene.room(id).expect("id from the scene's rooms");
                RoomFacts {
                    id,
                    label: room.label,
                    area_m2: f64::from(room_cells[k]) * cell_area_m2,
                    visibility: f64::from(room_free[k]) / f64::from(room_cells[k].max(1)),
                    doors: room.door_ids.len(),
                    intersecting_corridors: room.intersecting_corridors.len(),
                }
            })
            .collect();
        let relevant_room: Vec<bool> = rooms
            .iter()
            .map(|r| hypothesis.is_relevant(Some(r.label)))
            .collect();
        let relevant_cells = slot
            .iter()
            .zip(&free)
            .filter(|&(&s, &f)| f && s != 0 && relevant_room[usize::from(s) - 1])
            .count() as u64;
        Self {
            slot,
            free,
            room_known: vec![0; rooms.len()],
            room_cells,
            rooms,
            counted: vec![false; n],
            relevant_room,
            relevant_cells,
            relevant_known: 0,
            cell_area_m2,
            errors,
            rng,
            estimated_known: None,
        }
    }

    /// A segmented semantic map on `geometry` that knows no room yet (see
    /// [`SemanticMap::resegment`]).
    pub fn segmented(
        geometry: &GridGeometry,
        hypothesis: &Hypothesis,
        errors: LabelErrors,
        rng: Pcg64Mcg,
    ) -> Self {
        let mut map = Self::new(
            &Scene::empty("segmented", *geometry),
            geometry,
            hypothesis,
            errors,
            rng,
        );
        map.estimated_known = Some(Vec::new());
        map
    }

    /// Replaces the room layer with a segmentation of `merged`'s known free cells (the map
    /// must have this map's geometry); the label errors and their random stream carry on.
    pub fn resegment(
        &mut self,
        merged: &OccupancyGrid,
        hypothesis: &Hypothesis,
        params: &SegmentationParams,
    ) {
        let g = *merged.geometry();
        let free = Grid::from_vec(
            g,
            (0..g.len())
                .map(|i| merged.class_at_index(i) == CellClass::Free)
                .collect(),
        )
        .expect("one value per cell");
        let seg = segment_free_space(&free, params);
        let mut layer = Scene::empty("segmented", g);
        seg.apply_to(&mut layer);
        let (visibility, known) = estimate_rooms(&seg, merged);
        let rng = self.rng.clone();
        let mut next = Self::new(&layer, &g, hypothesis, self.errors, rng);
        for (room, v) in next.rooms.iter_mut().zip(visibility) {
            room.visibility = v;
        }
        next.estimated_known = Some(known);
        let all: Vec<u32> = (0..g.len() as u32).collect();
        next.update_from(merged, &all);
        *self = next;
    }

    /// Applies the merged map's class changes.
    pub fn update_from(&mut self, grid: &OccupancyGrid, changed: &[u32]) {
        for &i in changed {
            let i = i as usize;
            let known = grid.class_at_index(i) != CellClass::Unknown;
            if known == self.counted[i] {
                continue;
            }
            self.counted[i] = known;
            let s = usize::from(self.slot[i]);
            if s == 0 {
                continue;
            }
            let k = s - 1;
            if known {
                self.room_known[k] += 1;
            } else {
                self.room_known[k] -= 1;
            }
            if self.free[i] && self.relevant_room[k] {
                if known {
                    self.relevant_known += 1;
                } else {
                    self.relevant_known -= 1;
                }
            }
        }
    }

    /// The room (index into [`SemanticMap::rooms`]) of map cell `index`, if any.
    pub fn room_of(&self, index: usize) -> Option<usize> {
        self.slot
            .get(index)
            .and_then(|&s| (s != 0).then(|| usize::from(s) - 1))
    }

    /// The room of map cell `cell` (on this map's `geometry`), or of the nearest cell within
    /// two cells that has one (a candidate may stand in a doorway's wall gap).
    pub fn room_near(&self, geometry: &GridGeometry, cell: usar_world::Cell) -> Option<usize> {
        (0..=2).find_map(|r: i32| {
            (-r..=r)
                .flat_map(|dr| (-r..=r).map(move |dc| (dc, dr)))
                .filter(|&(dc, dr)| dc.abs().max(dr.abs()) == r)
                .find_map(|(dc, dr)| {
                    let i = geometry
                        .checked_index(usar_world::Cell::new(cell.col + dc, cell.row + dr))?;
                    self.room_of(i)
                })
        })
    }

    pub fn rooms(&self) -> &[RoomFacts] {
        &self.rooms
    }

    /// Known fraction of room `k`, in [0, 1].
    pub fn perceived_fraction(&self, k: usize) -> f64 {
        match &self.estimated_known {
            Some(known) => known[k],
            None => f64::from(self.room_known[k]) / f64::from(self.room_cells[k].max(1)),
        }
    }

    /// The label of room `k` as the semantic mapping module reports it now (one classification:
    /// with an error model, each call may draw).
    pub fn perceived_label(&mut self, k: usize) -> RoomLabel {
        let truth = self.rooms[k].label;
        match self.errors {
            LabelErrors::Perfect => truth,
            LabelErrors::Random { rate } => {
                if self.rng.random::<f64>() < rate {
                    let others: Vec<RoomLabel> =
                        RoomLabel::ALL.into_iter().filter(|&l| l != truth).collect();
                    others[self.rng.random_range(0..others.len())]
                } else {
                    truth
                }
            }
            LabelErrors::UntilKnown { threshold } => {
                if self.perceived_fraction(k) < threshold {
                    RoomLabel::ALL[self.rng.random_range(0..RoomLabel::ALL.len())]
                } else {
                    truth
                }
            }
        }
    }

    /// Explored relevant area: known map cells on the free floor of relevant rooms, m².
    pub fn relevant_area_m2(&self) -> f64 {
        self.relevant_known as f64 * self.cell_area_m2
    }

    /// The free floor of the relevant rooms, m².
    pub fn relevant_total_m2(&self) -> f64 {
        self.relevant_cells as f64 * self.cell_area_m2
    }

    /// Explored fraction of the relevant area (1 when nothing is relevant).
    pub fn relevant_fraction(&self) -> f64 {
        if self.relevant_cells == 0 {
            1.0
        } else {
            self.relevant_known as f64 / self.relevant_cells as f64
        }
    }
}

/// Per segment of `merged`: visibility (free share of the known cells in its bounding box) and
/// known fraction (share of its border cells with no unknown 4-neighbour).
fn estimate_rooms(seg: &Segmentation, merged: &OccupancyGrid) -> (Vec<f64>, Vec<f64>) {
    let g = *merged.geometry();
    let n = seg.segments.len();
    let mut bbox = vec![(i32::MAX, i32::MAX, i32::MIN, i32::MIN); n];
    let mut border = vec![0u32; n];
    let mut open = vec![0u32; n];
    for i in 0..g.len() {
        let id = seg.room_id.as_slice()[i];
        if id == 0 {
            continue;
        }
        let k = usize::from(id) - 1;
        let c = g.cell_of_index(i);
        let b = &mut bbox[k];
        *b = (
            b.0.min(c.col),
            b.1.min(c.row),
            b.2.max(c.col),
            b.3.max(c.row),
        );
        let mut on_border = false;
        let mut unknown = false;
        for (dc, dr) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let m = usar_world::Cell::new(c.col + dc, c.row + dr);
            if seg.room_id.get(m).is_none_or(|&other| other != id) {
                on_border = true;
                unknown |= !g.contains(m) || merged.class(m) == CellClass::Unknown;
            }
        }
        if on_border {
            border[k] += 1;
            open[k] += u32::from(unknown);
        }
    }
    let visibility = bbox
        .iter()
        .map(|&(c0, r0, c1, r1)| {
            let (mut free, mut occupied) = (0u32, 0u32);
            for row in r0..=r1 {
                for col in c0..=c1 {
                    match merged.class(usar_world::Cell::new(col, row)) {
                        CellClass::Free => free += 1,
                        CellClass::Occupied => occupied += 1,
                        CellClass::Unknown => {}
                    }
                }
            }
            f64::from(free) / f64::from((free + occupied).max(1))
        })
        .collect();
    let known = border
        .iter()
        .zip(&open)
        .map(|(&b, &o)| 1.0 - f64::from(o) / f64::from(b.max(1)))
        .collect();
    (visibility, known)
}

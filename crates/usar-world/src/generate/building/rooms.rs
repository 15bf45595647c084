//! Rooms and doors on the skeleton's rows, sized so that the room labels take the area shares of
//! paper 002 Tables 2–3.
//!
//! Big rooms are placed first (through rooms spanning both rows of a band, opening onto both of
//! its corridors, or long single-row halls) until their area reaches the big-room share of the
//! estimated room area. The rest of every row is then filled from west to east, each new room
//! taking the label (small or medium) that is furthest behind its share; the last one or two
//! slots of a row are chosen among all splits of what is left so that the balance comes closest
//! to its target. A row too deep for a small room gets small rooms by splitting a slot into a
//! front room and a back room reached through it. Labels come from the rooms' areas
//! ([`crate::RoomLabel::for_room_area`]), so every room is counted under the label it ends up
//! with; rooms just below a threshold are avoided (their door openings could lift them over it)
//! and the furniture never takes a room below its label's lower threshold.

use super::layout::{CellRect, CellScale, Side, Skeleton};
use super::params::BuildingParams;
use crate::scene::RoomLabel;
use rand::Rng;
use rand::seq::SliceRandom;
use rand_pcg::Pcg64Mcg;

/// How a room sits in its row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum RoomKind {
    /// Opens onto the row's corridor.
    Front,
    /// Behind a front room, reached only through it.
    Back { front_room: usize },
    /// Spans both rows of a band; opens onto the corridors on both sides.
    Through { twin_segment: usize },
}

/// A planned room: its free rectangle (walls lie outside it).
#[derive(Clone, Debug)]
pub(super) struct RoomPlan {
    pub rect: CellRect,
    pub segment: usize,
    pub kind: RoomKind,
}

/// What is on the far side of a door.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Opening {
    Room(usize),
    Corridor(usize),
}

/// A planned door: the cells of the opening through the wall. The opening belongs to `owner`,
/// always a room (never a corridor).
#[derive(Clone, Debug)]
pub(super) struct DoorPlan {
    pub rect: CellRect,
    pub owner: usize,
    pub other: Opening,
}

impl DoorPlan {
    /// The side of room `rect` the door is on, if it touches that room's rectangle.
    pub fn side_of(&self, rect: &CellRect) -> Option<Side> {
        let d = &self.rect;
        let spans_x = d.x0 >= rect.x0 && d.x1 <= rect.x1;
        let spans_y = d.y0 >= rect.y0 && d.y1 <= rect.y1;
        if spans_x && d.y0 == rect.y1 {
            Some(Side::North)
        } else if spans_x && d.y1 == rect.y0 {
            Some(Side::South)
        } else if spans_y && d.x1 == rect.x0 {
            Some(Side::West)
        } else if spans_y && d.x0 == rect.x1 {
            Some(Side::East)
        } else {
            None
        }
    }
}

/// Largest width-to-depth ratio of the rooms of a split slot (no corridor-like storerooms).
const MAX_SPLIT_ASPECT: f64 = 3.0;

/// Rooms planned less than this below a label threshold are avoided: their door openings (which
/// belong to them) could lift them into the next label. Four 1.2 m doors in a 0.2 m wall are
/// ≈ 1 m².
const AMBIGUOUS_BELOW_M2: f64 = 1.5;

/// Label indices used in the running totals.
const SMALL: usize = 0;
const MEDIUM: usize = 1;
const BIG: usize = 2;

struct Allocator<'a> {
    sk: &'a Skeleton,
    p: &'a BuildingParams,
    scale: &'a CellScale,
    /// Free x interval `[x0, x1)` of every segment.
    free: Vec<(i32, i32)>,
    rooms: Vec<RoomPlan>,
    /// Allocated area per label (small, medium, big), cells.
    area: [f64; 3],
    /// Target fraction of the room area per label.
    target: [f64; 3],
    min_side: i32,
}

/// Plans the rooms of every segment. `estimated_room_cells` is the expected total room area.
pub(super) fn plan_rooms(
    sk: &Skeleton,
    p: &BuildingParams,
    scale: &CellScale,
    estimated_room_cells: f64,
    rng: &mut Pcg64Mcg,
) -> Vec<RoomPlan> {
    let mut a = Allocator {
        sk,
        p,
        scale,
        free: sk.segments.iter().map(|s| (s.rect.x0, s.rect.x1)).collect(),
        rooms: Vec::new(),
        area: [0.0; 3],
        target: p.label_shares.room_fractions(),
        min_side: scale.cells(p.min_room_side_m),
    };
    a.place_big_rooms(estimated_room_cells, rng);
    let mut order: Vec<usize> = (0..sk.segments.len()).collect();
    order.shuffle(rng);
    for s in order {
        a.fill_segment(s, rng);
    }
    a.rooms.sort_by_key(|r| (r.segment, r.rect.x0, r.rect.y0));
    // Back rooms refer to their front room by index: re-link after sorting.
    let fronts: Vec<CellRect> = a.rooms.iter().map(|r| r.rect).collect();
    let mut rooms = a.rooms;
    for room in rooms.iter_mut() {
        if let RoomKind::Back { .. } = room.kind {
            let seg = &sk.segments[room.segment].rect;
            let r = room.rect;
            if let Some(f) = fronts.iter().position(|f| {
                f.x0 == r.x0 && f.x1 == r.x1 && f.y0 >= seg.y0 && f.y1 <= seg.y1 && *f != r
            }) {
                room.kind = RoomKind::Back { front_room: f };
            }
        }
    }
    rooms
}

impl Allocator<'_> {
    fn cells(&self, m2: f64) -> f64 {
        m2 / self.scale.cell_area_m2()
    }

    fn label_of(&self, cells: i64) -> usize {
        match RoomLabel::for_room_area(cells as f64 * self.scale.cell_area_m2(), self.p.thresholds)
        {
            RoomLabel::SmallRoom => SMALL,
            RoomLabel::MediumRoom => MEDIUM,
            _ => BIG,
        }
    }

    fn push(&mut self, rect: CellRect, segment: usize, kind: RoomKind) -> usize {
        let label = self.label_of(rect.area());
        self.area[label] += rect.area() as f64;
        self.rooms.push(RoomPlan {
            rect,
            segment,
            kind,
        });
        self.rooms.len() - 1
    }

    /// Shortest leftover worth a room of its own (a room plus the wall before it).
    fn min_rest(&self) -> i32 {
        self.min_side + self.sk.wall
    }

    /// Width `w` adjusted so that what is left of `len` is either nothing or a whole room.
    fn fit(&self, w: i32, len: i32) -> i32 {
        let rest = len - w;
        if rest <= 0 || rest < self.min_rest() {
            len
        } else {
            w
        }
    }

    /// Width of a big room of about `w` (at least `lo`) adjusted so that what is left of `len`
    /// is nothing or at least `rest_min`: a sliver that could only become a small room would
    /// push the small-room share up, so the big room either takes it or leaves a medium room.
    fn fit_big(&self, w: i32, len: i32, lo: i32, rest_min: i32) -> i32 {
        let rest = len - w;
        if rest <= 0 {
            return len;
        }
        if rest >= rest_min {
            return w;
        }
        let shrunk = len - rest_min;
        if shrunk >= lo && w - shrunk < len - w {
            shrunk
        } else {
            len
        }
    }

    /// The shortest rest of a row of depth `depth` that can hold a medium room (with its wall).
    fn medium_rest(&self, depth: i32) -> i32 {
        self.width_range(MEDIUM, depth)
            .map_or(self.min_rest(), |r| r.0 + self.sk.wall)
    }

    fn place_big_rooms(&mut self, estimated_room_cells: f64, rng: &mut Pcg64Mcg) {
        let big = self.p.big_room_m2;
        let target = self.target[BIG] * estimated_room_cells;
        for _ in 0..1000 {
            // Stop when one more (smallest) big room would overshoot more than it fills.
            let deficit = target - self.area[BIG];
            if deficit <= self.cells(big.min_m2) / 2.0 {
                break;
            }
            let want = if deficit < self.cells(big.max_m2) {
                deficit.clamp(self.cells(big.min_m2), self.cells(big.max_m2))
            } else {
                rng.random_range(self.cells(big.min_m2)..=self.cells(big.max_m2))
            };
            let options = self.big_options(want);
            if options.is_empty() {
                break;
            }
            let through: Vec<&BigOption> = options.iter().filter(|o| o.twin.is_some()).collect();
            let pick = if !through.is_empty() && rng.random_bool(0.6) {
                *through[rng.random_range(0..through.len())]
            } else {
                options[rng.random_range(0..options.len())]
            };
            self.place_big(pick);
        }
    }

    /// Every way to place a big room of about `want` cells at an end of a free interval.
    fn big_options(&self, want: f64) -> Vec<BigOption> {
        let tw = self.sk.wall;
        let mut out = Vec::new();
        for (s, seg) in self.sk.segments.iter().enumerate() {
            let (x0, x1) = self.free[s];
            let len = x1 - x0;
            let depth = seg.rect.height();
            let big_min = self.cells(self.p.big_room_m2.min_m2);
            // Single-row hall.
            let w = ((want / f64::from(depth)).ceil() as i32).max(self.min_side);
            if w <= len {
                let lo = (big_min / f64::from(depth)).ceil() as i32;
                let w = self.fit_big(w, len, lo, self.medium_rest(depth));
                out.push(BigOption {
                    segment: s,
                    twin: None,
                    west: true,
                    width: w,
                });
                if w < len {
                    out.push(BigOption {
                        segment: s,
                        twin: None,
                        west: false,
                        width: w,
                    });
                }
            }
            // Through room with the twin (listed once, from the southern row).
            if let Some(t) = seg.twin
                && t > s
                && self.free[t] == self.free[s]
            {
                let twin_depth = self.sk.segments[t].rect.height();
                let d = depth + tw + twin_depth;
                let w = ((want / f64::from(d)).ceil() as i32).max(self.min_side);
                if w <= len {
                    let lo = (big_min / f64::from(d)).ceil() as i32;
                    let rest_min = self.medium_rest(depth).max(self.medium_rest(twin_depth));
                    let w = self.fit_big(w, len, lo, rest_min);
                    out.push(BigOption {
                        segment: s,
                        twin: Some(t),
                        west: true,
                        width: w,
                    });
                    if w < len {
                        out.push(BigOption {
                            segment: s,
                            twin: Some(t),
                            west: false,
                            width: w,
                        });
                    }
                }
            }
        }
        out
    }

    fn place_big(&mut self, o: BigOption) {
        let tw = self.sk.wall;
        let seg = self.sk.segments[o.segment].rect;
        let (x0, x1) = self.free[o.segment];
        let (rx0, rx1) = if o.west {
            (x0, x0 + o.width)
        } else {
            (x1 - o.width, x1)
        };
        let shrink = |free: &mut (i32, i32)| {
            if o.width >= free.1 - free.0 {
                *free = (free.1, free.1);
            } else if o.west {
                free.0 = rx1 + tw;
            } else {
                free.1 = rx0 - tw;
            }
        };
        match o.twin {
            None => {
                shrink(&mut self.free[o.segment]);
                self.push(
                    CellRect::new(rx0, seg.y0, rx1, seg.y1),
                    o.segment,
                    RoomKind::Front,
                );
            }
            Some(t) => {
                let other = self.sk.segments[t].rect;
                shrink(&mut self.free[o.segment]);
                shrink(&mut self.free[t]);
                let (y0, y1) = (seg.y0.min(other.y0), seg.y1.max(other.y1));
                self.push(
                    CellRect::new(rx0, y0, rx1, y1),
                    o.segment,
                    RoomKind::Through { twin_segment: t },
                );
            }
        }
    }

    /// The label (small or medium) furthest behind its share of the room area.
    fn next_label(&self) -> usize {
        let behind = |l: usize| {
            if self.target[l] <= 0.0 {
                f64::INFINITY
            } else {
                self.area[l] / self.target[l]
            }
        };
        if behind(SMALL) < behind(MEDIUM) {
            SMALL
        } else {
            MEDIUM
        }
    }

    /// Whole-cell width range giving an area within the label's range at depth `depth`.
    fn width_range(&self, label: usize, depth: i32) -> Option<(i32, i32)> {
        let r = match label {
            SMALL => self.p.small_room_m2,
            MEDIUM => self.p.medium_room_m2,
            _ => self.p.big_room_m2,
        };
        let lo = ((self.cells(r.min_m2) / f64::from(depth)).ceil() as i32).max(self.min_side);
        let hi = (self.cells(r.max_m2) / f64::from(depth)).floor() as i32;
        (lo <= hi).then_some((lo, hi))
    }

    fn fill_segment(&mut self, s: usize, rng: &mut Pcg64Mcg) {
        let seg = self.sk.segments[s].clone();
        let tw = self.sk.wall;
        let depth = seg.rect.height();
        let (mut x, end) = self.free[s];
        let can_split = depth >= 2 * self.min_side + tw;
        let medium_hi = self
            .width_range(MEDIUM, depth)
            .map_or(self.min_side, |r| r.1);
        let finish_span = 2 * medium_hi.max(self.min_side) + tw;
        while end - x >= self.min_side {
            let len = end - x;
            if len <= finish_span {
                self.finish(s, x, end);
                break;
            }
            let label = self.next_label();
            let single = self.width_range(label, depth);
            let split_needed = label == SMALL && single.is_none();
            let split_wanted = can_split && rng.random_bool(self.p.back_room_probability);
            let mut placed = false;
            if can_split
                && (split_needed || split_wanted)
                && let Some((w, front_depth)) = self.split_plan(label, depth, len, rng)
            {
                let w = self.fit(w, len);
                self.push_split(s, x, w, front_depth);
                x += w + tw;
                placed = true;
            }
            if !placed {
                let (lo, hi) = single
                    .or_else(|| self.width_range(MEDIUM, depth))
                    .unwrap_or((self.min_side, self.min_side.max(len)));
                let w = self.choose_width(lo, hi, len, rng);
                self.push(
                    CellRect::new(x, seg.rect.y0, x + w, seg.rect.y1),
                    s,
                    RoomKind::Front,
                );
                x += w + tw;
            }
        }
        self.free[s] = (end, end);
    }

    /// Ends a row: the rest `[x, end)` becomes one or two slots, each a whole room or split into
    /// a front and a back room, whichever brings the small/medium balance closest to its target
    /// while keeping the rooms' areas near their label's range (and not adding a big room).
    fn finish(&mut self, s: usize, x: i32, end: i32) {
        let tw = self.sk.wall;
        let depth = self.sk.segments[s].rect.height();
        let len = end - x;
        let front_depth = (depth - tw) / 2;
        let back_depth = depth - tw - front_depth;
        let splittable = |w: i32| {
            front_depth >= self.min_side
                && back_depth >= self.min_side
                && f64::from(w) <= MAX_SPLIT_ASPECT * f64::from(back_depth.min(front_depth))
        };
        let mut options: Vec<Vec<(i32, bool)>> = vec![vec![(len, false)]];
        if splittable(len) {
            options.push(vec![(len, true)]);
        }
        let span = len - tw - 2 * self.min_side;
        if span >= 0 {
            let steps = span.clamp(1, 24);
            for k in 0..=steps {
                let w1 = self.min_side + span * k / steps;
                let w2 = len - tw - w1;
                for (a, b) in [(false, false), (true, false), (false, true), (true, true)] {
                    if (!a || splittable(w1)) && (!b || splittable(w2)) {
                        options.push(vec![(w1, a), (w2, b)]);
                    }
                }
            }
        }
        let areas = |w: i32, split: bool| -> Vec<i64> {
            if split {
                vec![
                    i64::from(w) * i64::from(front_depth),
                    i64::from(w) * i64::from(back_depth),
                ]
            } else {
                vec![i64::from(w) * i64::from(depth)]
            }
        };
        let score = |slots: &[(i32, bool)]| -> f64 {
            let mut added = [0.0; 3];
            let mut penalty = 0.0;
            for &(w, split) in slots {
                for a in areas(w, split) {
                    let label = self.label_of(a);
                    added[label] += a as f64;
                    penalty += self.size_penalty(label, a);
                }
            }
            let small = self.area[SMALL] + added[SMALL];
            let medium = self.area[MEDIUM] + added[MEDIUM];
            let want = self.target[SMALL] / (self.target[SMALL] + self.target[MEDIUM]).max(1e-9);
            let have = small / (small + medium).max(1.0);
            // One office room moves the balance by ≈ 0.01; weigh that like a size penalty.
            10.0 * (have - want).abs() + penalty
        };
        let best = options
            .iter()
            .map(|o| (score(o), o))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, o)| o.clone())
            .unwrap_or_else(|| vec![(len, false)]);
        let y = self.sk.segments[s].rect;
        let mut x = x;
        for (w, split) in best {
            if split {
                self.push_split(s, x, w, front_depth);
            } else {
                self.push(CellRect::new(x, y.y0, x + w, y.y1), s, RoomKind::Front);
            }
            x += w + tw;
        }
    }

    /// How far a room of `cells` strays from its label's configured range: 0 inside
    /// [0.8 × min, 1.25 × max], 0.05 outside it, 0.3 for a big room (the big rooms are placed
    /// on purpose, not by filling a row).
    fn size_penalty(&self, label: usize, cells: i64) -> f64 {
        let r = match label {
            SMALL => self.p.small_room_m2,
            MEDIUM => self.p.medium_room_m2,
            _ => return 0.3,
        };
        let a = cells as f64;
        // Just below a threshold, the door openings could lift the room into the next label.
        let t = self.p.thresholds;
        let near_threshold = [t.small_below_m2, t.medium_below_m2]
            .iter()
            .any(|&m2| a < self.cells(m2) && a >= self.cells(m2) - self.cells(AMBIGUOUS_BELOW_M2));
        if near_threshold {
            1.0
        } else if a < 0.8 * self.cells(r.min_m2) || a > 1.25 * self.cells(r.max_m2) {
            0.05
        } else {
            0.0
        }
    }

    /// A width in `[lo, hi]` that leaves either nothing or a whole room of `len`.
    fn choose_width(&self, lo: i32, hi: i32, len: i32, rng: &mut Pcg64Mcg) -> i32 {
        if len <= hi {
            return len; // the rest of the row fits this label: take it all
        }
        if len < lo {
            return len;
        }
        let w = rng.random_range(lo..=hi);
        let rest = len - w;
        if rest >= self.min_rest() {
            return w;
        }
        // Leave room for one more room if the label allows it, else take everything.
        let shorter = len - self.min_rest();
        if shorter >= lo { shorter } else { len }
    }

    /// Width and front depth of a slot split into a front room (of `label`) and a small back
    /// room, or `None` if no width gives both their label.
    fn split_plan(
        &self,
        label: usize,
        depth: i32,
        len: i32,
        rng: &mut Pcg64Mcg,
    ) -> Option<(i32, i32)> {
        let tw = self.sk.wall;
        let usable = depth - tw;
        let mut candidates: Vec<(i32, i32, i32)> = Vec::new(); // (front depth, lo, hi)
        for step in 0..=8 {
            let front = self.min_side + (usable - 2 * self.min_side) * step / 8;
            let back = usable - front;
            if front < self.min_side || back < self.min_side {
                continue;
            }
            if let (Some(f), Some(b)) = (
                self.width_range(label, front),
                self.width_range(SMALL, back),
            ) {
                // No room of the pair longer than MAX_SPLIT_ASPECT times its depth.
                let longest = (MAX_SPLIT_ASPECT * f64::from(front.min(back))).floor() as i32;
                let (lo, hi) = (f.0.max(b.0), f.1.min(b.1).min(longest));
                if lo <= hi && lo <= len {
                    candidates.push((front, lo, hi.min(len)));
                }
            }
        }
        if candidates.is_empty() {
            return None;
        }
        let (front, lo, hi) = candidates[rng.random_range(0..candidates.len())];
        let w = rng.random_range(lo..=hi);
        let rest = len - w;
        let w = if rest > 0 && rest < self.min_rest() {
            if len - self.min_rest() >= lo {
                len - self.min_rest()
            } else {
                w
            }
        } else {
            w
        };
        Some((w, front))
    }

    fn push_split(&mut self, s: usize, x: i32, w: i32, front_depth: i32) {
        let seg = self.sk.segments[s].rect;
        let tw = self.sk.wall;
        let (front, back) = match self.sk.segments[s].front {
            Side::North => (
                CellRect::new(x, seg.y1 - front_depth, x + w, seg.y1),
                CellRect::new(x, seg.y0, x + w, seg.y1 - front_depth - tw),
            ),
            _ => (
                CellRect::new(x, seg.y0, x + w, seg.y0 + front_depth),
                CellRect::new(x, seg.y0 + front_depth + tw, x + w, seg.y1),
            ),
        };
        let f = self.push(front, s, RoomKind::Front);
        self.push(back, s, RoomKind::Back { front_room: f });
    }
}

#[derive(Clone, Copy, Debug)]
struct BigOption {
    segment: usize,
    twin: Option<usize>,
    west: bool,
    width: i32,
}

/// Plans the doors: one or more corridor doors per front and through room (one per
/// `frontage_per_door_m` of frontage), one door from every back room into its front room, and
/// the optional side doors onto cross corridors and connecting doors between neighbours.
pub(super) fn plan_doors(
    sk: &Skeleton,
    rooms: &[RoomPlan],
    p: &BuildingParams,
    scale: &CellScale,
    rng: &mut Pcg64Mcg,
) -> Vec<DoorPlan> {
    let tw = sk.wall;
    let mut doors = Vec::new();
    let margin = scale.cells(0.3);
    let door_cells = |range: super::params::LengthRange, rng: &mut Pcg64Mcg| {
        let lo = (range.min_m / scale.resolution_m).ceil() as i32;
        let hi = ((range.max_m / scale.resolution_m).floor() as i32).max(lo);
        rng.random_range(lo..=hi)
    };
    let min_door =
        (p.door_width_m.min_m.min(p.front_door_width_m.min_m) / scale.resolution_m).ceil() as i32;
    let is_small = |r: &RoomPlan| {
        RoomLabel::for_room_area(r.rect.area() as f64 * scale.cell_area_m2(), p.thresholds)
            == RoomLabel::SmallRoom
    };
    // An opening of `want` cells inside [a, b) of a wall, away from its ends when possible.
    let place = |a: i32, b: i32, want: i32, rng: &mut Pcg64Mcg| -> Option<(i32, i32)> {
        let len = b - a;
        let m = if len - 2 * margin >= min_door {
            margin
        } else {
            0
        };
        let w = want.min(len - 2 * m);
        if w < min_door.min(len) || w <= 0 {
            return None;
        }
        let start = rng.random_range(a + m..=b - m - w);
        Some((start, start + w))
    };
    for (i, room) in rooms.iter().enumerate() {
        let seg = &sk.segments[room.segment];
        let r = room.rect;
        let width_range = if is_small(room) {
            p.door_width_m
        } else {
            p.front_door_width_m
        };
        let frontage_doors = |len_cells: i32| {
            let metres = f64::from(len_cells) * scale.resolution_m;
            ((metres / p.frontage_per_door_m).floor() as i32).clamp(1, 4)
        };
        let mut corridor_doors = |side: Side, corridor: usize, rng: &mut Pcg64Mcg| {
            let n = frontage_doors(r.width());
            for k in 0..n {
                let a = r.x0 + r.width() * k / n;
                let b = r.x0 + r.width() * (k + 1) / n;
                let want = door_cells(width_range, rng);
                if let Some((d0, d1)) = place(a, b, want, rng) {
                    let rect = match side {
                        Side::North => CellRect::new(d0, r.y1, d1, r.y1 + tw),
                        _ => CellRect::new(d0, r.y0 - tw, d1, r.y0),
                    };
                    doors.push(DoorPlan {
                        rect,
                        owner: i,
                        other: Opening::Corridor(corridor),
                    });
                }
            }
        };
        match room.kind {
            RoomKind::Front => corridor_doors(seg.front, seg.front_corridor, rng),
            RoomKind::Through { twin_segment } => {
                corridor_doors(seg.front, seg.front_corridor, rng);
                let twin = &sk.segments[twin_segment];
                corridor_doors(twin.front, twin.front_corridor, rng);
            }
            RoomKind::Back { front_room } => {
                let want = door_cells(p.door_width_m, rng);
                if let Some((d0, d1)) = place(r.x0, r.x1, want, rng) {
                    let f = &rooms[front_room].rect;
                    let (y0, y1) = if f.y0 >= r.y1 {
                        (r.y1, f.y0)
                    } else {
                        (f.y1, r.y0)
                    };
                    doors.push(DoorPlan {
                        rect: CellRect::new(d0, y0, d1, y1),
                        owner: i,
                        other: Opening::Room(front_room),
                    });
                }
            }
        }
        // Side doors onto a cross corridor just west or east of the room.
        if !matches!(room.kind, RoomKind::Back { .. }) {
            for (at_end, corridor, west) in [
                (r.x0 == seg.rect.x0, seg.west_corridor, true),
                (r.x1 == seg.rect.x1, seg.east_corridor, false),
            ] {
                let Some(corridor) = corridor else { continue };
                if !at_end || !rng.random_bool(p.side_door_probability) {
                    continue;
                }
                let want = door_cells(p.door_width_m, rng);
                if let Some((d0, d1)) = place(r.y0, r.y1, want, rng) {
                    let rect = if west {
                        CellRect::new(r.x0 - tw, d0, r.x0, d1)
                    } else {
                        CellRect::new(r.x1, d0, r.x1 + tw, d1)
                    };
                    doors.push(DoorPlan {
                        rect,
                        owner: i,
                        other: Opening::Corridor(corridor),
                    });
                }
            }
        }
    }
    // Connecting doors between east–west neighbours (the western room owns the opening).
    for i in 0..rooms.len() {
        for j in 0..rooms.len() {
            let (a, b) = (&rooms[i].rect, &rooms[j].rect);
            if b.x0 != a.x1 + tw {
                continue;
            }
            let (y0, y1) = (a.y0.max(b.y0), a.y1.min(b.y1));
            if y1 - y0 < min_door + 2 * margin || !rng.random_bool(p.connecting_door_probability) {
                continue;
            }
            let want = door_cells(p.door_width_m, rng);
            if let Some((d0, d1)) = place(y0, y1, want, rng) {
                doors.push(DoorPlan {
                    rect: CellRect::new(a.x1, d0, b.x0, d1),
                    owner: i,
                    other: Opening::Room(j),
                });
            }
        }
    }
    doors
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::building::layout::plan_skeleton;
    use rand::SeedableRng;

    #[test]
    fn rooms_do_not_overlap_and_every_door_joins_its_two_spaces_through_a_wall() {
        for (p, seed) in [(BuildingParams::office(), 5), (BuildingParams::mall(), 6)] {
            let scale = CellScale::new(&p);
            let mut rng = Pcg64Mcg::seed_from_u64(seed);
            let sk = plan_skeleton(&p, &scale, &mut rng, |_| p.label_shares.corridor);
            let total: i64 = sk.segments.iter().map(|s| s.rect.area()).sum();
            let rooms = plan_rooms(&sk, &p, &scale, total as f64, &mut rng);
            let doors = plan_doors(&sk, &rooms, &p, &scale, &mut rng);
            let min_side = scale.cells(p.min_room_side_m);
            for (i, a) in rooms.iter().enumerate() {
                assert!(
                    a.rect.width() >= min_side && a.rect.height() >= min_side,
                    "{a:?}"
                );
                for b in &rooms[i + 1..] {
                    assert!(!a.rect.intersects(&b.rect), "{a:?} overlaps {b:?}");
                }
                for c in &sk.corridors {
                    assert!(!a.rect.intersects(&c.rect));
                }
            }
            for d in &doors {
                let owner = &rooms[d.owner].rect;
                let side = d.side_of(owner).expect("door on its owner's wall");
                let other = match d.other {
                    Opening::Room(j) => rooms[j].rect,
                    Opening::Corridor(j) => sk.corridors[j].rect,
                };
                // One step beyond the opening, away from the owner, lies the other space.
                let (col, row) = match side {
                    Side::North => (d.rect.x0, d.rect.y1),
                    Side::South => (d.rect.x0, d.rect.y0 - 1),
                    Side::West => (d.rect.x0 - 1, d.rect.y0),
                    Side::East => (d.rect.x1, d.rect.y0),
                };
                assert!(other.contains(col, row), "{d:?} does not reach {other:?}");
                let along = d.rect.width().max(d.rect.height());
                assert!(f64::from(along) * p.resolution_m >= 1.0 - 1e-9);
            }
        }
    }
}

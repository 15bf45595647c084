//! Parameters of the building-floor generators and their paper-002 defaults.
//!
//! Paper 002 (§4.1) gives the label distribution of its two floors (Tables 2–3) but neither their
//! size nor how the rooms are laid out. The office's size follows from Table 4 with Table 2: with
//! S-MCDM and MR coordination the explored big-room area levels off at ≈ 1 850–1 880 m²
//! (1 851.3 ± 7.8 m² with 6 robots and MRv1: every big room explored), which is Table 2's 2 304
//! big-room cells, so a cell of Table 2 is ≈ 0.82 m² and the 8 388 labelled cells ≈ 6 900 m²; the
//! default office is 100 m × 77 m (≈ 6 900 m² of labelled floor). (An earlier default of
//! 80 m × 62 m took the 20-minute total explored area of Table 5, ≈ 4 000–5 000 m², for the
//! floor's size; the paper's teams never finish the floor, so that floor was too small and six
//! robots saturated it.) The mall's Table 7 total, ≈ 5 800 m², gives the default mall of
//! 105 m × 60 m (≈ 5 850 m²). Every other constant below is ours, documented where it is
//! declared.

use crate::error::{Result, WorldError};
use crate::scene::RoomSizeThresholds;
use std::path::Path;

/// Shares of the labelled floor area per semantic label (fractions that sum to 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LabelShares {
    pub corridor: f64,
    pub small_room: f64,
    pub medium_room: f64,
    pub big_room: f64,
}

impl LabelShares {
    /// Paper 002 Table 2 (office): 2 493 corridor, 756 small-room, 2 835 medium-room and
    /// 2 304 big-room cells of 8 388 (30 %, 9 %, 34 %, 27 %).
    pub const OFFICE_TABLE_2: LabelShares = LabelShares {
        corridor: 2493.0 / 8388.0,
        small_room: 756.0 / 8388.0,
        medium_room: 2835.0 / 8388.0,
        big_room: 2304.0 / 8388.0,
    };

    /// Paper 002 Table 3 (mall): 1 449 corridor, 1 332 small-room, 2 088 medium-room and
    /// 3 393 big-room cells of 8 262 (18 %, 16 %, 25 %, 41 %).
    pub const MALL_TABLE_3: LabelShares = LabelShares {
        corridor: 1449.0 / 8262.0,
        small_room: 1332.0 / 8262.0,
        medium_room: 2088.0 / 8262.0,
        big_room: 3393.0 / 8262.0,
    };

    /// The three room shares (small, medium, big) as fractions of the room (non-corridor) area.
    pub(super) fn room_fractions(&self) -> [f64; 3] {
        let rooms = self.small_room + self.medium_room + self.big_room;
        [
            self.small_room / rooms,
            self.medium_room / rooms,
            self.big_room / rooms,
        ]
    }
}

/// A closed interval of lengths, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthRange {
    pub min_m: f64,
    pub max_m: f64,
}

impl LengthRange {
    pub const fn new(min_m: f64, max_m: f64) -> Self {
        Self { min_m, max_m }
    }
}

/// A closed interval of floor areas, m².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaRange {
    pub min_m2: f64,
    pub max_m2: f64,
}

impl AreaRange {
    pub const fn new(min_m2: f64, max_m2: f64) -> Self {
        Self { min_m2, max_m2 }
    }

    pub(super) fn mean_m2(&self) -> f64 {
        (self.min_m2 + self.max_m2) / 2.0
    }
}

/// Parameters of a building floor (paper 002 §4.1 `office` and `mall`).
///
/// The floor is a rectangle `width_m × height_m` closed by exterior walls. East–west corridors
/// run its whole width; north–south cross corridors join them; rows of rooms lie between the
/// corridors and along the exterior walls, each room opening onto a corridor (or, for back rooms,
/// onto the room in front of it). The corridor width is chosen inside `corridor_width_m` so that
/// the corridor share of the labelled area matches `label_shares.corridor`; the rooms are sized
/// so that the room labels match the other shares.
#[derive(Clone, Debug, PartialEq)]
pub struct BuildingParams {
    /// Floor width (x), metres.
    pub width_m: f64,
    /// Floor depth (y), metres.
    pub height_m: f64,
    /// Grid resolution, metres.
    pub resolution_m: f64,
    /// Thickness of every wall, exterior and interior, metres (0.2 m: a light partition).
    pub wall_thickness_m: f64,
    /// Range of corridor widths; the generator picks the width that best matches the corridor
    /// share of `label_shares`.
    pub corridor_width_m: LengthRange,
    /// Preferred depth of a row of rooms (from the corridor wall to the back wall), metres; sets
    /// the number of east–west corridors.
    pub row_depth_m: f64,
    /// Shallowest row of rooms accepted, metres.
    pub min_row_depth_m: f64,
    /// Preferred spacing of the north–south cross corridors, metres.
    pub block_length_m: f64,
    /// Probability that a cross corridor is open between two neighbouring east–west corridors.
    pub cross_corridor_probability: f64,
    /// Probability, per exterior row of rooms, of a corridor stub that runs from the outermost
    /// east–west corridor to the exterior wall (an exit: a dead end).
    pub stub_probability: f64,
    /// Probability, per end of the building, of a north–south corridor along the end wall that
    /// joins the ends of the east–west corridors (corners and T junctions instead of dead ends).
    pub ring_probability: f64,
    /// Target shares of the labelled area per label (paper 002 Tables 2–3).
    pub label_shares: LabelShares,
    /// Floor-area range of a generated small room (before furniture).
    pub small_room_m2: AreaRange,
    /// Floor-area range of a generated medium room (before furniture).
    pub medium_room_m2: AreaRange,
    /// Floor-area range of a generated big room (before furniture).
    pub big_room_m2: AreaRange,
    /// Area limits between the labels: rooms are labelled from their free floor area with
    /// [`crate::RoomLabel::for_room_area`].
    pub thresholds: RoomSizeThresholds,
    /// Shortest side of a room, metres.
    pub min_room_side_m: f64,
    /// Width range of the doors of small rooms and of doors between two rooms, metres.
    pub door_width_m: LengthRange,
    /// Width range of the corridor doors of medium and big rooms (shop fronts in a mall), metres.
    pub front_door_width_m: LengthRange,
    /// A room gets one corridor door per this many metres of corridor frontage (at least one).
    pub frontage_per_door_m: f64,
    /// Probability that a room slot deep enough for two rooms is split into a front room and a
    /// back room (office behind office, shop and storeroom) even when the label plan does not
    /// need it.
    pub back_room_probability: f64,
    /// Probability of a door between two neighbouring rooms of a row.
    pub connecting_door_probability: f64,
    /// Probability of a second corridor door in the side wall of a room next to a cross corridor.
    pub side_door_probability: f64,
    /// Share of each room's floor covered by furniture (desks, shelves, partitions: the "short
    /// line segments" of paper 002 Fig. 4).
    pub furniture_fraction: f64,
    /// Length range of a piece of furniture, metres.
    pub furniture_length_m: LengthRange,
    /// Depth of the furniture-free zone behind every door, metres.
    pub door_clearance_m: f64,
    /// Radius by which obstacles are inflated when checking that furniture leaves every room in
    /// one piece: a Pioneer 3-DX's circumscribed radius (≈ 0.32 m) rounded up.
    pub robot_clearance_m: f64,
    /// One victim per this much labelled area, clamped to `victims`.
    pub area_per_victim_m2: f64,
    /// Least and largest number of victims.
    pub victims: (usize, usize),
    /// Least and largest number of heat sources that are not victims (radiators, a small fire).
    pub heat_sources: (usize, usize),
    /// Number of start poses (enough for the largest team of paper 002 §4.4: 12 robots).
    pub start_poses: usize,
    /// Least distance between two start poses, metres.
    pub start_pose_spacing_m: f64,
    /// Least distance between a start pose and any obstacle, metres.
    pub start_pose_clearance_m: f64,
}

impl BuildingParams {
    /// The paper-002 office: mostly small and medium rooms along corridors (Table 2).
    ///
    /// Room areas: small 14–27.5 m² (one-person offices; below the 30 m² small-room limit),
    /// medium 35–75 m² (shared offices, meeting rooms) and big 150–230 m² (open-plan offices, a
    /// canteen): Table 2's cells per room at ≈ 0.82 m² a cell (see the module documentation) are
    /// ≈ 55 m² per medium room (2 835 / 42) and ≈ 190 m² per big room (2 304 / 10). With Table 2's
    /// area shares on ≈ 6 900 m² these give ≈ 25–30 small, 35–45 medium and 8–12 big rooms
    /// (Table 2: 21, 42, 10). Corridors 2–5 m wide (≈ 3–3.5 m is what the 30 % corridor share
    /// asks for).
    pub fn office() -> Self {
        Self {
            width_m: 100.0,
            height_m: 77.0,
            // The team maps of paper 002's runs are 0.2 m: a floor on the same grid puts every
            // wall face on a map cell boundary. On a 0.1 m floor, half the 0.2 m walls straddle
            // two map cells, whose near halves grazing beams clear while the far side is never
            // seen: fake frontiers along every such wall that no robot can resolve.
            resolution_m: 0.2,
            wall_thickness_m: 0.2,
            corridor_width_m: LengthRange::new(2.0, 5.0),
            row_depth_m: 6.0,
            min_row_depth_m: 4.0,
            block_length_m: 20.0,
            cross_corridor_probability: 0.6,
            stub_probability: 0.35,
            ring_probability: 0.5,
            label_shares: LabelShares::OFFICE_TABLE_2,
            small_room_m2: AreaRange::new(14.0, 27.5),
            medium_room_m2: AreaRange::new(35.0, 75.0),
            big_room_m2: AreaRange::new(150.0, 230.0),
            thresholds: RoomSizeThresholds::default(),
            min_room_side_m: 2.4,
            door_width_m: LengthRange::new(1.0, 1.2),
            front_door_width_m: LengthRange::new(1.0, 1.6),
            frontage_per_door_m: 12.0,
            back_room_probability: 0.05,
            connecting_door_probability: 0.15,
            side_door_probability: 0.3,
            furniture_fraction: 0.05,
            furniture_length_m: LengthRange::new(0.8, 2.4),
            door_clearance_m: 1.2,
            robot_clearance_m: 0.35,
            area_per_victim_m2: 400.0,
            victims: (8, 16),
            heat_sources: (2, 4),
            start_poses: 12,
            start_pose_spacing_m: 1.1,
            start_pose_clearance_m: 0.45,
        }
    }

    /// The paper-002 mall: few very big rooms (≈ 12 % of the rooms, 41 % of the area, Table 3)
    /// and shops along wide galleries.
    ///
    /// Room areas: small 20–28.5 m² (kiosks, storerooms behind shops), medium 35–64 m² (shops),
    /// big 190–370 m² (anchor stores, a food court). With Table 3's shares on ≈ 5 850 m² these give
    /// ≈ 38–44 small, 28–36 medium and 7–10 big rooms (Table 3: 37, 31, 9). Galleries at least
    /// 4 m wide; rows ≈ 12 m deep, so a quarter of the shop slots get a storeroom behind.
    pub fn mall() -> Self {
        Self {
            width_m: 105.0,
            height_m: 60.0,
            resolution_m: 0.1,
            corridor_width_m: LengthRange::new(4.0, 8.0),
            row_depth_m: 11.0,
            min_row_depth_m: 6.0,
            block_length_m: 32.0,
            cross_corridor_probability: 0.5,
            stub_probability: 0.5,
            ring_probability: 0.25,
            label_shares: LabelShares::MALL_TABLE_3,
            small_room_m2: AreaRange::new(20.0, 28.5),
            medium_room_m2: AreaRange::new(35.0, 64.0),
            big_room_m2: AreaRange::new(190.0, 370.0),
            front_door_width_m: LengthRange::new(1.8, 3.6),
            frontage_per_door_m: 15.0,
            back_room_probability: 0.25,
            connecting_door_probability: 0.05,
            furniture_fraction: 0.03,
            furniture_length_m: LengthRange::new(1.0, 3.5),
            ..Self::office()
        }
    }

    /// Checks every field; the error names the field, the value found and what was expected.
    /// The generators do not need this (they clamp), but a caller taking parameters from a user
    /// should report bad ones instead of silently generating something else.
    pub fn check(&self) -> Result<()> {
        let path = Path::new("building parameters");
        let bad = |field: &str, found: String, expected: &str| {
            Err(WorldError::invalid(path, field, found, expected))
        };
        let in_range = |field: &str, v: f64, lo: f64, hi: f64| -> Result<()> {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(WorldError::invalid(
                    path,
                    field,
                    v,
                    format!("a number in [{lo}, {hi}]"),
                ))
            }
        };
        in_range("width_m", self.width_m, MIN_SIDE_M, MAX_SIDE_M)?;
        in_range("height_m", self.height_m, MIN_SIDE_M, MAX_SIDE_M)?;
        in_range("resolution_m", self.resolution_m, 0.02, 0.5)?;
        for (field, side) in [("width_m", self.width_m), ("height_m", self.height_m)] {
            if side / self.resolution_m > MAX_GRID_SIDE as f64 {
                return bad(
                    field,
                    format!("{side} m at {} m cells", self.resolution_m),
                    "at most 8 000 cells per side",
                );
            }
        }
        in_range(
            "wall_thickness_m",
            self.wall_thickness_m,
            self.resolution_m,
            0.5,
        )?;
        for (field, r) in [
            ("corridor_width_m", self.corridor_width_m),
            ("door_width_m", self.door_width_m),
            ("front_door_width_m", self.front_door_width_m),
            ("furniture_length_m", self.furniture_length_m),
        ] {
            in_range(&format!("{field}.min_m"), r.min_m, self.resolution_m, 50.0)?;
            in_range(&format!("{field}.max_m"), r.max_m, r.min_m, 50.0)?;
        }
        in_range(
            "corridor_width_m.min_m",
            self.corridor_width_m.min_m,
            1.5,
            50.0,
        )?;
        in_range("door_width_m.min_m", self.door_width_m.min_m, 1.0, 50.0)?;
        in_range(
            "front_door_width_m.min_m",
            self.front_door_width_m.min_m,
            1.0,
            50.0,
        )?;
        in_range("min_room_side_m", self.min_room_side_m, 2.0, 20.0)?;
        in_range(
            "min_row_depth_m",
            self.min_row_depth_m,
            self.min_room_side_m,
            50.0,
        )?;
        in_range("row_depth_m", self.row_depth_m, self.min_row_depth_m, 50.0)?;
        in_range("block_length_m", self.block_length_m, 8.0, 1000.0)?;
        in_range("frontage_per_door_m", self.frontage_per_door_m, 2.0, 1000.0)?;
        for (field, p) in [
            (
                "cross_corridor_probability",
                self.cross_corridor_probability,
            ),
            ("stub_probability", self.stub_probability),
            ("ring_probability", self.ring_probability),
            ("back_room_probability", self.back_room_probability),
            (
                "connecting_door_probability",
                self.connecting_door_probability,
            ),
            ("side_door_probability", self.side_door_probability),
        ] {
            in_range(field, p, 0.0, 1.0)?;
        }
        in_range("furniture_fraction", self.furniture_fraction, 0.0, 0.3)?;
        in_range("door_clearance_m", self.door_clearance_m, 0.0, 5.0)?;
        in_range("robot_clearance_m", self.robot_clearance_m, 0.0, 1.0)?;
        in_range("area_per_victim_m2", self.area_per_victim_m2, 1.0, 1e9)?;
        in_range("start_pose_spacing_m", self.start_pose_spacing_m, 0.3, 10.0)?;
        in_range(
            "start_pose_clearance_m",
            self.start_pose_clearance_m,
            0.0,
            2.0,
        )?;
        let s = self.label_shares;
        for (field, v) in [
            ("label_shares.corridor", s.corridor),
            ("label_shares.small_room", s.small_room),
            ("label_shares.medium_room", s.medium_room),
            ("label_shares.big_room", s.big_room),
        ] {
            in_range(field, v, 0.0, 1.0)?;
        }
        let sum = s.corridor + s.small_room + s.medium_room + s.big_room;
        if (sum - 1.0).abs() > 1e-6 || s.corridor >= 0.9 {
            return bad(
                "label_shares",
                format!("shares summing to {sum} with corridor {}", s.corridor),
                "shares summing to 1 with a corridor share below 0.9",
            );
        }
        let t = self.thresholds;
        if !(t.small_below_m2.is_finite()
            && t.small_below_m2 > 0.0
            && t.medium_below_m2.is_finite()
            && t.medium_below_m2 > t.small_below_m2)
        {
            return bad(
                "thresholds",
                format!("{t:?}"),
                "0 < small_below_m2 < medium_below_m2, finite",
            );
        }
        let side2 = self.min_room_side_m * self.min_room_side_m;
        for (field, r, lo, hi) in [
            ("small_room_m2", self.small_room_m2, side2, t.small_below_m2),
            (
                "medium_room_m2",
                self.medium_room_m2,
                t.small_below_m2,
                t.medium_below_m2,
            ),
            (
                "big_room_m2",
                self.big_room_m2,
                t.medium_below_m2,
                f64::INFINITY,
            ),
        ] {
            let ok = r.min_m2.is_finite()
                && r.max_m2.is_finite()
                && r.min_m2 >= lo
                && r.max_m2 >= r.min_m2
                && r.max_m2 < hi;
            if !ok {
                return bad(
                    field,
                    format!("[{}, {}]", r.min_m2, r.max_m2),
                    &format!("min ≤ max inside [{lo}, {hi}) m² (the label's area interval)"),
                );
            }
        }
        if self.victims.0 > self.victims.1 || self.victims.1 > 1000 {
            return bad(
                "victims",
                format!("{:?}", self.victims),
                "(min, max) with min ≤ max ≤ 1000",
            );
        }
        if self.heat_sources.0 > self.heat_sources.1 || self.heat_sources.1 > 1000 {
            return bad(
                "heat_sources",
                format!("{:?}", self.heat_sources),
                "(min, max) with min ≤ max ≤ 1000",
            );
        }
        if self.start_poses > 1000 {
            return bad("start_poses", self.start_poses.to_string(), "at most 1000");
        }
        Ok(())
    }

    /// The parameters with every field clamped into the range [`BuildingParams::check`] accepts,
    /// so that generation never panics. Non-finite values fall back to the default of the floor
    /// whose label shares the parameters carry (the mall's for Table 3, else the office's).
    pub(super) fn sanitized(&self) -> BuildingParams {
        let d = if self.label_shares == LabelShares::MALL_TABLE_3 {
            Self::mall()
        } else {
            Self::office()
        };
        let clamp = |v: f64, lo: f64, hi: f64, default: f64| {
            if v.is_finite() {
                v.clamp(lo, hi.max(lo))
            } else {
                default.clamp(lo, hi.max(lo))
            }
        };
        let resolution_m = clamp(self.resolution_m, 0.02, 0.5, d.resolution_m);
        let max_side = MAX_GRID_SIDE as f64 * resolution_m;
        let width_m = clamp(
            self.width_m,
            MIN_SIDE_M,
            MAX_SIDE_M.min(max_side),
            d.width_m,
        );
        let height_m = clamp(
            self.height_m,
            MIN_SIDE_M,
            MAX_SIDE_M.min(max_side),
            d.height_m,
        );
        let range = |r: LengthRange, lo: f64, hi: f64, default: LengthRange| {
            let min_m = clamp(r.min_m, lo, hi, default.min_m);
            LengthRange::new(min_m, clamp(r.max_m, min_m, hi, default.max_m))
        };
        let min_room_side_m = clamp(self.min_room_side_m, 2.0, 20.0, d.min_room_side_m);
        let min_row_depth_m = clamp(
            self.min_row_depth_m,
            min_room_side_m,
            50.0,
            d.min_row_depth_m,
        );
        let mut t = self.thresholds;
        if !(t.small_below_m2.is_finite()
            && t.small_below_m2 > 0.0
            && t.medium_below_m2.is_finite()
            && t.medium_below_m2 > t.small_below_m2)
        {
            t = RoomSizeThresholds::default();
        }
        let side2 = min_room_side_m * min_room_side_m;
        let area = |r: AreaRange, lo: f64, hi: f64, default: AreaRange| {
            // Keep the range strictly inside the label's interval.
            let hi = (hi - 0.01 * hi.min(1e6)).max(lo);
            let min_m2 = clamp(r.min_m2, lo, hi, default.min_m2);
            AreaRange::new(min_m2, clamp(r.max_m2, min_m2, hi, default.max_m2))
        };
        let small_lo = side2.min(t.small_below_m2 * 0.5);
        let s = self.label_shares;
        let shares_ok = [s.corridor, s.small_room, s.medium_room, s.big_room]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0)
            && s.corridor < 0.9
            && s.small_room + s.medium_room + s.big_room > 0.0;
        let label_shares = if shares_ok {
            let sum = s.corridor + s.small_room + s.medium_room + s.big_room;
            LabelShares {
                corridor: s.corridor / sum,
                small_room: s.small_room / sum,
                medium_room: s.medium_room / sum,
                big_room: s.big_room / sum,
            }
        } else {
            d.label_shares
        };
        let victims_max = self.victims.1.min(1000);
        let heat_max = self.heat_sources.1.min(1000);
        BuildingParams {
            width_m,
            height_m,
            resolution_m,
            wall_thickness_m: clamp(self.wall_thickness_m, resolution_m, 0.5, d.wall_thickness_m),
            corridor_width_m: range(self.corridor_width_m, 1.5, 50.0, d.corridor_width_m),
            row_depth_m: clamp(self.row_depth_m, min_row_depth_m, 50.0, d.row_depth_m),
            min_row_depth_m,
            block_length_m: clamp(self.block_length_m, 8.0, 1000.0, d.block_length_m),
            cross_corridor_probability: clamp(self.cross_corridor_probability, 0.0, 1.0, 0.5),
            stub_probability: clamp(self.stub_probability, 0.0, 1.0, 0.5),
            ring_probability: clamp(self.ring_probability, 0.0, 1.0, 0.5),
            label_shares,
            small_room_m2: area(
                self.small_room_m2,
                small_lo,
                t.small_below_m2,
                d.small_room_m2,
            ),
            medium_room_m2: area(
                self.medium_room_m2,
                t.small_below_m2,
                t.medium_below_m2,
                d.medium_room_m2,
            ),
            big_room_m2: area(self.big_room_m2, t.medium_below_m2, 1e7, d.big_room_m2),
            thresholds: t,
            min_room_side_m,
            door_width_m: range(self.door_width_m, 1.0, 50.0, d.door_width_m),
            front_door_width_m: range(self.front_door_width_m, 1.0, 50.0, d.front_door_width_m),
            frontage_per_door_m: clamp(self.frontage_per_door_m, 2.0, 1000.0, 12.0),
            back_room_probability: clamp(self.back_room_probability, 0.0, 1.0, 0.1),
            connecting_door_probability: clamp(self.connecting_door_probability, 0.0, 1.0, 0.1),
            side_door_probability: clamp(self.side_door_probability, 0.0, 1.0, 0.3),
            furniture_fraction: clamp(self.furniture_fraction, 0.0, 0.3, d.furniture_fraction),
            furniture_length_m: range(
                self.furniture_length_m,
                resolution_m,
                50.0,
                d.furniture_length_m,
            ),
            door_clearance_m: clamp(self.door_clearance_m, 0.0, 5.0, d.door_clearance_m),
            robot_clearance_m: clamp(self.robot_clearance_m, 0.0, 1.0, d.robot_clearance_m),
            area_per_victim_m2: clamp(self.area_per_victim_m2, 1.0, 1e9, d.area_per_victim_m2),
            victims: (self.victims.0.min(victims_max), victims_max),
            heat_sources: (self.heat_sources.0.min(heat_max), heat_max),
            start_poses: self.start_poses.min(1000),
            start_pose_spacing_m: clamp(self.start_pose_spacing_m, 0.3, 10.0, 1.1),
            start_pose_clearance_m: clamp(self.start_pose_clearance_m, 0.0, 2.0, 0.45),
        }
    }
}

/// Smallest floor side accepted, metres: one corridor with a row of rooms on each side.
pub const MIN_SIDE_M: f64 = 20.0;
/// Largest floor side accepted, metres.
pub const MAX_SIDE_M: f64 = 400.0;
/// Largest number of cells per side of a generated floor.
pub const MAX_GRID_SIDE: u32 = 8000;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_pass_their_own_check() {
        BuildingParams::office().check().unwrap();
        BuildingParams::mall().check().unwrap();
    }

    #[test]
    fn table_shares_sum_to_one() {
        for s in [LabelShares::OFFICE_TABLE_2, LabelShares::MALL_TABLE_3] {
            let sum = s.corridor + s.small_room + s.medium_room + s.big_room;
            assert!((sum - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn check_names_the_bad_field_and_sanitized_repairs_it() {
        let p = BuildingParams {
            width_m: f64::NAN,
            resolution_m: -1.0,
            ..BuildingParams::office()
        };
        let message = p.check().unwrap_err().to_string();
        assert!(message.contains("width_m"), "{message}");
        let fixed = p.sanitized();
        fixed.check().unwrap();
        assert_eq!(fixed.width_m, BuildingParams::office().width_m);
        assert_eq!(fixed.resolution_m, 0.02);
        let huge = BuildingParams {
            width_m: 1e9,
            ..BuildingParams::office()
        };
        assert!(huge.check().unwrap_err().to_string().contains("width_m"));
        huge.sanitized().check().unwrap();
    }
}

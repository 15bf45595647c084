//! The semantic layer: rooms with labels, the doors between them, corridor intersections
//! (paper 002 §3.1).

use crate::geometry::Point2;
use serde::{Deserialize, Serialize};

/// The semantic label of a room, as used by paper 002 (Tables 2–3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RoomLabel {
    Corridor,
    SmallRoom,
    MediumRoom,
    BigRoom,
}

impl RoomLabel {
    pub const ALL: [RoomLabel; 4] = [
        RoomLabel::Corridor,
        RoomLabel::SmallRoom,
        RoomLabel::MediumRoom,
        RoomLabel::BigRoom,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            RoomLabel::Corridor => "corridor",
            RoomLabel::SmallRoom => "small_room",
            RoomLabel::MediumRoom => "medium_room",
            RoomLabel::BigRoom => "big_room",
        }
    }

    /// Label of a room by its floor area, with the area thresholds the generators and the room
    /// segmentation share (see [`RoomSizeThresholds`]).
    pub fn for_room_area(area_m2: f64, thresholds: RoomSizeThresholds) -> RoomLabel {
        if area_m2 < thresholds.small_below_m2 {
            RoomLabel::SmallRoom
        } else if area_m2 < thresholds.medium_below_m2 {
            RoomLabel::MediumRoom
        } else {
            RoomLabel::BigRoom
        }
    }
}

impl std::fmt::Display for RoomLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Room-size classes by floor area. Paper 002 labels rooms "according to their size" without
/// giving the limits; these defaults put a one-person office (≤ 30 m²) in `small_room`, a meeting
/// room or lab (30–100 m²) in `medium_room` and halls, canteens and shops above 100 m² in
/// `big_room`, which reproduces the label shares of Tables 2–3 on our generated floors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoomSizeThresholds {
    pub small_below_m2: f64,
    pub medium_below_m2: f64,
}

impl Default for RoomSizeThresholds {
    fn default() -> Self {
        Self {
            small_below_m2: 30.0,
            medium_below_m2: 100.0,
        }
    }
}

/// Identifier of a room; 0 in the room layer means "not in any room".
pub type RoomId = u16;

/// A room or corridor of the semantic layer. Its cells are those of the room layer carrying `id`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Room {
    pub id: RoomId,
    pub label: RoomLabel,
    /// Ids of the doors that open into this room.
    #[serde(default)]
    pub door_ids: Vec<u32>,
    /// For corridors: the other corridors that intersect this one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub intersecting_corridors: Vec<RoomId>,
}

/// A doorway between two rooms (or a room and a corridor).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Door {
    pub id: u32,
    /// Centre of the doorway.
    pub position: Point2,
    pub width_m: f64,
    /// The two rooms the door joins (0 = outside every room).
    pub rooms: [RoomId; 2],
}

//! What viewers receive: a small [`Frame`] many times a second (robots, victims, hand-offs,
//! clock) and a larger [`MapView`] when the maps change (the team's merged occupancy grid with
//! semantic labels, the MAXQ robot's cell map, the BTM, the explored area over time).

use serde::{Deserialize, Serialize};

/// One robot as the console shows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotView {
    /// 0 is the MAXQ robot, 1… the team, then the BTM crawler (when the mission has one).
    pub id: usize,
    pub name: String,
    /// `maxq`, `team` or `btm`.
    pub kind: String,
    pub x: f64,
    pub y: f64,
    pub theta: f64,
    /// `autonomous` or `operator`.
    pub mode: String,
    /// The MAXQ subtask (NUR/NG, VI, HC₂, HC₃, exited), the team robot's run mode
    /// (exploring, recovering, idle, failed, teleoperated, sent) or the crawler's progress.
    pub task: String,
    /// Where it is heading, if anywhere.
    pub goal: Option<[f64; 2]>,
}

/// A possible victim: met by the MAXQ robot, or reported by a team robot to the base station.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VictimView {
    pub id: usize,
    pub x: f64,
    pub y: f64,
    /// `pending` (undecided), `tagged` (a victim: tagged by the robot or confirmed by the
    /// operator) or `dismissed`.
    pub status: String,
    pub probability: Option<f64>,
}

/// What a hand-off asks of the operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HandOffKind {
    /// A possible victim: Confirm / Reject.
    Victim,
    /// A stuck robot: drive it until it gets going again.
    Stuck,
}

/// A hand-off waiting for the operator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HandOffView {
    pub id: u64,
    pub robot: usize,
    pub kind: HandOffKind,
    pub x: f64,
    pub y: f64,
    /// Why a robot is stuck: `slipping` (its commands do not take effect; control returns when
    /// one does) or `no progress` (it has driven without exploring anything new; control
    /// returns once the operator's driving explores something).
    pub reason: Option<String>,
    /// Where the stuck robot's exploration would go next (`east`, `north`, `west`, `south`),
    /// if anywhere: what the robot would do, for the person to judge.
    pub suggested: Option<usar_rescue::exploration::Direction>,
    pub probability: Option<f64>,
    pub size_m2: Option<f64>,
    /// URLs of the sensor images (thermal region, depth profile).
    pub thermal: Option<String>,
    pub depth: Option<String>,
}

/// A frame of the live mission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// Always `frame`.
    #[serde(rename = "type")]
    pub kind: String,
    pub seq: u64,
    /// The mission clock, simulated seconds.
    pub time_s: f64,
    pub paused: bool,
    /// The speed asked for and the one measured over the last second (sim s per wall s).
    pub speed: f64,
    pub measured_speed: f64,
    pub robots: Vec<RobotView>,
    pub victims: Vec<VictimView>,
    pub handoffs: Vec<HandOffView>,
    pub explored_m2: f64,
    pub coverage: f64,
    pub weights: [f64; 3],
    pub hypothesis: String,
    pub btm_nodes: usize,
    pub btm_links: usize,
    /// How the mission ended (`time limit`, `stopped`), once it has.
    pub team_finish: Option<String>,
    /// Primitives the MAXQ robot's policy has chosen so far.
    pub maxq_primitives: u64,
    /// Tags the MAXQ robot carried out (its own and those the operator confirmed).
    pub maxq_tags: u32,
    /// Version of the latest map message.
    pub map_seq: u64,
}

/// A BTM node or link for the overlay.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BtmNodeView {
    pub id: u32,
    pub x: f64,
    pub y: f64,
    pub kind: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BtmLinkView {
    pub start: u32,
    pub end: Option<u32>,
    pub searched: bool,
    /// For an open link: its direction from the start node.
    pub direction_rad: f64,
}

/// The maps (sent when they change).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapView {
    /// Always `map`.
    #[serde(rename = "type")]
    pub kind: String,
    pub seq: u64,
    /// The team's merged grid: size, resolution, origin (world coordinates of cell (0, 0)'s
    /// lower-left corner); `cells` base64 of one byte per cell, row 0 southernmost:
    /// 0 unknown, 1 free, 2 occupied; `labels` the same with 0 no room, 1 corridor,
    /// 2 small, 3 medium, 4 big room (known cells only).
    pub width: u32,
    pub height: u32,
    pub resolution_m: f64,
    pub origin: [f64; 2],
    pub cells: String,
    pub labels: String,
    /// The MAXQ robot's cell map (paper 000 §V categories), one byte per coarse cell:
    /// 0 unknown, 1 open unvisited, 2 open visited, 3 climbable unvisited, 4 climbable
    /// visited, 5 non-climbable, 6 victim, 7 unknown obstacle.
    pub cell_cols: u32,
    pub cell_rows: u32,
    pub cell_size_m: f64,
    pub cell_origin: [f64; 2],
    pub cell_map: String,
    pub btm_nodes: Vec<BtmNodeView>,
    pub btm_links: Vec<BtmLinkView>,
    /// Explored area over time: (simulated s, m²).
    pub explored: Vec<[f64; 2]>,
}

//! What the console shows of the running mission, taken from what the robots report — the
//! team's poses and merged map as its controller believes them, the crawler's pose estimate
//! and Behavioral Trace Map, the rescuer's cell map and possible victims, the desk's questions
//! and the base station's victim board. The camera images of a victim hand-off are rendered
//! from the scene, as a camera would show it to the person at the desk; coverage is the
//! evaluation's figure.

use crate::hook::{FRAME_PERIOD, MAP_PERIOD, Override, Pacer};
use crate::images;
use crate::mission::Shared;
use crate::snapshot::{
    BtmLinkView, BtmNodeView, Frame, HandOffKind, HandOffView, MapView, RobotView, VictimView,
};
use base64::Engine;
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;
use std::time::{Duration, Instant};
use usar_map::CellClass;
use usar_mission::LiveMission;
use usar_rescue::VictimMark;
use usar_rescue::VictimStatus;
use usar_rescue::cell_map::MapCell;
use usar_rescue::controller::Question;
use usar_rescue::perception::victim_probability;
use usar_world::RoomLabel;
use usar_world::cellview::PAPER_CELL_SIDE_M;

/// Per host robot id, the console's number: 0 the rescuer, 1…n the team, n + 1 the crawler.
pub(crate) fn console_ids(live: &LiveMission<'_, '_>) -> Vec<(usize, usize)> {
    let n = live.team_len();
    let mut ids: Vec<(usize, usize)> = (0..n)
        .filter_map(|k| live.team_robot(k).map(|id| (id.0, k + 1)))
        .collect();
    ids.extend(live.rescuer_robot().map(|id| (id.0, 0)));
    ids
}

/// The display code of a room label (see [`MapView::labels`]).
fn label_code(label: Option<RoomLabel>) -> u8 {
    match label {
        None => 0,
        Some(RoomLabel::Corridor) => 1,
        Some(RoomLabel::SmallRoom) => 2,
        Some(RoomLabel::MediumRoom) => 3,
        Some(RoomLabel::BigRoom) => 4,
    }
}

/// The display code of a cell-map category (see [`MapView::cell_map`]).
fn cell_code(c: MapCell) -> u8 {
    match c {
        MapCell::Unknown => 0,
        MapCell::OpenUnvisited => 1,
        MapCell::OpenVisited => 2,
        MapCell::ClimbableUnvisited => 3,
        MapCell::ClimbableVisited => 4,
        MapCell::NonClimbable => 5,
        MapCell::Victim => 6,
        MapCell::UnknownObstacle => 7,
    }
}

fn mark_name(mark: VictimMark) -> &'static str {
    match mark {
        VictimMark::Pending => "pending",
        VictimMark::Tagged => "tagged",
        VictimMark::Dismissed => "dismissed",
    }
}

/// Renders the camera images of victim question `id` the first time it is shown: the thermal
/// region at `at` and the depth profile ahead of the asking robot (host id `robot`).
fn render_images(
    live: &LiveMission<'_, '_>,
    shared: &Shared,
    id: u64,
    robot: usize,
    at: usar_world::Point2,
) {
    let mut stored = shared.lock_images();
    stored.entry(id).or_insert_with(|| {
        let truth = live.evaluator();
        let scene = truth.scene();
        let body = truth
            .robots()
            .get(robot)
            .map_or(usar_world::Pose2::new(at.x, at.y, 0.0), |r| r.pose);
        let cell_m = live
            .rescuer()
            .map_or(PAPER_CELL_SIDE_M, |r| r.zone().resolution_m);
        let heading = ((body.theta / FRAC_PI_2).round() as i64).rem_euclid(4) as u8;
        (
            images::thermal_png(scene, at, cell_m),
            images::depth_png(scene, body.position(), heading, cell_m),
        )
    });
}

/// The crawler's BTM nodes, for a map message.
fn btm_nodes(live: &LiveMission<'_, '_>) -> Vec<BtmNodeView> {
    let Some(btm) = live.crawler().map(|c| c.btm()) else {
        return Vec::new();
    };
    btm.nodes
        .iter()
        .map(|n| BtmNodeView {
            id: n.id,
            x: n.x_m,
            y: n.y_m,
            kind: n.kind.clone(),
        })
        .collect()
}

/// The crawler's BTM links, for a map message.
fn btm_links(live: &LiveMission<'_, '_>) -> Vec<BtmLinkView> {
    let Some(btm) = live.crawler().map(|c| c.btm()) else {
        return Vec::new();
    };
    btm.links
        .iter()
        .map(|l| BtmLinkView {
            start: l.start,
            end: l.end,
            searched: l.searched,
            direction_rad: l.direction_rad,
        })
        .collect()
}

/// The latest views, and what was last sent.
pub(crate) struct Observed {
    pub weights: [f64; 3],
    pub hypothesis: String,
    /// How the mission ended, once it has.
    pub finish: Option<String>,
    pub ids: Vec<(usize, usize)>,
    last_frame: Instant,
    last_map: Instant,
    seq: u64,
    map_seq: u64,
    /// What the last map message showed: explored samples, cell-map codes, BTM size.
    map_state: (usize, Vec<u8>, usize),
    robots: Vec<RobotView>,
    victims: Vec<VictimView>,
    handoffs: Vec<HandOffView>,
    explored: Vec<[f64; 2]>,
    explored_m2: f64,
    coverage: f64,
    btm: (usize, usize),
    maxq: (u64, u32),
    /// A map message waiting to go out with the next frame.
    pending_map: Option<MapView>,
}

impl Observed {
    pub(crate) fn new(hypothesis: &str, weights: [f64; 3]) -> Self {
        let long_ago = Instant::now() - Duration::from_secs(10);
        Self {
            weights,
            hypothesis: hypothesis.into(),
            finish: None,
            ids: Vec::new(),
            last_frame: long_ago,
            last_map: long_ago,
            seq: 0,
            map_seq: 0,
            map_state: (usize::MAX, Vec::new(), usize::MAX),
            robots: Vec::new(),
            victims: Vec::new(),
            handoffs: Vec::new(),
            explored: Vec::new(),
            explored_m2: 0.0,
            coverage: 0.0,
            btm: (0, 0),
            maxq: (0, 0),
            pending_map: None,
        }
    }

    pub(crate) fn frame_due(&self) -> bool {
        self.last_frame.elapsed() >= FRAME_PERIOD
    }

    /// The console's number of host robot `id`.
    fn console_id(&self, id: usize) -> usize {
        self.ids
            .iter()
            .find(|(host, _)| *host == id)
            .map_or(id, |&(_, c)| c)
    }

    /// Takes the views from the mission; a map message is prepared when the maps changed and
    /// the last one is [`MAP_PERIOD`] old.
    pub(crate) fn observe(
        &mut self,
        live: &LiveMission<'_, '_>,
        overrides: &[Option<Override>],
        shared: &Shared,
    ) {
        let now = live.time_s();
        self.robots.clear();
        self.rescuer(live);
        self.team(live, overrides);
        self.crawler(live);
        self.victims(live);
        self.handoffs(live, shared);
        self.explored_m2 = live.team().base_station().merged.known_area_m2();
        self.coverage = live.coverage();
        if self.explored.last().is_none_or(|s| now - s[0] >= 1.0) {
            self.explored.push([now, self.explored_m2]);
        }
        let cell_map: Vec<u8> = live
            .rescuer()
            .and_then(|r| r.agent())
            .map(|a| a.map.cells.iter().map(|&c| cell_code(c)).collect())
            .unwrap_or_default();
        let state = (self.explored.len(), cell_map, self.btm.0 + self.btm.1);
        if state != self.map_state && self.last_map.elapsed() >= MAP_PERIOD {
            self.last_map = Instant::now();
            self.map_seq += 1;
            self.pending_map = Some(self.map_view(live, &state.1));
            self.map_state = state;
        }
    }

    /// Paper 000's robot where it believes it is: the centre of its cell, facing its heading.
    fn rescuer(&mut self, live: &LiveMission<'_, '_>) {
        let Some(rescuer) = live.rescuer() else {
            return;
        };
        self.maxq = (rescuer.log.primitives, rescuer.tags.len() as u32);
        let Some(agent) = rescuer.agent() else {
            return;
        };
        let p = rescuer.zone().cell_center(agent.robot.cell);
        let state = agent.state();
        let task = if state.done() {
            "exited"
        } else if state.stuck() {
            "HC3: operator drives"
        } else {
            match state.victim_status() {
                VictimStatus::UncertainAtHand => "HC2: victim to operator",
                VictimStatus::CertainAtHand => "VI: tag",
                VictimStatus::ToReach => "VI: approach victim",
                VictimStatus::None => "NUR: explore (NG)",
            }
        };
        let asking = live
            .rescuer_robot()
            .is_some_and(|id| live.desk().questions().any(|q| q.robot == id.0));
        self.robots.push(RobotView {
            id: 0,
            name: "MAXQ".into(),
            kind: "maxq".into(),
            x: p.x,
            y: p.y,
            theta: f64::from(agent.robot.heading) * FRAC_PI_2,
            mode: if asking { "operator" } else { "autonomous" }.into(),
            task: task.into(),
            goal: None,
        });
    }

    /// The team's robots at the poses their controller believes.
    fn team(&mut self, live: &LiveMission<'_, '_>, overrides: &[Option<Override>]) {
        let team = live.team();
        let truth = live.evaluator();
        for k in 0..live.team_len() {
            let (Some(pose), Some(id)) = (team.pose(k), live.team_robot(k)) else {
                continue;
            };
            let control = overrides.get(k).and_then(Option::as_ref);
            let (mode, task) = match control {
                Some(Override::Teleop { .. }) => ("operator", "teleoperated"),
                Some(Override::Path { .. }) => ("operator", "sent to a point"),
                // Whether it failed is the evaluation's to say (the team sees it fall silent).
                None if truth.robot(id).failed => ("autonomous", "failed"),
                None if team.is_recovering(k) => ("autonomous", "recovering"),
                None if team.robot_goal(k).is_some() => ("autonomous", "exploring"),
                None => ("autonomous", "idle"),
            };
            let goal = match control {
                Some(Override::Path { follower, .. }) => follower.goal(),
                _ => team.robot_goal(k),
            };
            self.robots.push(RobotView {
                id: k + 1,
                name: format!("team {}", k + 1),
                kind: "team".into(),
                x: pose.x,
                y: pose.y,
                theta: pose.theta,
                mode: mode.into(),
                task: task.into(),
                goal: goal.map(|p| [p.x, p.y]),
            });
        }
    }

    /// The crawler at its own pose estimate, and its BTM's size.
    fn crawler(&mut self, live: &LiveMission<'_, '_>) {
        let Some(explorer) = live.crawler() else {
            return;
        };
        let btm = explorer.btm();
        self.btm = (btm.nodes.len(), btm.links.len());
        let pose = explorer.estimated_pose();
        let task = match live.crawler_finished() {
            None => format!("building the BTM (paper 004): {} nodes", btm.nodes.len()),
            Some(Ok(stop)) => format!("BTM built ({stop:?}): {} nodes", btm.nodes.len()),
            Some(Err(e)) => format!("BTM build failed: {e}"),
        };
        self.robots.push(RobotView {
            id: live.team_len() + 1,
            name: "BTM crawler".into(),
            kind: "btm".into(),
            x: pose.x,
            y: pose.y,
            theta: pose.theta,
            mode: "autonomous".into(),
            task,
            goal: None,
        });
    }

    /// The rescuer's possible victims, then the team's reports on the base station's board
    /// (`pending` until the operator answers, then `tagged` or `dismissed`).
    fn victims(&mut self, live: &LiveMission<'_, '_>) {
        self.victims.clear();
        if let Some(rescuer) = live.rescuer()
            && let Some(agent) = rescuer.agent()
        {
            for ((c, r), mark, probability) in agent.possible_victims() {
                let p = rescuer.zone().cell_center(usar_world::Cell::new(c, r));
                self.victims.push(VictimView {
                    id: self.victims.len(),
                    x: p.x,
                    y: p.y,
                    status: mark_name(mark).into(),
                    probability,
                });
            }
        }
        for e in &live.board().entries {
            let status = match e.confirmed {
                None => "pending",
                Some((true, _)) => "tagged",
                Some((false, _)) => "dismissed",
            };
            self.victims.push(VictimView {
                id: self.victims.len(),
                x: e.at.x,
                y: e.at.y,
                status: status.into(),
                probability: Some(victim_probability(true, e.report.size_m2)),
            });
        }
    }

    /// The desk's questions: the one attended first. A victim question comes with the camera
    /// images of the asking robot (rendered once, when first shown).
    fn handoffs(&mut self, live: &LiveMission<'_, '_>, shared: &Shared) {
        self.handoffs.clear();
        let rescuer = live.rescuer();
        let questions: Vec<_> = live.desk().questions().collect();
        for q in questions {
            let robot = self.console_id(q.robot);
            let view = match q.question {
                Question::Victim {
                    probability,
                    size_m2,
                    at,
                    ..
                } => {
                    render_images(live, shared, q.id, q.robot, at);
                    HandOffView {
                        id: q.id,
                        robot,
                        kind: HandOffKind::Victim,
                        x: at.x,
                        y: at.y,
                        reason: None,
                        suggested: None,
                        probability: Some(probability),
                        size_m2: Some(size_m2),
                        thermal: Some(format!("/api/handoff/{}/thermal.png", q.id)),
                        depth: Some(format!("/api/handoff/{}/depth.png", q.id)),
                    }
                }
                Question::Drive { request, .. } => {
                    let Some(r) = rescuer else { continue };
                    let p = r
                        .zone()
                        .cell_center(usar_world::Cell::new(request.cell.0, request.cell.1));
                    let slipping = r.agent().is_some_and(|a| a.is_stuck());
                    HandOffView {
                        id: q.id,
                        robot,
                        kind: HandOffKind::Stuck,
                        x: p.x,
                        y: p.y,
                        reason: Some(if slipping { "slipping" } else { "no progress" }.into()),
                        suggested: request.suggested,
                        probability: None,
                        size_m2: None,
                        thermal: None,
                        depth: None,
                    }
                }
            };
            self.handoffs.push(view);
        }
    }

    /// The map message: the team's merged grid with the room labels its semantic map holds
    /// (the oracle's or its own segmentation's), the rescuer's cell map, the BTM.
    fn map_view(&self, live: &LiveMission<'_, '_>, cell_map: &[u8]) -> MapView {
        let team = live.team();
        let merged = &team.base_station().merged;
        let semantic = team.semantic_map();
        let g = *merged.geometry();
        let mut cells = Vec::with_capacity(g.len());
        let mut labels = Vec::with_capacity(g.len());
        for i in 0..g.len() {
            let class = merged.class_at_index(i);
            cells.push(match class {
                CellClass::Unknown => 0u8,
                CellClass::Free => 1,
                CellClass::Occupied => 2,
            });
            let label = semantic
                .room_of(i)
                .and_then(|k| semantic.rooms().get(k))
                .map(|r| r.label);
            labels.push(if class == CellClass::Unknown {
                0
            } else {
                label_code(label)
            });
        }
        let zone = live.rescuer().map(|r| *r.zone());
        let b64 = base64::engine::general_purpose::STANDARD;
        MapView {
            kind: "map".into(),
            seq: self.map_seq,
            width: g.width,
            height: g.height,
            resolution_m: g.resolution_m,
            origin: [g.origin.x, g.origin.y],
            cells: b64.encode(&cells),
            labels: b64.encode(&labels),
            cell_cols: zone.map_or(0, |z| z.width),
            cell_rows: zone.map_or(0, |z| z.height),
            cell_size_m: zone.map_or(0.0, |z| z.resolution_m),
            cell_origin: zone.map_or([0.0; 2], |z| [z.origin.x, z.origin.y]),
            cell_map: b64.encode(cell_map),
            btm_nodes: btm_nodes(live),
            btm_links: btm_links(live),
            explored: self.explored.clone(),
        }
    }

    /// Publishes a frame now, and the map message prepared, if any.
    pub(crate) fn publish(
        &mut self,
        shared: &Arc<Shared>,
        sim_s: f64,
        pacer: &Pacer,
        measured: f64,
    ) {
        self.seq += 1;
        self.last_frame = Instant::now();
        if let Some(m) = self.pending_map.take()
            && let Ok(text) = serde_json::to_string(&m)
        {
            shared.map_tx.send_replace(Arc::from(text));
        }
        let frame = Frame {
            kind: "frame".into(),
            seq: self.seq,
            time_s: sim_s,
            paused: pacer.paused,
            speed: pacer.speed,
            measured_speed: measured,
            robots: self.robots.clone(),
            victims: self.victims.clone(),
            handoffs: self.handoffs.clone(),
            explored_m2: self.explored_m2,
            coverage: self.coverage,
            weights: self.weights,
            hypothesis: self.hypothesis.clone(),
            btm_nodes: self.btm.0,
            btm_links: self.btm.1,
            team_finish: self.finish.clone(),
            maxq_primitives: self.maxq.0,
            maxq_tags: self.maxq.1,
            map_seq: self.map_seq,
        };
        if let Ok(text) = serde_json::to_string(&frame) {
            shared.frame_tx.send_replace(Arc::from(text));
        }
    }
}

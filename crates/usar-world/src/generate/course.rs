//! Paper 004 Fig. 15 test course: "a couple of passages, multi-link junctions, an elevator hall
//! (a potential free space), and a slope", plus stairs (§II-A: "Slope and Stairs are considered to
//! be the basic three dimensional features").
//!
//! The paper shows the course only as a schematic, so the layout below keeps its elements and the
//! robot's run (start at a passage end, over a slope, right at a divergence, along the hall's wall,
//! right again to the goal) and adds what the paper's node kinds need (§III: dead end, corner, T,
//! crossing, free space, obstacle). Centre lines, with the default sizes (metres, x east, y north):
//!
//! ```text
//!                 ┌──────── hall 12 × 10 ────────┐
//!   C3 ───────────┤                              │
//!   │             └──────────────┬───────────────┘
//!   │                            │
//!   D2                           T1 ────────────────────── T2 ─ stairs ▲ platform ─ D3
//!                                │                         │
//!   S (start) ────────────────── X ── ramp ▲ top ▼ ramp ── C1
//!                                │
//!                                D1
//! ```
//!
//! - S: the start, a dead end at the west end of the main passage (y = 5);
//! - X: a crossing (x = 12); D1 a dead end south of it;
//! - a triangular slope (up, level top, down) between X and the corner C1: it lies on the loop
//!   X–C1–T2–T1–X, so a robot that cannot climb it reaches C1 the other way round;
//! - T1 and T2: T junctions on the passage y = 13; east of T2 a flight of stairs climbs to a
//!   platform that ends in the dead end D3 (only stair climbers get there);
//! - the hall north of T1, wider than twice a 4 m laser search radius in both directions, with a
//!   second exit west to the corner C3 and the dead end D2 (the goal end).
//!
//! A wheeled robot (slope ≤ 15°, steps ≤ 0.05 m) reaches every level cell; a crawler (≤ 35°,
//! steps ≤ 0.2 m) everything. The seed varies the passage width (±10 %), the hall's size
//! (±0.5 m), where the slope starts, where the hall's west exit and D2 lie; never the topology.
//! Every junction is recorded at the crossing point of its passages' centre lines (a dead end
//! half a passage width from its end wall); all coordinates are multiples of the resolution.

use super::draw::{fill_rect, shape_floor};
use crate::error::{Result, WorldError};
use crate::geometry::{Point2, Pose2, Rect};
use crate::grid::{Grid, GridGeometry};
use crate::scene::{
    Door, Junction, JunctionKind, Provenance, Room, RoomLabel, RoomSizeThresholds, Scene,
    TerrainFeature, obstacle,
};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::ops::RangeInclusive;
use std::path::Path;

/// Parameters of the test course. Every value is clamped into the range given in its comment.
#[derive(Clone, Debug, PartialEq)]
pub struct CourseParams {
    /// Fine grid resolution, metres (0.02–0.25; default 0.1: a 0.3 m stair tread spans 3 cells
    /// and a 20° ramp rises 3.6 cm per cell).
    pub resolution_m: f64,
    /// Nominal passage width, metres (1.0–2.2; default 1.6, paper 004's course: "passages" a
    /// 0.39 m wide KAMUI turns in).
    pub passage_width_m: f64,
    /// Relative variation of the passage width drawn per seed (0–0.1; default 0.1 = ±10 %).
    pub width_variation: f64,
    /// Hall width (x) and depth (y), metres (9–14; defaults 12 × 10: more than twice a 4 m
    /// laser search radius, and a `big_room` of 120 m²).
    pub hall_width_m: f64,
    pub hall_depth_m: f64,
    /// Inclination of both ramps of the slope, radians (1°–60°; default 20°: a crawler climbs
    /// ≤ 35°, a wheeled robot ≤ 15°; paper 004 ran KAMUI over 10°).
    pub slope_inclination_rad: f64,
    /// Horizontal length of each ramp, metres (0.5–4; default 2.5).
    pub slope_run_m: f64,
    /// Length of the slope's level top, metres (0–2; default 1).
    pub slope_top_m: f64,
    /// Rise of each stair, metres (0.01–0.5; default 0.15: a crawler climbs ≤ 0.2 m, a wheeled
    /// robot ≤ 0.05 m).
    pub step_height_m: f64,
    /// Tread depth, metres (resolution–1; default 0.3).
    pub step_depth_m: f64,
    /// Number of steps (1–20; default 4).
    pub steps: u32,
    /// Length of the platform above the stairs, metres (1–5; default 2.5).
    pub platform_length_m: f64,
}

impl Default for CourseParams {
    fn default() -> Self {
        Self {
            resolution_m: 0.1,
            passage_width_m: 1.6,
            width_variation: 0.1,
            hall_width_m: 12.0,
            hall_depth_m: 10.0,
            slope_inclination_rad: 20f64.to_radians(),
            slope_run_m: 2.5,
            slope_top_m: 1.0,
            step_height_m: 0.15,
            step_depth_m: 0.3,
            steps: 4,
            platform_length_m: 2.5,
        }
    }
}

const RESOLUTION_M: RangeInclusive<f64> = 0.02..=0.25;
const PASSAGE_WIDTH_M: RangeInclusive<f64> = 1.0..=2.2;
const WIDTH_VARIATION: RangeInclusive<f64> = 0.0..=0.1;
const HALL_SIDE_M: RangeInclusive<f64> = 9.0..=14.0;
const SLOPE_INCLINATION_DEG: RangeInclusive<f64> = 1.0..=60.0;
const SLOPE_RUN_M: RangeInclusive<f64> = 0.5..=4.0;
const SLOPE_TOP_M: RangeInclusive<f64> = 0.0..=2.0;
const STEP_HEIGHT_M: RangeInclusive<f64> = 0.01..=0.5;
const STEP_DEPTH_MAX_M: f64 = 1.0;
const STEPS: RangeInclusive<u32> = 1..=20;
const PLATFORM_LENGTH_M: RangeInclusive<f64> = 1.0..=5.0;
/// Solid wall kept around the course, metres.
const MARGIN_M: f64 = 1.0;

/// Rounds to nanometres, so that sums of multiples of the resolution are written as 2.8 rather
/// than 2.8000000000000003.
fn tidy(v: f64) -> f64 {
    (v * 1e9).round() / 1e9
}

fn clamp(v: f64, r: &RangeInclusive<f64>) -> f64 {
    if v.is_finite() {
        v.clamp(*r.start(), *r.end())
    } else {
        *r.start()
    }
}

impl CourseParams {
    /// Reports the first parameter outside its range; `source` names where the parameters came
    /// from. [`generate_course`] clamps instead of failing.
    pub fn validate(&self, source: &Path) -> Result<()> {
        let degrees = self.slope_inclination_rad.to_degrees();
        let checks: [(&str, f64, RangeInclusive<f64>); 11] = [
            ("resolution_m", self.resolution_m, RESOLUTION_M),
            ("passage_width_m", self.passage_width_m, PASSAGE_WIDTH_M),
            ("width_variation", self.width_variation, WIDTH_VARIATION),
            ("hall_width_m", self.hall_width_m, HALL_SIDE_M),
            ("hall_depth_m", self.hall_depth_m, HALL_SIDE_M),
            (
                "slope_inclination_rad (in degrees)",
                degrees,
                SLOPE_INCLINATION_DEG,
            ),
            ("slope_run_m", self.slope_run_m, SLOPE_RUN_M),
            ("slope_top_m", self.slope_top_m, SLOPE_TOP_M),
            ("step_height_m", self.step_height_m, STEP_HEIGHT_M),
            (
                "step_depth_m",
                self.step_depth_m,
                self.resolution_m..=STEP_DEPTH_MAX_M,
            ),
            (
                "platform_length_m",
                self.platform_length_m,
                PLATFORM_LENGTH_M,
            ),
        ];
        for (field, v, range) in checks {
            if !range.contains(&v) {
                return Err(WorldError::invalid(
                    source,
                    field,
                    v,
                    format!("a value in {}..={}", range.start(), range.end()),
                ));
            }
        }
        if !STEPS.contains(&self.steps) {
            return Err(WorldError::invalid(
                source,
                "steps",
                self.steps,
                "1..=20 steps",
            ));
        }
        Ok(())
    }

    fn sanitized(&self) -> CourseParams {
        let resolution_m = clamp(self.resolution_m, &RESOLUTION_M);
        CourseParams {
            resolution_m,
            passage_width_m: clamp(self.passage_width_m, &PASSAGE_WIDTH_M),
            width_variation: clamp(self.width_variation, &WIDTH_VARIATION),
            hall_width_m: clamp(self.hall_width_m, &HALL_SIDE_M),
            hall_depth_m: clamp(self.hall_depth_m, &HALL_SIDE_M),
            slope_inclination_rad: clamp(
                self.slope_inclination_rad.to_degrees(),
                &SLOPE_INCLINATION_DEG,
            )
            .to_radians(),
            slope_run_m: clamp(self.slope_run_m, &SLOPE_RUN_M),
            slope_top_m: clamp(self.slope_top_m, &SLOPE_TOP_M),
            step_height_m: clamp(self.step_height_m, &STEP_HEIGHT_M),
            step_depth_m: clamp(self.step_depth_m, &(resolution_m..=STEP_DEPTH_MAX_M)),
            steps: self.steps.clamp(*STEPS.start(), *STEPS.end()),
            platform_length_m: clamp(self.platform_length_m, &PLATFORM_LENGTH_M),
        }
    }
}

/// Where everything lies, metres; see the module documentation.
struct Plan {
    res: f64,
    /// Passage width and half width.
    width: f64,
    half: f64,
    /// Centre lines: the main passage, the passage of T1 and T2, the hall's west exit.
    y_main: f64,
    y_upper: f64,
    y_west_exit: f64,
    x_start: f64,
    x_cross: f64,
    x_corner: f64,
    x_west: f64,
    y_dead_south: f64,
    y_dead_west: f64,
    hall: Rect,
    /// Foot of the up ramp, start of the top, start of the down ramp, end of the down ramp.
    slope_x: [f64; 4],
    stairs_x: f64,
    platform_x: f64,
    end_x: f64,
    width_m: f64,
    height_m: f64,
}

impl Plan {
    fn new(rng: &mut Pcg64Mcg, p: &CourseParams) -> Plan {
        let res = p.resolution_m;
        let snap = |v: f64| tidy((v / res).round() * res);
        let variation = p.width_variation;
        let jitter = if variation > 0.0 {
            rng.random_range(-variation..=variation)
        } else {
            0.0
        };
        let width = (snap(p.passage_width_m * (1.0 + jitter) / 2.0) * 2.0).max(2.0 * res);
        let half = width / 2.0;
        let hall_w = snap(p.hall_width_m + rng.random_range(-0.5..=0.5))
            .clamp(*HALL_SIDE_M.start(), *HALL_SIDE_M.end());
        let hall_d = snap(p.hall_depth_m + rng.random_range(-0.5..=0.5))
            .clamp(*HALL_SIDE_M.start(), *HALL_SIDE_M.end());
        let (y_main, y_upper, x_start, x_cross) = (5.0, 13.0, 2.0, 12.0);
        let y_dead_south = 1.8;
        let hall_y0 = 16.0;
        let hall_x0 = snap(x_cross - hall_w / 2.0);
        let hall = Rect::new(
            hall_x0,
            hall_y0,
            tidy(hall_x0 + hall_w),
            tidy(hall_y0 + hall_d),
        );
        let y_west_exit = snap(hall_y0 + rng.random_range(0.55..=0.75) * hall_d);
        let x_west = snap(hall_x0 - 3.0);
        let y_dead_west = snap(rng.random_range(9.0..=10.0));
        let slope_lead = snap(rng.random_range(1.0..=2.5));
        let run = snap(p.slope_run_m).max(res);
        let top = snap(p.slope_top_m);
        let a = snap(x_cross + half + slope_lead);
        let slope_x = [
            a,
            tidy(a + run),
            tidy(a + run + top),
            tidy(a + 2.0 * run + top),
        ];
        let x_corner = snap((slope_x[3] + 1.5 + half).max(26.0));
        let stairs_x = snap(x_corner + half + 1.5);
        let platform_x = tidy(stairs_x + f64::from(p.steps) * p.step_depth_m);
        let end_x = snap(platform_x + p.platform_length_m).max(platform_x + res);
        let width_m = ((end_x + MARGIN_M) / res).ceil() * res;
        let height_m = ((hall.max.y + MARGIN_M) / res).ceil() * res;
        Plan {
            res,
            width,
            half,
            y_main,
            y_upper,
            y_west_exit,
            x_start,
            x_cross,
            x_corner,
            x_west,
            y_dead_south,
            y_dead_west,
            hall,
            slope_x,
            stairs_x,
            platform_x,
            end_x,
            width_m,
            height_m,
        }
    }

    /// The rectangle of a passage between two centre-line points (one coordinate shared),
    /// extended by half a width on every side.
    fn passage(&self, a: Point2, b: Point2) -> Rect {
        let h = self.half;
        Rect::new(
            a.x.min(b.x) - h,
            a.y.min(b.y) - h,
            a.x.max(b.x) + h,
            a.y.max(b.y) + h,
        )
    }

    fn junctions(&self) -> Vec<Junction> {
        let j = |kind, x, y| Junction {
            kind,
            position: Point2::new(x, y),
        };
        vec![
            j(JunctionKind::DeadEnd, self.x_start, self.y_main),
            j(JunctionKind::Crossing, self.x_cross, self.y_main),
            j(JunctionKind::DeadEnd, self.x_cross, self.y_dead_south),
            j(JunctionKind::Corner, self.x_corner, self.y_main),
            j(JunctionKind::TJunction, self.x_cross, self.y_upper),
            j(JunctionKind::TJunction, self.x_corner, self.y_upper),
            j(
                JunctionKind::DeadEnd,
                tidy(self.end_x - self.half),
                self.y_upper,
            ),
            j(JunctionKind::Corner, self.x_west, self.y_west_exit),
            j(JunctionKind::DeadEnd, self.x_west, self.y_dead_west),
        ]
    }
}

/// Room ids of the course's semantic layer.
const HALL_ROOM: u16 = 1;
const PASSAGE_ROOM: u16 = 2;

/// Generates the test course (deterministic in `seed` and `params`; out-of-range parameters
/// are clamped, see [`CourseParams::validate`]).
pub fn generate_course(seed: u64, params: &CourseParams) -> Scene {
    let p = params.sanitized();
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let plan = Plan::new(&mut rng, &p);
    let res = plan.res;
    let geometry = GridGeometry::new(
        (plan.width_m / res).round() as u32,
        (plan.height_m / res).round() as u32,
        res,
        Point2::new(0.0, 0.0),
    );
    let mut scene = Scene::empty(format!("course-{seed}"), geometry);
    scene.provenance = Provenance {
        source: "course".into(),
        seed: Some(seed),
        detail: format!(
            "passage_width_m={:.2} slope_inclination_deg={:.1} step_height_m={} step_depth_m={} steps={}",
            plan.width,
            p.slope_inclination_rad.to_degrees(),
            p.step_height_m,
            p.step_depth_m,
            p.steps
        ),
    };
    scene.obstacle = Grid::filled(geometry, obstacle::WALL);

    let pt = Point2::new;
    let passages = [
        plan.passage(
            pt(plan.x_start, plan.y_main),
            pt(plan.x_corner, plan.y_main),
        ),
        plan.passage(
            pt(plan.x_cross, plan.y_dead_south),
            pt(plan.x_cross, plan.hall.min.y),
        ),
        plan.passage(
            pt(plan.x_corner, plan.y_main),
            pt(plan.x_corner, plan.y_upper),
        ),
        plan.passage(
            pt(plan.x_cross, plan.y_upper),
            pt(plan.end_x - plan.half, plan.y_upper),
        ),
        plan.passage(
            pt(plan.x_west, plan.y_west_exit),
            pt(plan.hall.min.x, plan.y_west_exit),
        ),
        plan.passage(
            pt(plan.x_west, plan.y_dead_west),
            pt(plan.x_west, plan.y_west_exit),
        ),
    ];
    for rect in passages {
        fill_rect(&mut scene.obstacle, rect, obstacle::NONE);
        fill_rect(&mut scene.room_id, rect, PASSAGE_ROOM);
    }
    fill_rect(&mut scene.obstacle, plan.hall, obstacle::NONE);
    fill_rect(&mut scene.room_id, plan.hall, HALL_ROOM);

    scene.ground_truth.features = shape_terrain(&mut scene, &plan, &p);
    scene
        .ground_truth
        .features
        .insert(0, TerrainFeature::Hall { region: plan.hall });
    scene.ground_truth.junctions = plan.junctions();

    let hall_label = RoomLabel::for_room_area(plan.hall.area(), RoomSizeThresholds::default());
    scene.rooms = vec![
        Room {
            id: HALL_ROOM,
            label: hall_label,
            door_ids: vec![1, 2],
            intersecting_corridors: vec![],
        },
        Room {
            id: PASSAGE_ROOM,
            label: RoomLabel::Corridor,
            door_ids: vec![1, 2],
            intersecting_corridors: vec![],
        },
    ];
    scene.doors = vec![
        Door {
            id: 1,
            position: pt(plan.x_cross, plan.hall.min.y),
            width_m: plan.width,
            rooms: [PASSAGE_ROOM, HALL_ROOM],
        },
        Door {
            id: 2,
            position: pt(plan.hall.min.x, plan.y_west_exit),
            width_m: plan.width,
            rooms: [PASSAGE_ROOM, HALL_ROOM],
        },
    ];
    // Start at the west terminal end of the main passage, facing along it (east).
    scene.start_poses = vec![Pose2::new(plan.x_start, plan.y_main, 0.0)];
    scene
}

/// Heights of the slope, the stairs and the platform; returns their features.
fn shape_terrain(scene: &mut Scene, plan: &Plan, p: &CourseParams) -> Vec<TerrainFeature> {
    let (y0, y1) = (tidy(plan.y_main - plan.half), tidy(plan.y_main + plan.half));
    let gradient = p.slope_inclination_rad.tan();
    let [up, top, down, end] = plan.slope_x;
    let rise = gradient * (top - up);
    let up_ramp = Rect::new(up, y0, top, y1);
    let plateau = Rect::new(top, y0, down, y1);
    let down_ramp = Rect::new(down, y0, end, y1);
    shape_floor(scene, up_ramp, |c| (gradient * (c.x - up)) as f32);
    shape_floor(scene, plateau, |_| rise as f32);
    shape_floor(scene, down_ramp, |c| (gradient * (end - c.x)) as f32);

    let (s0, s1) = (
        tidy(plan.y_upper - plan.half),
        tidy(plan.y_upper + plan.half),
    );
    let (h, d, n) = (p.step_height_m, p.step_depth_m, p.steps);
    let stairs = Rect::new(plan.stairs_x, s0, plan.platform_x, s1);
    shape_floor(scene, stairs, |c| {
        let step = ((c.x - plan.stairs_x) / d).floor() + 1.0;
        (step.clamp(1.0, f64::from(n)) * h) as f32
    });
    let platform = Rect::new(plan.platform_x, s0, plan.end_x, s1);
    shape_floor(scene, platform, |_| (f64::from(n) * h) as f32);
    vec![
        TerrainFeature::Slope {
            region: up_ramp,
            inclination_rad: p.slope_inclination_rad,
            uphill_rad: 0.0,
        },
        TerrainFeature::Slope {
            region: down_ramp,
            inclination_rad: p.slope_inclination_rad,
            uphill_rad: std::f64::consts::PI,
        },
        TerrainFeature::Stairs {
            region: stairs,
            step_height_m: h,
            step_depth_m: d,
            steps: n,
            uphill_rad: 0.0,
        },
    ]
}

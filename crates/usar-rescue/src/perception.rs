//! What the robot senses from a cell facing one of the four headings (paper 000 §IV-A, §VI):
//!
//! - the **front 3-D depth array D_xy** ([`usar_sim::sensors::read_depth`]) is turned into
//!   points; those falling in the cell ahead are fitted by a least-squares plane
//!   ([`LeastSquaresPlane`]); slope, roughness and height against the robot's reference floor
//!   classify the cell as open, climbable or non-climbable with the cell view's thresholds
//!   ([`CellViewParams`]). A drop — "an abrupt increase in the depth values" (Fig. 4(c)) — shows
//!   as points far below the floor or as beams without return, and is non-climbable;
//! - the **infrared** sensors on the sides and back mark neighbouring cells where something is
//!   closer than one cell (unknown obstacles);
//! - the **thermal camera** gives heat regions with h (human band) and size s; the victim
//!   probability is [`victim_probability`].
//!
//! A reading depends only on (cell, heading): it is taken once per run, the first time the
//! robot stands there (noise from the run's perception stream), and cached; or all at once
//! beforehand ([`Perception::sense_all`]).

use crate::agent::{CellReading, HeatReading};
use crate::exploration::Direction;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use usar_sim::sensors::{
    DepthImage, DepthSpec, HeatTruth, InfraredReading, InfraredSpec, SensingWorld, ThermalSpec,
    read_depth, read_infrared, read_thermal,
};
use usar_world::cellview::{CellClass, CellView, CellViewParams, LeastSquaresPlane};
use usar_world::{Cell, Point2, Pose2, Rect, Scene};

/// Victim probability p = f(h, s) (paper 000 §IV-A-3): 0 without a human heat signature,
/// otherwise `s / (s + s₀)`, rising with the size of the warm region. With s₀ = 0.08 m² a
/// region of 0.04 m² (a mostly buried person) gives p = 0.33 — uncertain, handed to the
/// operator rather than dismissed — and one of 0.19 m² or more gives p > 0.7 (tagged
/// automatically).
pub fn victim_probability(human_signature: bool, size_m2: f64) -> f64 {
    if !human_signature || size_m2 <= 0.0 {
        return 0.0;
    }
    size_m2 / (size_m2 + HALF_SIZE_M2)
}

/// s₀ of [`victim_probability`], m².
pub const HALF_SIZE_M2: f64 = 0.08;
/// Above this the robot tags by itself (§IV-A-3).
pub const TAG_THRESHOLD: f64 = 0.7;
/// Below this the robot dismisses the heat region (§IV-A-3).
pub const DISMISS_THRESHOLD: f64 = 0.3;

/// Fewer points of D_xy than this inside the cell ahead read as a drop.
const MIN_POINTS: u32 = 6;

/// A level cell returning fewer than this share of the points a level floor at the robot's own
/// height would return is hidden behind a face and non-climbable. On the rubble arenas a
/// partly hidden open floor returns ≥ 0.44 of them, a floor seen past a slab ≤ 0.3.
const OCCLUDED_SHARE: f64 = 0.4;

/// How far below `climbable_max_height_m` the visible top of a pile must stay for the cell to
/// read as climbable. On the rubble arenas the visible tops of climbable cells reach 0.28 m
/// and those of non-climbable cells start at 0.30 m (the rest of the pile hides behind its
/// near face), against the 0.35 m limit.
const VISIBLE_TOP_MARGIN_M: f64 = 0.06;

/// The cached reading of one (cell, heading).
#[derive(Clone, Debug, Default)]
struct Reading {
    /// Class of the cell ahead from D_xy (`None`: ahead lies outside the arena).
    front: Option<CellClass>,
    /// Infrared hits by neighbour: bit k set for [`NEIGHBOURS`]\[k\] relative to the heading.
    infrared: u8,
    heat: std::ops::Range<u32>,
}

/// Neighbours the infrared sensors look at, relative to the heading (forward, left):
/// left, back-left, back, back-right, right — the default five sensor directions.
pub const INFRARED_NEIGHBOURS: [(i32, i32); 5] = [(0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1)];

/// The infrared sensors that see something closer than `reach_m` (a cell), as a mask: bit k
/// for [`INFRARED_NEIGHBOURS`]\[k\].
pub fn infrared_mask(reading: &InfraredReading, reach_m: f64) -> u8 {
    reading
        .ranges_m
        .iter()
        .take(INFRARED_NEIGHBOURS.len())
        .enumerate()
        .filter(|(_, range)| range.is_some_and(|d| d < reach_m))
        .fold(0, |mask, (k, _)| mask | 1 << k)
}

/// Sensors and the per-scene cache of their readings.
#[derive(Clone)]
pub struct Perception {
    world: SensingWorld,
    depth: DepthSpec,
    infrared: InfraredSpec,
    thermal: ThermalSpec,
    params: CellViewParams,
    /// Floor height of the robot's global frame (its start cell), metres.
    reference_floor_m: f64,
    cols: i32,
    readings: Vec<Option<Reading>>,
    heat: Vec<HeatReading>,
    rng: Pcg64Mcg,
}

impl Perception {
    /// Sensors on `scene` with default specs; `start` is the cell whose floor is the reference.
    pub fn new(scene: &Scene, view: &CellView, start: Cell, seed: u64) -> Self {
        let reference_floor_m = view
            .terrain_at(start)
            .map_or(view.reference_floor_m, |t| t.median_height_m);
        Self {
            world: SensingWorld::new(scene),
            depth: DepthSpec::default(),
            infrared: InfraredSpec::default(),
            thermal: ThermalSpec::default(),
            params: CellViewParams::default(),
            reference_floor_m,
            cols: view.cols as i32,
            readings: vec![None; view.classes.len() * 4],
            heat: Vec::new(),
            rng: Pcg64Mcg::seed_from_u64(seed),
        }
    }

    /// Takes the reading of every cell a robot can stand on (passable terrain) and every
    /// heading now, in a fixed order, so that a run reads only the cache. Training prepares
    /// its scenes this way, in parallel and ahead of the (sequential) learning.
    pub fn sense_all(&mut self, scene: &Scene, view: &CellView) {
        for (i, class) in view.terrain_classes.iter().enumerate() {
            if !class.is_passable_terrain(true) {
                continue;
            }
            let cell = view.geometry.cell_of_index(i);
            for heading in Direction::ALL {
                self.reading(scene, view, cell, heading);
            }
        }
    }

    fn reading(
        &mut self,
        scene: &Scene,
        view: &CellView,
        cell: Cell,
        heading: Direction,
    ) -> &Reading {
        let key = ((cell.row * self.cols + cell.col) as usize) * 4 + heading.index();
        if self.readings[key].is_none() {
            let r = self.sense(scene, view, cell, heading);
            self.readings[key] = Some(r);
        }
        self.readings[key].as_ref().expect("just filled")
    }

    /// Everything the sensors read from `cell` facing `heading`.
    pub fn read(
        &mut self,
        scene: &Scene,
        view: &CellView,
        cell: Cell,
        heading: Direction,
    ) -> CellReading<'_, HeatTruth> {
        let Reading {
            front,
            infrared,
            heat,
        } = self.reading(scene, view, cell, heading).clone();
        CellReading {
            front,
            infrared,
            heat: &self.heat[heat.start as usize..heat.end as usize],
        }
    }

    /// The class of the cell ahead as D_xy shows it.
    pub fn front(
        &mut self,
        scene: &Scene,
        view: &CellView,
        cell: Cell,
        heading: Direction,
    ) -> Option<CellClass> {
        self.reading(scene, view, cell, heading).front
    }

    /// Infrared hits as a bit mask over [`INFRARED_NEIGHBOURS`].
    pub fn infrared(
        &mut self,
        scene: &Scene,
        view: &CellView,
        cell: Cell,
        heading: Direction,
    ) -> u8 {
        self.reading(scene, view, cell, heading).infrared
    }

    /// Heat regions seen.
    pub fn heat(
        &mut self,
        scene: &Scene,
        view: &CellView,
        cell: Cell,
        heading: Direction,
    ) -> &[HeatReading] {
        let range = self.reading(scene, view, cell, heading).heat.clone();
        &self.heat[range.start as usize..range.end as usize]
    }

    fn pose(view: &CellView, cell: Cell, heading: Direction) -> Pose2 {
        let c = view.cell_center(cell);
        Pose2::new(
            c.x,
            c.y,
            heading.index() as f64 * std::f64::consts::FRAC_PI_2,
        )
    }

    fn sense(&mut self, scene: &Scene, view: &CellView, cell: Cell, heading: Direction) -> Reading {
        let pose = Self::pose(view, cell, heading);
        let floor = view
            .terrain_at(cell)
            .map_or(self.reference_floor_m, |t| t.median_height_m);
        let (dc, dr) = heading.step();
        let ahead = Cell::new(cell.col + dc, cell.row + dr);
        let front = view
            .index(ahead)
            .map(|_| self.classify_ahead(view, pose, floor, ahead));
        let reading = read_infrared(&self.infrared, &self.world, pose, floor, &mut self.rng);
        let infrared = infrared_mask(&reading, view.cell_size_m);
        let start = self.heat.len() as u32;
        for d in read_thermal(
            &self.thermal,
            scene,
            &self.world,
            pose,
            floor,
            &mut self.rng,
        ) {
            let Some(c) = view.cell_of(d.position(pose)) else {
                continue;
            };
            self.heat.push(HeatReading {
                cell: (c.col, c.row),
                human_signature: d.human_signature,
                size_m2: d.size_m2,
                source: d.truth,
            });
        }
        Reading {
            front,
            infrared,
            heat: start..self.heat.len() as u32,
        }
    }

    /// Rubble classification of §IV-A-4 of the cell `ahead` from one D_xy frame taken now.
    fn classify_ahead(
        &mut self,
        view: &CellView,
        pose: Pose2,
        floor_m: f64,
        ahead: Cell,
    ) -> CellClass {
        let image = read_depth(&self.depth, &self.world, pose, floor_m, &mut self.rng);
        let classifier = RubbleClassifier {
            params: self.params,
            reference_floor_m: self.reference_floor_m,
            // Half a fine cell inside the border: a beam stopped by the side of a neighbouring
            // pile meets it on the border line, and belongs to that neighbour.
            margin_m: 0.5 * self.world.geometry().resolution_m,
            max_range_m: self.depth.max_range_m,
        };
        classifier.classify(
            &image,
            pose,
            floor_m,
            view.cell_rect(ahead),
            view.cell_center(ahead),
        )
    }
}

/// Paper 000 §IV-A-4's rubble classification of one cell from a D_xy frame: a least-squares
/// plane through the points falling in the cell, its slope, roughness and height against the
/// robot's reference floor.
#[derive(Clone, Debug, PartialEq)]
pub struct RubbleClassifier {
    /// The thresholds of the classes.
    pub params: CellViewParams,
    /// Floor height of the robot's global frame (where it started), metres.
    pub reference_floor_m: f64,
    /// Points this close to the cell's border are left out (they may belong to a neighbour's
    /// side), metres.
    pub margin_m: f64,
    /// The depth array's range, metres.
    pub max_range_m: f64,
}

impl RubbleClassifier {
    /// How many beams of `image` would meet a level floor at height `floor_m` (the robot's own) inside
    /// `rect` (shrunk by `margin`) within the sensor's range.
    fn expected_floor_points(
        &self,
        image: &DepthImage,
        pose: Pose2,
        rect: usar_world::Rect,
        margin: f64,
        floor_m: f64,
    ) -> u32 {
        let drop = image.sensor_z_m - floor_m;
        if drop <= 0.0 {
            return 0;
        }
        let mut n = 0;
        for &pitch in &image.row_pitch_down_rad {
            if pitch <= 0.0 || drop / pitch.sin() > self.max_range_m {
                continue;
            }
            let horizontal = drop / pitch.tan();
            for &yaw in &image.col_yaw_rad {
                let (s, c) = (pose.theta + yaw).sin_cos();
                let (x, y) = (pose.x + horizontal * c, pose.y + horizontal * s);
                if x >= rect.min.x + margin
                    && x < rect.max.x - margin
                    && y >= rect.min.y + margin
                    && y < rect.max.y - margin
                {
                    n += 1;
                }
            }
        }
        n
    }

    /// The class of the cell `rect` (centre `centre`) in `image`, taken at `pose` by a robot
    /// standing on a floor at `floor_m`.
    pub fn classify(
        &self,
        image: &DepthImage,
        pose: Pose2,
        floor_m: f64,
        rect: Rect,
        centre: Point2,
    ) -> CellClass {
        let margin = self.margin_m;
        let (s, c) = pose.theta.sin_cos();
        let mut plane = LeastSquaresPlane::new();
        let (mut lowest, mut highest) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut heights: Vec<f64> = Vec::with_capacity(image.depth_m.len());
        for row in 0..image.rows {
            for col in 0..image.cols {
                let Some([bx, by, bz]) = image.point_body(row, col) else {
                    continue;
                };
                let x = pose.x + c * bx - s * by;
                let y = pose.y + s * bx + c * by;
                if !(x >= rect.min.x + margin
                    && x < rect.max.x - margin
                    && y >= rect.min.y + margin
                    && y < rect.max.y - margin)
                {
                    continue;
                }
                let z = image.sensor_z_m + bz;
                plane.push(x - centre.x, y - centre.y, z);
                lowest = lowest.min(z);
                highest = highest.max(z);
                heights.push(z);
            }
        }
        let p = &self.params;
        let Some(fit) = plane.fit().filter(|f| f.points >= MIN_POINTS) else {
            // The beams that should land in the cell went further (or nowhere): the depth
            // values jump past the cell, the floor falls away (Fig. 4(c)).
            return CellClass::Drop;
        };
        heights.sort_by(f64::total_cmp);
        let median = heights[heights.len() / 2];
        let reference = self.reference_floor_m;
        if median < reference - p.drop_depth_m {
            return CellClass::Drop;
        }
        let deviation = (highest - reference).max(reference - lowest);
        // D_xy sees the near part of a pile; its far part and top may hide behind the near
        // face. A visible top within `VISIBLE_TOP_MARGIN_M` of the climbable limit is read as
        // non-climbable.
        if deviation > p.climbable_max_height_m - VISIBLE_TOP_MARGIN_M {
            return CellClass::NonClimbable;
        }
        // Beams that a level floor would return from inside the cell. Far fewer returns from
        // a level surface mean that a face (a slab, a steep pile) stopped the beams before the
        // cell's floor: the floor seen is a sliver, and the cell is non-climbable. Rubble that
        // is low enough to climb shadows part of its own cell, so it is classified by its fit.
        let expected = self.expected_floor_points(image, pose, rect, margin, floor_m);
        if deviation <= p.open_max_height_m
            && f64::from(fit.points) < OCCLUDED_SHARE * expected as f64
        {
            return CellClass::NonClimbable;
        }
        p.terrain_class(fit.slope_rad, fit.roughness_m, deviation)
    }
}

use proptest::prelude::*;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;
use usar_sim::sensors::{LaserModel, LaserSpec, SensingWorld, ThermalSpec, read_thermal};
use usar_sim::{RobotSpec, SimConfig, Simulation};
use usar_world::{Cell, GridGeometry, GridRay, HeatSource, Point2, Pose2, Scene, Victim, obstacle};

fn random_scene(walls: &[(i32, i32)]) -> Scene {
    let g = GridGeometry::new(40, 40, 0.1, Point2::new(0.0, 0.0));
    let mut s = Scene::empty("random", g);
    for &(c, r) in walls {
        s.obstacle[Cell::new(c, r)] = obstacle::WALL;
    }
    s
}

proptest! {
    /// A laser ray never passes through an occupied cell: every point of a beam before its
    /// range lies on a free cell, and a returned range ends at an occupied one.
    #[test]
    fn laser_ray_never_passes_through_an_occupied_cell(
        walls in proptest::collection::vec((0i32..40, 0i32..40), 0..200),
        x in 0.05f64..3.95, y in 0.05f64..3.95, theta in -3.2f64..3.2,
    ) {
        let scene = random_scene(&walls);
        let g = *scene.geometry();
        prop_assume!(!scene.is_obstacle(g.world_to_cell(Point2::new(x, y))));
        let world = SensingWorld::new(&scene);
        let spec = LaserSpec { range_noise_sd_m: 0.0, max_range_m: 3.0, ..LaserSpec::default() };
        let scan = LaserModel::new(spec).scan(&world, Pose2::new(x, y, theta), 0.0, &mut Pcg64Mcg::seed_from_u64(1));
        for (i, &r) in scan.ranges_m.iter().enumerate() {
            let a = scan.beam_angle(i);
            let reach = if r.is_finite() { f64::from(r) } else { 3.0 };
            for k in 0..200 {
                let d = reach * k as f64 / 200.0;
                let p = Point2::new(x, y).offset(a, d);
                let cell = g.world_to_cell(p);
                prop_assert!(!g.contains(cell) || !scene.is_obstacle(cell), "beam {i} crosses occupied {cell:?} at {d} < {r}");
            }
            if r.is_finite() {
                // The range ends on an occupied cell: the beam's interval inside some occupied
                // cell near the end point reaches the range, within the f32 rounding of the
                // range (an ulp is 1.2e-7 m at 1.5 m, while a beam clipping a cell's corner may
                // cross it in 3e-8 m: walls = [(6, 9)], x = 1.9624…, y = 0.8042…, θ = 3.1936…).
                let tol = 2.0 * f64::from(f32::EPSILON) * f64::from(r) + 1e-12;
                let end = g.world_to_cell(Point2::new(x, y).offset(a, f64::from(r)));
                let hits = (-1..=1).flat_map(|dc| (-1..=1).map(move |dr| Cell::new(end.col + dc, end.row + dr)))
                    .filter(|&c| g.contains(c) && scene.is_obstacle(c))
                    .filter_map(|c| beam_interval_in_cell(&g, c, Point2::new(x, y), a))
                    .any(|(t_in, t_out)| t_in <= f64::from(r) + tol && t_out >= f64::from(r) - tol);
                prop_assert!(hits, "beam {i} ends in free space at {r}");
            }
        }
    }
}

/// Where the beam from `origin` at `angle` is inside `cell`: (entry, exit) distances, slab method.
fn beam_interval_in_cell(
    g: &GridGeometry,
    cell: Cell,
    origin: Point2,
    angle: f64,
) -> Option<(f64, f64)> {
    let mid = g.cell_center(cell);
    let half = g.resolution_m / 2.0;
    let (s, c) = angle.sin_cos();
    let (mut t_in, mut t_out) = (0.0f64, f64::INFINITY);
    for (o, d, mid) in [(origin.x, c, mid.x), (origin.y, s, mid.y)] {
        let (a, b) = (mid - half, mid + half);
        if d.abs() < 1e-15 {
            if o < a || o > b {
                return None;
            }
            continue;
        }
        let (t0, t1) = ((a - o) / d, (b - o) / d);
        t_in = t_in.max(t0.min(t1));
        t_out = t_out.min(t0.max(t1));
    }
    (t_in <= t_out).then_some((t_in, t_out))
}

/// The horizontal cast as first written: blocking heights read cell by cell along `advance`.
fn reference_cast(
    scene: &Scene,
    origin: Point2,
    angle: f64,
    z_m: f32,
    max_range_m: f64,
) -> Option<f64> {
    let g = scene.geometry();
    let (s, c) = angle.sin_cos();
    let mut ray = GridRay::new(g, origin, c, s);
    let max_t = max_range_m / g.resolution_m;
    loop {
        let i = ray.index_in(g.width, g.height)?;
        let cell = g.cell_of_index(i);
        let height = if scene.is_obstacle(cell) {
            f32::INFINITY
        } else {
            scene.floor_height_m[cell]
        };
        if height >= z_m {
            return Some(ray.t_entry * g.resolution_m);
        }
        ray.advance();
        if ray.t_entry > max_t {
            return None;
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// The fast cast (bitmaps of rising cells and obstacles, fixed-point walk) finds what the
    /// reference finds, with raised floor, sunken floor and beams above, between and below the
    /// floor heights.
    #[test]
    fn horizontal_cast_matches_the_reference_cast(
        walls in proptest::collection::vec((0i32..40, 0i32..40), 0..60),
        steps in proptest::collection::vec((0i32..40, 0i32..40, -0.4f32..0.6), 0..80),
        x in -0.3f64..4.3, y in -0.3f64..4.3, z in -0.5f32..0.8, max_range in 0.0f64..6.0,
    ) {
        let mut scene = random_scene(&walls);
        for &(c, r, h) in &steps {
            scene.floor_height_m[Cell::new(c, r)] = h;
        }
        let world = SensingWorld::new(&scene);
        for k in 0..36 {
            let angle = -3.1 + k as f64 * 0.1723;
            let (s, c) = angle.sin_cos();
            let fast = world.cast_horizontal(Point2::new(x, y), c, s, z, max_range);
            let slow = reference_cast(&scene, Point2::new(x, y), angle, z, max_range);
            match (fast, slow) {
                (None, None) => {}
                (Some(a), Some(b)) => prop_assert!((a - b).abs() < 1e-6, "beam {k}: {a} vs {b}"),
                ends => prop_assert!(false, "beam {k}: {ends:?}"),
            }
        }
    }
}

#[test]
fn a_beam_clipping_a_wall_corner_ends_inside_that_wall_cell() {
    // Beam 234 crosses cell (21, 26) over less than 1e-6 m near its corner (22, 27).
    let scene = random_scene(&[(21, 26)]);
    let world = SensingWorld::new(&scene);
    let (x, y, theta) = (2.322509504547689, 2.5417432799339856, 1.2870802101779544);
    let spec = LaserSpec {
        range_noise_sd_m: 0.0,
        max_range_m: 3.0,
        ..LaserSpec::default()
    };
    let scan = LaserModel::new(spec).scan(
        &world,
        Pose2::new(x, y, theta),
        0.0,
        &mut Pcg64Mcg::seed_from_u64(1),
    );
    let r = f64::from(scan.ranges_m[234]);
    let a = scan.beam_angle(234);
    let cell_at = |d: f64| {
        scene
            .geometry()
            .world_to_cell(Point2::new(x, y).offset(a, d))
    };
    assert_eq!(cell_at(r + 3e-8), Cell::new(21, 26));
    assert_eq!(cell_at(r - 1e-6), Cell::new(22, 26));
}

#[test]
fn same_seed_gives_the_same_noisy_scan() {
    let scene = Arc::new(random_scene(&[(30, 10), (10, 30)]));
    let scan = |seed| {
        let mut sim = Simulation::new(scene.clone(), SimConfig::default(), seed);
        let id = sim
            .add_robot(RobotSpec::crawler(), Pose2::new(2.0, 2.0, 0.3))
            .unwrap();
        let mut s = Default::default();
        sim.scan_laser(id, &mut s);
        s
    };
    assert_eq!(scan(5), scan(5));
    assert_ne!(scan(5), scan(6));
}

#[test]
fn thermal_camera_sees_victims_in_view_but_not_behind_walls_or_outside_the_band() {
    let mut scene = random_scene(&[]);
    for row in 0..40 {
        scene.obstacle[Cell::new(30, row)] = obstacle::WALL;
    }
    let victim = |id, x: f64| Victim {
        id,
        position: Point2::new(x, 2.0),
        heat_c: 34.0,
        visible_size_m2: 0.5,
        buried_fraction: 0.2,
    };
    scene.victims = vec![victim(1, 2.5), victim(2, 3.5)];
    scene.heat_sources = vec![HeatSource {
        id: 1,
        position: Point2::new(2.0, 2.4),
        heat_c: 200.0,
        size_m2: 0.3,
        kind: "fire".into(),
    }];
    let world = SensingWorld::new(&scene);
    let spec = ThermalSpec {
        temperature_noise_sd_c: 0.0,
        size_noise_fraction: 0.0,
        ..ThermalSpec::default()
    };
    let seen = read_thermal(
        &spec,
        &scene,
        &world,
        Pose2::new(1.0, 2.0, 0.0),
        0.0,
        &mut Pcg64Mcg::seed_from_u64(1),
    );
    // Victim 1 in view; victim 2 behind the wall at x = 3.0; the fire in view but too hot.
    assert_eq!(seen.len(), 2, "{seen:?}");
    assert!(seen[0].human_signature && (seen[0].size_m2 - 0.4).abs() < 1e-9);
    assert!(
        (seen[0]
            .position(Pose2::new(1.0, 2.0, 0.0))
            .distance(Point2::new(2.5, 2.0)))
            < 1e-9
    );
    assert!(!seen[1].human_signature);
    // Facing away, nothing is seen.
    let behind = read_thermal(
        &spec,
        &scene,
        &world,
        Pose2::new(1.0, 2.0, std::f64::consts::PI),
        0.0,
        &mut Pcg64Mcg::seed_from_u64(1),
    );
    assert!(behind.is_empty());
}

#[test]
fn infrared_and_depth_see_the_wall_beside_and_ahead() {
    let mut scene = random_scene(&[]);
    for col in 0..40 {
        scene.obstacle[Cell::new(col, 25)] = obstacle::WALL;
    }
    let scene = Arc::new(scene);
    let mut sim = Simulation::new(scene, SimConfig::default(), 3);
    // Facing east, the wall at y = 2.5 is 0.5 m to the left.
    let id = sim
        .add_robot(RobotSpec::crawler(), Pose2::new(2.0, 2.0, 0.0))
        .unwrap();
    let ir = sim.read_infrared(id);
    let left = ir.ranges_m[0].expect("wall on the left");
    assert!((left - 0.5).abs() < 0.05, "{left}");
    assert!(ir.ranges_m[4].is_none(), "nothing on the right");
    // Facing north the depth array sees the wall: the top rows return short ranges.
    let id2 = sim
        .add_robot(
            RobotSpec::crawler(),
            Pose2::new(1.0, 1.6, std::f64::consts::FRAC_PI_2),
        )
        .unwrap();
    let depth = sim.read_depth(id2);
    let top = depth.point_body(0, depth.cols / 2).expect("a return");
    assert!((top[0] - 0.9).abs() < 0.05, "wall 0.9 m ahead, got {top:?}");
}

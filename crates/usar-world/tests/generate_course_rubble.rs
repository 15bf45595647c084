//! The rubble arenas of paper 000 §VI and the test course of paper 004 Fig. 15.

use std::collections::BTreeSet;
use std::path::Path;
use usar_world::cellview::{CellClass, CellView, CellViewParams, LeastSquaresPlane};
use usar_world::generate::{
    CourseParams, RubbleParams, RubbleStyle, generate_course, generate_rubble,
};
use usar_world::{
    Cell, JunctionKind, Point2, Rect, Scene, TerrainFeature, obstacle, scene_from_json,
    scene_to_json,
};

const SEEDS: [u64; 6] = [0, 1, 2, 17, 99, 2024];

fn rubble(style: RubbleStyle, seed: u64) -> Scene {
    generate_rubble(seed, &RubbleParams::with_style(style))
}

fn view(scene: &Scene) -> CellView {
    CellView::from_scene(scene, &CellViewParams::default())
}

/// The class each coarse cell was painted to be, from the ground-truth features.
fn intended_classes(scene: &Scene, view: &CellView) -> Vec<CellClass> {
    let mut classes = vec![CellClass::Open; view.classes.len()];
    for f in &scene.ground_truth.features {
        let (region, class) = match f {
            TerrainFeature::Rubble {
                region,
                climbable: true,
                ..
            } => (region, CellClass::Climbable),
            TerrainFeature::Rubble {
                region,
                climbable: false,
                ..
            } => (region, CellClass::NonClimbable),
            TerrainFeature::Drop { region, .. } => (region, CellClass::Drop),
            other => panic!("unexpected feature in a rubble arena: {other:?}"),
        };
        let cell = view
            .cell_of(region.center())
            .expect("feature inside the arena");
        assert!(
            (region.width() - view.cell_size_m).abs() < 1e-9,
            "a feature covers exactly one coarse cell"
        );
        classes[view.index(cell).unwrap()] = class;
    }
    classes
}

fn coarse_cell(view: &CellView, p: Point2) -> Cell {
    view.cell_of(p).expect("point inside the arena")
}

#[test]
fn rubble_same_seed_gives_identical_file_and_different_seeds_differ() {
    for style in RubbleStyle::ALL {
        let a = scene_to_json(&rubble(style, 7));
        let b = scene_to_json(&rubble(style, 7));
        assert!(a == b, "{style}: same seed, different files");
        let c = scene_to_json(&rubble(style, 8));
        assert!(a != c, "{style}: seeds 7 and 8 gave the same arena");
    }
}

#[test]
fn rubble_round_trips_through_the_scene_file() {
    for style in RubbleStyle::ALL {
        let scene = rubble(style, 3);
        let back = scene_from_json(&scene_to_json(&scene), Path::new("rubble.json"))
            .unwrap_or_else(|e| panic!("{style}: {e}"));
        assert_eq!(back, scene);
    }
}

#[test]
fn rubble_has_20_by_20_coarse_cells_of_0_84_m2() {
    let scene = rubble(RubbleStyle::Random, 1);
    let side = scene
        .coarse_cell_m
        .expect("rubble arenas define their coarse cell");
    assert!((side * side - 0.84).abs() < 1e-12);
    let view = view(&scene);
    assert_eq!((view.cols, view.rows), (20, 20));
    assert!((view.cell_size_m * view.cell_size_m - 0.84).abs() < 1e-12);
    // Coarse cells align with fine cells: 10 per side, none of them wall.
    assert!((scene.geometry().resolution_m * 10.0 - side).abs() < 1e-12);
    assert!(view.terrain.iter().all(|t| t.fine_cells == 100));
    assert!(view.geometry.origin.distance(Point2::new(0.0, 0.0)) < 1e-9);
    // 336 m² as in the paper.
    assert!((400.0 * side * side - 336.0).abs() < 1e-9);
}

#[test]
fn rubble_cell_view_classes_match_the_intended_features() {
    for style in RubbleStyle::ALL {
        for seed in SEEDS {
            let scene = rubble(style, seed);
            let view = view(&scene);
            let intended = intended_classes(&scene, &view);
            for (i, (&want, &got)) in intended.iter().zip(&view.terrain_classes).enumerate() {
                let c = view.geometry.cell_of_index(i);
                assert_eq!(
                    got, want,
                    "{style} seed {seed}: cell ({}, {}) measured {:?}",
                    c.col, c.row, view.terrain[i]
                );
            }
            assert!(
                view.reference_floor_m.abs() < 0.01,
                "reference floor {}",
                view.reference_floor_m
            );
        }
    }
}

#[test]
fn rubble_class_shares_stay_within_the_style_ranges() {
    for style in RubbleStyle::ALL {
        let shares = style.class_shares();
        for seed in SEEDS {
            let view = view(&rubble(style, seed));
            let share =
                |class| view.terrain_classes.iter().filter(|&&c| c == class).count() as f64 / 400.0;
            let nc = share(CellClass::NonClimbable);
            let cl = share(CellClass::Climbable);
            let dr = share(CellClass::Drop);
            assert!(
                shares.non_climbable.contains(&nc),
                "{style} seed {seed}: non-climbable {nc}"
            );
            assert!(
                shares.climbable.contains(&cl),
                "{style} seed {seed}: climbable {cl}"
            );
            assert!(shares.drop.contains(&dr), "{style} seed {seed}: drop {dr}");
        }
    }
    // The styles differ as paper 000 describes them.
    let a = RubbleStyle::SceneA.class_shares();
    let b = RubbleStyle::SceneB.class_shares();
    let c = RubbleStyle::SceneC.class_shares();
    assert!(a.climbable.start() > c.climbable.end() && a.climbable.start() > b.climbable.end());
    assert!(c.non_climbable.end() > a.non_climbable.end());
    assert!(b.non_climbable.end() <= a.non_climbable.start());
}

#[test]
fn rubble_victims_are_7_or_8_warm_and_reachable_with_climbing() {
    for style in RubbleStyle::ALL {
        for seed in SEEDS {
            let scene = rubble(style, seed);
            let view = view(&scene);
            assert!(
                (7..=8).contains(&scene.victims.len()),
                "{style} seed {seed}: {}",
                scene.victims.len()
            );
            let start = coarse_cell(&view, scene.start_poses[0].position());
            let reach = view.reachable(start, true);
            let mut cells = BTreeSet::new();
            for v in &scene.victims {
                let c = coarse_cell(&view, v.position);
                assert!(cells.insert(c), "two victims in one cell");
                assert_eq!(view.class(c), CellClass::Victim);
                assert!(
                    reach[view.index(c).unwrap()],
                    "{style} seed {seed}: victim {} unreachable",
                    v.id
                );
                assert!((30.0..=37.0).contains(&v.heat_c));
                assert!(v.visible_size_m2 > 0.0 && (0.0..=1.0).contains(&v.buried_fraction));
                assert!(!scene.is_obstacle(scene.geometry().world_to_cell(v.position)));
            }
            assert!(
                scene
                    .victims
                    .iter()
                    .filter(|v| v.buried_fraction >= 0.3)
                    .count()
                    >= 2,
                "partly buried victims"
            );
            // Every open or climbable cell is reachable by a climbing robot.
            for (i, &class) in view.terrain_classes.iter().enumerate() {
                if class.is_passable_terrain(true) {
                    assert!(reach[i], "{style} seed {seed}: passable cell {i} cut off");
                }
            }
        }
    }
}

#[test]
fn rubble_styles_needing_it_hide_a_victim_behind_climbable_rubble() {
    for style in RubbleStyle::ALL {
        for seed in SEEDS {
            let scene = rubble(style, seed);
            let view = view(&scene);
            let start = coarse_cell(&view, scene.start_poses[0].position());
            let walk = view.reachable(start, false);
            let hidden = scene
                .victims
                .iter()
                .filter(|v| !walk[view.index(coarse_cell(&view, v.position)).unwrap()])
                .count();
            if style.needs_climb_only_victim() {
                assert!(
                    hidden >= 1,
                    "{style} seed {seed}: every victim reachable without climbing"
                );
            }
        }
    }
}

#[test]
fn rubble_victims_lie_mostly_in_corners() {
    for style in RubbleStyle::ALL {
        for seed in SEEDS {
            let scene = rubble(style, seed);
            let view = view(&scene);
            let cornered = scene
                .victims
                .iter()
                .filter(|v| {
                    let c = coarse_cell(&view, v.position);
                    let blocked = [(1, 0), (0, 1), (-1, 0), (0, -1)]
                        .iter()
                        .filter(|(dc, dr)| {
                            !view.is_passable(Cell::new(c.col + dc, c.row + dr), true)
                        })
                        .count();
                    blocked >= 2
                })
                .count();
            assert!(
                2 * cornered >= scene.victims.len(),
                "{style} seed {seed}: {cornered} in corners"
            );
        }
    }
}

#[test]
fn rubble_has_three_open_start_poses_reachable_with_right_angle_headings() {
    for style in RubbleStyle::ALL {
        for seed in SEEDS {
            let scene = rubble(style, seed);
            let view = view(&scene);
            assert_eq!(scene.start_poses.len(), 3);
            let reach = view.reachable(coarse_cell(&view, scene.start_poses[0].position()), true);
            let mut cells = BTreeSet::new();
            for p in &scene.start_poses {
                let c = coarse_cell(&view, p.position());
                assert!(cells.insert(c), "two start poses in one cell");
                assert_eq!(view.class(c), CellClass::Open, "{style} seed {seed}");
                assert!(reach[view.index(c).unwrap()]);
                assert!(
                    view.cell_center(c).distance(p.position()) < 1e-9,
                    "start at the cell centre"
                );
                let quarter = p.theta / std::f64::consts::FRAC_PI_2;
                assert!(
                    (quarter - quarter.round()).abs() < 1e-12,
                    "heading {}",
                    p.theta
                );
            }
        }
    }
}

#[test]
fn rubble_has_one_or_two_heat_sources_that_are_not_victims() {
    for seed in SEEDS {
        let scene = rubble(RubbleStyle::Random, seed);
        assert!((1..=2).contains(&scene.heat_sources.len()));
        let view = view(&scene);
        for h in &scene.heat_sources {
            let c = coarse_cell(&view, h.position);
            assert_ne!(view.class(c), CellClass::Victim);
            assert!(!h.kind.is_empty() && h.size_m2 > 0.0);
        }
    }
}

#[test]
fn rubble_is_walled_all_around() {
    let scene = rubble(RubbleStyle::SceneB, 5);
    let g = *scene.geometry();
    let (w, h) = (g.width as i32, g.height as i32);
    for col in 0..w {
        assert_eq!(scene.obstacle[Cell::new(col, 0)], obstacle::WALL);
        assert_eq!(scene.obstacle[Cell::new(col, h - 1)], obstacle::WALL);
    }
    for row in 0..h {
        assert_eq!(scene.obstacle[Cell::new(0, row)], obstacle::WALL);
        assert_eq!(scene.obstacle[Cell::new(w - 1, row)], obstacle::WALL);
    }
    let walls = scene
        .obstacle
        .as_slice()
        .iter()
        .filter(|&&o| o == obstacle::WALL)
        .count();
    assert_eq!(walls, 2 * (w + h) as usize - 4, "no wall inside the arena");
}

#[test]
fn rubble_out_of_range_parameters_are_reported_and_clamped() {
    let bad = RubbleParams {
        cols: 0,
        fine_cells_per_side: 1000,
        ..RubbleParams::default()
    };
    let err = bad
        .validate(Path::new("rubble.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("rubble.toml") && err.contains("cols"), "{err}");
    #[allow(clippy::reversed_empty_ranges)]
    let backwards = RubbleParams {
        victims: 8..=7,
        ..RubbleParams::default()
    };
    assert!(
        backwards
            .validate(Path::new("p"))
            .unwrap_err()
            .to_string()
            .contains("victims")
    );
    assert!(RubbleParams::default().validate(Path::new("p")).is_ok());
    // Generation never panics: it clamps.
    let scene = generate_rubble(1, &bad);
    assert!(scene_from_json(&scene_to_json(&scene), Path::new("clamped.json")).is_ok());
    let view = view(&scene);
    assert_eq!(view.cols, 5);
}

#[test]
fn rubble_arena_of_other_size_keeps_coarse_alignment() {
    let params = RubbleParams {
        cols: 12,
        rows: 8,
        fine_cells_per_side: 6,
        ..RubbleParams::default()
    };
    let scene = generate_rubble(4, &params);
    let view = view(&scene);
    assert_eq!((view.cols, view.rows), (12, 8));
    assert!(view.terrain.iter().all(|t| t.fine_cells == 36));
    let intended = intended_classes(&scene, &view);
    assert_eq!(intended, view.terrain_classes);
}

// ---------------------------------------------------------------------------------------------
// Course (paper 004 Fig. 15)

fn course(seed: u64) -> Scene {
    generate_course(seed, &CourseParams::default())
}

/// Free distance from `p` in direction `angle_rad` to the first obstacle cell, metres.
fn free_run(scene: &Scene, p: Point2, angle_rad: f64) -> f64 {
    let g = scene.geometry();
    let step = g.resolution_m / 8.0;
    let mut d = 0.0;
    while d < 50.0 && !scene.is_obstacle(g.world_to_cell(p.offset(angle_rad, d + step))) {
        d += step;
    }
    d
}

fn passage_width(scene: &Scene) -> f64 {
    // The start is a dead end facing east: its free runs north and south span the passage.
    let s = scene.start_poses[0].position();
    free_run(scene, s, std::f64::consts::FRAC_PI_2)
        + free_run(scene, s, -std::f64::consts::FRAC_PI_2)
}

#[test]
fn course_same_seed_gives_identical_file_and_round_trips() {
    let a = scene_to_json(&course(5));
    assert!(a == scene_to_json(&course(5)));
    let back = scene_from_json(&a, Path::new("course.json")).unwrap();
    assert_eq!(back, course(5));
    assert!(
        a != scene_to_json(&course(6)),
        "the seed varies widths and positions"
    );
}

#[test]
fn course_has_every_junction_kind_of_paper_004() {
    let scene = course(1);
    let kinds: BTreeSet<JunctionKind> = scene
        .ground_truth
        .junctions
        .iter()
        .map(|j| j.kind)
        .collect();
    for kind in [
        JunctionKind::DeadEnd,
        JunctionKind::Corner,
        JunctionKind::TJunction,
        JunctionKind::Crossing,
    ] {
        assert!(kinds.contains(&kind), "{kind:?} missing");
    }
}

#[test]
fn course_junctions_lie_on_free_cells_at_passage_centres_with_their_kind() {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
    for seed in SEEDS {
        let scene = course(seed);
        let width = passage_width(&scene);
        assert!(
            (1.2..=2.0).contains(&width),
            "seed {seed}: passage width {width}"
        );
        let half = width / 2.0;
        let tolerance = scene.geometry().resolution_m;
        for j in &scene.ground_truth.junctions {
            let p = j.position;
            assert!(
                !scene.is_obstacle(scene.geometry().world_to_cell(p)),
                "{j:?} on an obstacle"
            );
            // Centre of a square junction area: all four diagonals reach the walls' corners.
            for k in 0..4 {
                let run = free_run(&scene, p, FRAC_PI_4 + f64::from(k) * FRAC_PI_2);
                assert!(
                    (run - half * 2f64.sqrt()).abs() <= 2.0 * tolerance,
                    "seed {seed} {j:?}: diagonal {run}"
                );
            }
            // The kind follows from the number of open directions; closed sides are half a
            // passage width away.
            let runs: Vec<f64> = (0..4)
                .map(|k| free_run(&scene, p, f64::from(k) * FRAC_PI_2))
                .collect();
            let open: Vec<bool> = runs.iter().map(|&r| r > width).collect();
            for (r, &o) in runs.iter().zip(&open) {
                assert!(
                    o || (r - half).abs() <= tolerance,
                    "seed {seed} {j:?}: closed side at {r}"
                );
            }
            let kind = match open.iter().filter(|&&o| o).count() {
                1 => JunctionKind::DeadEnd,
                2 if open[0] != open[2] => JunctionKind::Corner,
                3 => JunctionKind::TJunction,
                4 => JunctionKind::Crossing,
                n => panic!("seed {seed} {j:?}: {n} open directions, a straight passage? {runs:?}"),
            };
            assert_eq!(kind, j.kind, "seed {seed} at {p:?}, runs {runs:?}");
        }
    }
}

#[test]
fn course_start_pose_is_at_a_terminal_end_of_a_passage() {
    let scene = course(2);
    let start = scene.start_poses[0];
    let dead_end = scene
        .ground_truth
        .junctions
        .iter()
        .find(|j| j.position.distance(start.position()) < 1e-9)
        .expect("the start is a recorded passage end");
    assert_eq!(dead_end.kind, JunctionKind::DeadEnd);
    assert!(
        free_run(&scene, start.position(), start.theta) > 5.0,
        "facing along the passage"
    );
}

#[test]
fn course_hall_exceeds_a_4_m_laser_search_radius() {
    let scene = course(3);
    let halls: Vec<&Rect> = scene
        .ground_truth
        .features
        .iter()
        .filter_map(|f| match f {
            TerrainFeature::Hall { region } => Some(region),
            _ => None,
        })
        .collect();
    assert_eq!(halls.len(), 1);
    let hall = halls[0];
    let centre = hall.center();
    for k in 0..16 {
        let run = free_run(&scene, centre, f64::from(k) * std::f64::consts::PI / 8.0);
        assert!(run > 4.0, "a wall {run} m from the hall's centre");
    }
    assert!(hall.width() > 8.0 && hall.height() > 8.0);
}

/// Least-squares inclination of the floor over the free cells of a region.
fn measured_inclination(scene: &Scene, region: &Rect) -> f64 {
    let g = scene.geometry();
    let mut plane = LeastSquaresPlane::new();
    for row in 0..g.height as i32 {
        for col in 0..g.width as i32 {
            let c = Cell::new(col, row);
            let p = g.cell_center(c);
            if region.contains(p) && !scene.is_obstacle(c) {
                plane.push(
                    p.x - region.min.x,
                    p.y - region.min.y,
                    f64::from(scene.floor_height_m[c]),
                );
            }
        }
    }
    assert!(plane.len() > 20);
    plane.fit().unwrap().slope_rad
}

#[test]
fn course_slope_inclination_measured_from_heights_matches_the_declared_one() {
    for degrees in [20.0f64, 10.0, 35.0] {
        let params = CourseParams {
            slope_inclination_rad: degrees.to_radians(),
            ..CourseParams::default()
        };
        let scene = generate_course(4, &params);
        let slopes: Vec<_> = scene
            .ground_truth
            .features
            .iter()
            .filter_map(|f| match f {
                TerrainFeature::Slope {
                    region,
                    inclination_rad,
                    uphill_rad,
                } => Some((*region, *inclination_rad, *uphill_rad)),
                _ => None,
            })
            .collect();
        assert_eq!(slopes.len(), 2, "a triangular slope: up and down ramps");
        for (region, declared, uphill) in slopes {
            assert!((declared - degrees.to_radians()).abs() < 1e-12);
            let measured = measured_inclination(&scene, &region);
            assert!(
                (measured / declared - 1.0).abs() < 0.02,
                "{degrees}°: measured {}°",
                measured.to_degrees()
            );
            // The floor rises toward `uphill`.
            let g = scene.geometry();
            let low = g.world_to_cell(region.center().offset(uphill, -region.width() / 2.0 + 0.05));
            let high = g.world_to_cell(region.center().offset(uphill, region.width() / 2.0 - 0.05));
            assert!(scene.floor_height_m[high] > scene.floor_height_m[low]);
        }
    }
}

#[test]
fn course_stairs_rise_by_the_declared_step_height() {
    let scene = course(5);
    let g = *scene.geometry();
    let (region, h, d, n, uphill) = scene
        .ground_truth
        .features
        .iter()
        .find_map(|f| match f {
            TerrainFeature::Stairs {
                region,
                step_height_m,
                step_depth_m,
                steps,
                uphill_rad,
            } => Some((*region, *step_height_m, *step_depth_m, *steps, *uphill_rad)),
            _ => None,
        })
        .expect("stairs");
    assert_eq!((h, d), (0.15, 0.3));
    assert!((region.width() - f64::from(n) * d).abs() < 1e-9);
    assert_eq!(uphill, 0.0);
    let y = region.center().y;
    let height_at = |x: f64| f64::from(scene.floor_height_m[g.world_to_cell(Point2::new(x, y))]);
    let mut previous = height_at(region.min.x - d / 2.0);
    for i in 0..n {
        let here = height_at(region.min.x + (f64::from(i) + 0.5) * d);
        assert!(
            (here - previous - h).abs() < 1e-6,
            "step {i}: {previous} → {here}"
        );
        previous = here;
    }
}

/// Flood fill over free fine cells, stepping only where `step_ok(height from, height to)`.
fn reach(scene: &Scene, step_ok: impl Fn(f32, f32) -> bool) -> Vec<bool> {
    let g = *scene.geometry();
    let start = g.world_to_cell(scene.start_poses[0].position());
    let mut seen = vec![false; g.len()];
    seen[g.index(start)] = true;
    let mut stack = vec![start];
    while let Some(c) = stack.pop() {
        for (dc, dr) in [(1, 0), (0, 1), (-1, 0), (0, -1)] {
            let n = Cell::new(c.col + dc, c.row + dr);
            if g.contains(n)
                && !seen[g.index(n)]
                && !scene.is_obstacle(n)
                && step_ok(scene.floor_height_m[c], scene.floor_height_m[n])
            {
                seen[g.index(n)] = true;
                stack.push(n);
            }
        }
    }
    seen
}

#[test]
fn course_wheeled_robot_reaches_every_level_cell_and_crawler_everything() {
    for seed in SEEDS {
        let scene = course(seed);
        // A wheeled robot stays on level floor (slope and stairs exceed its 15° / 0.05 m).
        let level = reach(&scene, |a, b| a == 0.0 && b == 0.0);
        // A crawler climbs 0.2 m steps (and a 20° ramp rises 3.6 cm per 0.1 m cell).
        let crawler = reach(&scene, |a, b| (a - b).abs() <= 0.2);
        let mut unreached_level = 0;
        let mut unreached = 0;
        let mut raised = 0;
        for (i, (&o, &z)) in scene
            .obstacle
            .as_slice()
            .iter()
            .zip(scene.floor_height_m.as_slice())
            .enumerate()
        {
            if o != obstacle::NONE {
                continue;
            }
            unreached += usize::from(!crawler[i]);
            if z == 0.0 {
                unreached_level += usize::from(!level[i]);
            } else {
                raised += 1;
            }
        }
        assert_eq!(
            unreached_level, 0,
            "seed {seed}: level cells cut off for a wheeled robot"
        );
        assert_eq!(unreached, 0, "seed {seed}: cells a crawler cannot reach");
        assert!(raised > 100, "the slope and the stairs exist");
    }
}

#[test]
fn course_out_of_range_parameters_are_reported_and_clamped() {
    let bad = CourseParams {
        passage_width_m: 9.0,
        steps: 0,
        ..CourseParams::default()
    };
    let err = bad
        .validate(Path::new("course.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("course.toml") && err.contains("passage_width_m"),
        "{err}"
    );
    assert!(CourseParams::default().validate(Path::new("p")).is_ok());
    let scene = generate_course(0, &bad);
    assert!(scene_from_json(&scene_to_json(&scene), Path::new("clamped.json")).is_ok());
    assert!(passage_width(&scene) <= 2.2 * 1.1 + 1e-9);
}

#[test]
fn course_at_5_cm_resolution_keeps_its_geometry() {
    let params = CourseParams {
        resolution_m: 0.05,
        ..CourseParams::default()
    };
    let scene = generate_course(9, &params);
    assert_eq!(scene.geometry().resolution_m, 0.05);
    let width = passage_width(&scene);
    assert!((1.4..=1.8).contains(&width), "{width}");
    assert!(
        scene
            .ground_truth
            .junctions
            .iter()
            .all(|j| !scene.is_obstacle(scene.geometry().world_to_cell(j.position)))
    );
}

#[test]
fn a_refined_scene_keeps_every_cell_under_its_finer_cells() {
    let scene = usar_world::generate::generate(usar_world::generate::SceneKind::Office, 2);
    let fine = scene.refined(2);
    let (g, f) = (*scene.geometry(), *fine.geometry());
    assert_eq!((f.width, f.height), (g.width * 2, g.height * 2));
    assert_eq!(f.extent_m(), g.extent_m());
    for i in (0..f.len()).step_by(97) {
        let p = f.cell_center(f.cell_of_index(i));
        let c = g.world_to_cell(p);
        assert_eq!(fine.obstacle.as_slice()[i], scene.obstacle[c]);
        assert_eq!(fine.room_id.as_slice()[i], scene.room_id[c]);
        assert_eq!(fine.floor_height_m.as_slice()[i], scene.floor_height_m[c]);
    }
    assert_eq!(fine.victims, scene.victims);
}

#[test]
fn a_rubble_zone_is_laid_only_where_allowed_and_brings_its_victims() {
    use usar_world::generate::lay_rubble;
    let mut scene =
        usar_world::generate::generate(usar_world::generate::SceneKind::Office, 2).refined(2);
    let before = scene.clone();
    let g = *scene.geometry();
    let origin = usar_world::Point2::new(10.0, 10.0);
    // Only the left half of the 8 × 8 cell arena is allowed.
    let split_x = origin.x + 4.0 * 0.9165;
    let zone = lay_rubble(&mut scene, origin, (8, 8), 0.9165, 7, |c| {
        g.cell_center(c).x < split_x
    });
    let mut changed = 0;
    for i in 0..g.len() {
        let c = g.cell_of_index(i);
        let differs = scene.floor_height_m[c] != before.floor_height_m[c]
            || scene.obstacle[c] != before.obstacle[c];
        if differs {
            changed += 1;
            let p = g.cell_center(c);
            assert!(p.x < split_x && p.x >= origin.x && p.y >= origin.y, "{p:?}");
        }
    }
    assert!(changed > 100, "{changed} cells changed");
    assert_eq!(
        scene.victims.len(),
        before.victims.len() + zone.victims.len()
    );
    for id in &zone.victims {
        let v = scene.victims.iter().find(|v| v.id == *id).unwrap();
        assert!(v.position.x < split_x, "{v:?}");
    }
}

//! The paper-000 cell view: classes from heights, the plane fit, conversions, reachability.

use proptest::prelude::*;
use std::path::Path;
use usar_world::cellview::{
    CellClass, CellView, CellViewParams, LeastSquaresPlane, PAPER_CELL_SIDE_M,
};
use usar_world::generate::draw::{fill_obstacle, shape_floor};
use usar_world::{Cell, GridGeometry, Point2, Rect, Scene, Victim, obstacle};

/// Fine cells per coarse side in these tests: 10 cells of 0.1 m make 1 m coarse cells.
const FINE: u32 = 10;

fn flat_scene(cols: u32, rows: u32) -> Scene {
    let g = GridGeometry::new(cols * FINE, rows * FINE, 0.1, Point2::new(0.0, 0.0));
    let mut scene = Scene::empty("test", g);
    scene.coarse_cell_m = Some(1.0);
    scene
}

fn cell_rect(col: i32, row: i32) -> Rect {
    Rect::new(
        f64::from(col),
        f64::from(row),
        f64::from(col + 1),
        f64::from(row + 1),
    )
}

fn view(scene: &Scene) -> CellView {
    CellView::from_scene(scene, &CellViewParams::default())
}

/// A plane of `degrees` rising east over coarse cell (col, row), starting at the floor.
fn tilt_cell(scene: &mut Scene, col: i32, row: i32, degrees: f64) {
    let x0 = f64::from(col);
    let gradient = degrees.to_radians().tan();
    shape_floor(scene, cell_rect(col, row), |p| {
        (gradient * (p.x - x0)) as f32
    });
}

#[test]
fn flat_scene_is_all_open() {
    let scene = flat_scene(8, 6);
    let v = view(&scene);
    assert_eq!((v.cols, v.rows), (8, 6));
    assert_eq!(v.count(CellClass::Open), 48);
    assert_eq!(v.reference_floor_m, 0.0);
    assert!(
        v.terrain
            .iter()
            .all(|t| t.slope_rad == 0.0 && t.roughness_m == 0.0 && t.fine_cells == 100)
    );
}

#[test]
fn raised_flat_scene_is_still_open_because_the_reference_floor_follows_it() {
    let mut scene = flat_scene(4, 4);
    scene.floor_height_m.as_mut_slice().fill(3.0);
    let v = view(&scene);
    assert_eq!(v.count(CellClass::Open), 16);
    assert_eq!(v.reference_floor_m, 3.0);
}

#[test]
fn plane_of_10_degrees_is_climbable_and_of_30_degrees_non_climbable() {
    let mut scene = flat_scene(5, 3);
    tilt_cell(&mut scene, 1, 1, 10.0);
    tilt_cell(&mut scene, 3, 1, 30.0);
    let v = view(&scene);
    assert_eq!(v.class(Cell::new(1, 1)), CellClass::Climbable);
    assert_eq!(v.class(Cell::new(3, 1)), CellClass::NonClimbable);
    let t = v.terrain_at(Cell::new(1, 1)).unwrap();
    assert!((t.slope_rad.to_degrees() - 10.0).abs() < 1e-3, "{t:?}");
    assert!(t.uphill_rad.abs() < 1e-6, "rises east: {t:?}");
    assert!(t.roughness_m < 1e-5);
    // Everything else stays open.
    assert_eq!(v.count(CellClass::Open), 13);
}

#[test]
fn hole_is_a_drop_and_a_shallow_dip_is_climbable() {
    let mut scene = flat_scene(5, 3);
    shape_floor(&mut scene, cell_rect(1, 1), |_| -0.5);
    shape_floor(&mut scene, cell_rect(3, 1), |_| -0.2);
    let v = view(&scene);
    assert_eq!(v.class(Cell::new(1, 1)), CellClass::Drop);
    assert_eq!(v.class(Cell::new(3, 1)), CellClass::Climbable);
    assert!(!v.is_passable(Cell::new(1, 1), true));
}

#[test]
fn wall_filled_cell_is_non_climbable_and_a_thin_wall_is_not() {
    let mut scene = flat_scene(5, 3);
    // 30 of 100 fine cells of cell (1, 1); 10 of cell (3, 1).
    fill_obstacle(&mut scene, Rect::new(1.0, 1.0, 1.3, 2.0), obstacle::WALL);
    fill_obstacle(
        &mut scene,
        Rect::new(3.0, 1.0, 3.1, 2.0),
        obstacle::FURNITURE,
    );
    let v = view(&scene);
    assert_eq!(v.class(Cell::new(1, 1)), CellClass::NonClimbable);
    assert!((v.terrain_at(Cell::new(1, 1)).unwrap().obstacle_fraction - 0.3).abs() < 1e-12);
    assert_eq!(v.class(Cell::new(3, 1)), CellClass::Open);
}

#[test]
fn roughness_separates_open_climbable_and_non_climbable_rubble() {
    // Row 0 holds the test cells; rows 1–3 stay flat and set the reference floor to 0.
    let mut scene = flat_scene(4, 4);
    let checkerboard = |amplitude: f64| {
        move |p: Point2| {
            let k = (p.x / 0.1).floor() as i64 + (p.y / 0.1).floor() as i64;
            (if k % 2 == 0 { amplitude } else { -amplitude }) as f32
        }
    };
    shape_floor(&mut scene, cell_rect(0, 0), checkerboard(0.01));
    shape_floor(&mut scene, cell_rect(1, 0), checkerboard(0.03));
    shape_floor(&mut scene, cell_rect(2, 0), checkerboard(0.08));
    // A smooth block 0.5 m high: level, but too high to climb.
    shape_floor(&mut scene, cell_rect(3, 0), |_| 0.5);
    let v = view(&scene);
    assert_eq!(v.reference_floor_m, 0.0);
    assert!((v.terrain_at(Cell::new(1, 0)).unwrap().roughness_m - 0.03).abs() < 1e-6);
    let classes: Vec<CellClass> = (0..4).map(|c| v.class(Cell::new(c, 0))).collect();
    assert_eq!(
        classes,
        [
            CellClass::Open,
            CellClass::Climbable,
            CellClass::NonClimbable,
            CellClass::NonClimbable
        ]
    );
}

#[test]
fn victim_cell_is_victim_and_keeps_its_terrain_class() {
    let mut scene = flat_scene(3, 3);
    tilt_cell(&mut scene, 2, 2, 10.0);
    for (id, (x, y)) in [(1, (1.5, 1.5)), (2, (2.4, 2.6))] {
        scene.victims.push(Victim {
            id,
            position: Point2::new(x, y),
            heat_c: 34.0,
            visible_size_m2: 0.5,
            buried_fraction: 0.0,
        });
    }
    let v = view(&scene);
    assert_eq!(v.class(Cell::new(1, 1)), CellClass::Victim);
    assert_eq!(v.terrain_class(Cell::new(1, 1)), CellClass::Open);
    assert_eq!(v.class(Cell::new(2, 2)), CellClass::Victim);
    assert_eq!(v.terrain_class(Cell::new(2, 2)), CellClass::Climbable);
    // A victim cell is entered as its terrain allows.
    assert!(v.is_passable(Cell::new(1, 1), false));
    assert!(!v.is_passable(Cell::new(2, 2), false) && v.is_passable(Cell::new(2, 2), true));
    assert_eq!(v.count(CellClass::Victim), 2);
}

#[test]
fn reachable_crosses_climbable_rubble_only_when_the_robot_climbs() {
    // A barrier of piles down column 2 with one climbable cell at row 1.
    let mut scene = flat_scene(5, 3);
    for row in 0..3 {
        if row == 1 {
            tilt_cell(&mut scene, 2, row, 12.0);
        } else {
            shape_floor(&mut scene, cell_rect(2, row), |_| 1.0);
        }
    }
    let v = view(&scene);
    let walk = v.reachable(Cell::new(0, 0), false);
    let climb = v.reachable(Cell::new(0, 0), true);
    let east = v.index(Cell::new(4, 2)).unwrap();
    assert!(!walk[east] && climb[east]);
    assert_eq!(walk.iter().filter(|&&r| r).count(), 6);
    assert_eq!(climb.iter().filter(|&&r| r).count(), 13);
    assert!(
        v.reachable(Cell::new(2, 0), true).iter().all(|&r| !r),
        "start on a pile"
    );
    assert!(
        v.reachable(Cell::new(9, 9), true).iter().all(|&r| !r),
        "start outside"
    );
    assert_eq!(
        v.class(Cell::new(-1, 0)),
        CellClass::NonClimbable,
        "outside is the boundary"
    );
}

#[test]
fn cell_size_comes_from_the_params_then_the_scene_then_the_paper() {
    let mut scene = flat_scene(6, 6);
    assert_eq!(view(&scene).cell_size_m, 1.0);
    let two = CellViewParams {
        cell_size_m: Some(2.0),
        ..CellViewParams::default()
    };
    let v = CellView::from_scene(&scene, &two);
    assert_eq!((v.cell_size_m, v.cols), (2.0, 3));
    scene.coarse_cell_m = None;
    assert_eq!(view(&scene).cell_size_m, PAPER_CELL_SIDE_M);
    let broken = CellViewParams {
        cell_size_m: Some(-1.0),
        ..CellViewParams::default()
    };
    assert_eq!(
        CellView::from_scene(&scene, &broken).cell_size_m,
        PAPER_CELL_SIDE_M
    );
    let tiny = CellViewParams {
        cell_size_m: Some(0.01),
        ..CellViewParams::default()
    };
    assert_eq!(
        CellView::from_scene(&scene, &tiny).cell_size_m,
        0.1,
        "at least one fine cell"
    );
}

#[test]
fn coarse_grid_is_centred_on_the_fine_grid() {
    // 25 fine cells of 0.1 m with 1 m coarse cells: two whole cells, 0.25 m left over each side.
    let g = GridGeometry::new(25, 10, 0.1, Point2::new(-1.0, 0.0));
    let mut scene = Scene::empty("odd", g);
    scene.coarse_cell_m = Some(1.0);
    let v = view(&scene);
    assert_eq!((v.cols, v.rows), (2, 1));
    assert!(v.geometry.origin.distance(Point2::new(-0.75, 0.0)) < 1e-12);
    assert!(v.terrain.iter().all(|t| t.fine_cells == 100));
    assert_eq!(
        v.cell_of(Point2::new(-0.9, 0.5)),
        None,
        "in the leftover strip"
    );
}

#[test]
fn invalid_params_are_reported_with_their_field() {
    let p = CellViewParams {
        climbable_max_roughness_m: 0.01,
        ..CellViewParams::default()
    };
    let e = p.validate(Path::new("view.toml")).unwrap_err().to_string();
    assert!(
        e.contains("view.toml") && e.contains("climbable_max_roughness_m"),
        "{e}"
    );
    let p = CellViewParams {
        drop_depth_m: f64::NAN,
        ..CellViewParams::default()
    };
    assert!(
        p.validate(Path::new("v"))
            .unwrap_err()
            .to_string()
            .contains("drop_depth_m")
    );
    let p = CellViewParams {
        max_obstacle_fraction: 1.5,
        ..CellViewParams::default()
    };
    assert!(p.validate(Path::new("v")).is_err());
    assert!(CellViewParams::default().validate(Path::new("v")).is_ok());
}

proptest! {
    #[test]
    fn plane_fit_recovers_noise_free_planes(
        a in -3.0f64..3.0,
        b in -3.0f64..3.0,
        c in -10.0f64..10.0,
        points in prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0), 0..40),
    ) {
        let mut fit = LeastSquaresPlane::new();
        // Three corners keep the points from being collinear.
        for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0)].into_iter().chain(points) {
            fit.push(x, y, a * x + b * y + c);
        }
        let p = fit.fit().unwrap();
        prop_assert!((p.a - a).abs() < 1e-9 && (p.b - b).abs() < 1e-9 && (p.c - c).abs() < 1e-9, "{:?}", p);
        prop_assert!((p.slope_rad - a.hypot(b).atan()).abs() < 1e-9);
        prop_assert!(p.roughness_m < 1e-6);
    }

    #[test]
    fn cell_view_measures_the_slope_of_a_tilted_floor(
        degrees in 0.0f64..60.0,
        direction in -3.1f64..3.1,
    ) {
        let mut scene = flat_scene(3, 3);
        let g = degrees.to_radians().tan();
        let (s, c) = direction.sin_cos();
        shape_floor(&mut scene, cell_rect(1, 1), |p| (g * ((p.x - 1.5) * c + (p.y - 1.5) * s)) as f32);
        let v = view(&scene);
        let t = v.terrain_at(Cell::new(1, 1)).unwrap();
        prop_assert!((t.slope_rad - degrees.to_radians()).abs() < 1e-4, "{:?}", t);
        if degrees > 1.0 {
            let miss = usar_world::normalize_angle(t.uphill_rad - direction).abs();
            prop_assert!(miss < 1e-3, "uphill {} vs {}", t.uphill_rad, direction);
        }
    }

    #[test]
    fn world_and_coarse_cells_convert_both_ways(
        x in 0.0f64..7.99,
        y in 0.0f64..5.99,
    ) {
        let v = view(&flat_scene(8, 6));
        let p = Point2::new(x, y);
        let cell = v.cell_of(p).unwrap();
        prop_assert!(v.cell_rect(cell).contains(p));
        prop_assert_eq!(v.cell_of(v.cell_center(cell)), Some(cell));
        prop_assert!(v.cell_center(cell).distance(v.cell_rect(cell).center()) < 1e-12);
    }
}

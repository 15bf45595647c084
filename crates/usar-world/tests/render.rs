//! The renderer: sizes, orientation, colours of walls, floor, rooms, victims; the shared maps.

use std::path::{Path, PathBuf};
use usar_world::generate::draw::{fill_obstacle, fill_room, shape_floor};
use usar_world::io::image_map::{ImageMapOptions, read_image_map};
use usar_world::io::ros::read_ros_map;
use usar_world::render::{Canvas, RenderOptions, palette, render_scene};
use usar_world::{
    Cell, GridGeometry, HeatSource, Junction, JunctionKind, Point2, Pose2, Rect, Room, RoomLabel,
    Scene, Victim, obstacle,
};

fn ros_maps() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/maps/ros")
}

fn shared_scenes() -> Vec<Scene> {
    let mut scenes: Vec<Scene> = ["depot.yaml", "warehouse.yaml", "tb3_sandbox.yaml"]
        .iter()
        .map(|f| read_ros_map(&ros_maps().join(f)).unwrap())
        .collect();
    let willow = ImageMapOptions {
        resolution_m: 0.1,
        ..ImageMapOptions::default()
    };
    scenes.push(read_image_map(&ros_maps().join("willow-full.pgm"), &willow).unwrap());
    scenes
}

/// Colour of the (first) pixel of a cell.
fn cell_colour(canvas: &Canvas, cell: Cell) -> [u8; 3] {
    let (x, y, _, _) = canvas.cell_pixels(cell).unwrap();
    canvas.pixel(x, y).unwrap()
}

#[test]
fn every_shared_ros_map_renders_with_black_walls_and_white_floor() {
    for scene in shared_scenes() {
        let g = *scene.geometry();
        let opts = RenderOptions {
            px_per_cell: Some(2),
            ..RenderOptions::default()
        };
        let canvas = render_scene(&scene, &opts);
        assert_eq!(
            (canvas.width(), canvas.height()),
            (2 * g.width, 2 * g.height),
            "{}",
            scene.name
        );
        let start = g.world_to_cell(scene.start_poses[0].position());
        let wall = scene
            .obstacle
            .iter_cells()
            .find(|&(_, &o)| o == obstacle::WALL)
            .unwrap()
            .0;
        // A free cell well away from the start-pose mark.
        let free = scene
            .obstacle
            .iter_cells()
            .find(|&(c, &o)| o == obstacle::NONE && c.chebyshev(start) > 20)
            .unwrap()
            .0;
        assert_eq!(cell_colour(&canvas, wall), palette::WALL, "{}", scene.name);
        assert_eq!(cell_colour(&canvas, free), palette::FLOOR, "{}", scene.name);
        let (x, y, _, _) = canvas.cell_pixels(start).unwrap();
        assert_eq!(
            canvas.pixel(x, y),
            Some(palette::START_POSE),
            "{}",
            scene.name
        );
    }
}

#[test]
fn fitted_size_follows_max_side() {
    let willow = ImageMapOptions {
        resolution_m: 0.1,
        ..ImageMapOptions::default()
    };
    let scene = read_image_map(&ros_maps().join("willow-full.pgm"), &willow).unwrap();
    let canvas = render_scene(&scene, &RenderOptions::default());
    assert_eq!(
        (canvas.width(), canvas.height()),
        (1168, 1052),
        "584×526 at 2 px per cell"
    );
    let small = render_scene(
        &scene,
        &RenderOptions {
            max_side_px: 300,
            ..RenderOptions::default()
        },
    );
    assert_eq!(
        (small.cells_per_px(), small.width(), small.height()),
        (2, 292, 263)
    );
}

#[test]
fn image_is_not_upside_down() {
    // Walls fill the northern half (rows 10..20) of a 20×20 grid.
    let g = GridGeometry::new(20, 20, 0.1, Point2::new(0.0, 0.0));
    let mut scene = Scene::empty("north", g);
    fill_obstacle(&mut scene, Rect::new(0.0, 1.0, 2.0, 2.0), obstacle::WALL);
    let canvas = render_scene(
        &scene,
        &RenderOptions {
            px_per_cell: Some(3),
            ..Default::default()
        },
    );
    assert_eq!(canvas.height(), 60);
    for y in 0..30 {
        assert!(
            (0..60).all(|x| canvas.pixel(x, y) == Some(palette::WALL)),
            "row {y} should be wall"
        );
    }
    for y in 30..60 {
        assert!(
            (0..60).all(|x| canvas.pixel(x, y) == Some(palette::FLOOR)),
            "row {y} should be floor"
        );
    }
}

#[test]
fn downsampling_keeps_one_cell_walls_visible() {
    let g = GridGeometry::new(4000, 10, 0.1, Point2::new(0.0, 0.0));
    let mut scene = Scene::empty("long", g);
    scene.obstacle[Cell::new(1001, 5)] = obstacle::WALL;
    let canvas = render_scene(&scene, &RenderOptions::default());
    assert_eq!(canvas.cells_per_px(), 3);
    assert_eq!((canvas.width(), canvas.height()), (1334, 4));
    assert_eq!(canvas.pixel(333, 4 - 1 - 5 / 3), Some(palette::WALL));
}

#[test]
fn heights_labels_furniture_and_marks_get_their_colours() {
    let g = GridGeometry::new(80, 40, 0.1, Point2::new(0.0, 0.0));
    let mut scene = Scene::empty("colours", g);
    shape_floor(&mut scene, Rect::new(0.0, 0.0, 1.0, 1.0), |_| 0.4);
    shape_floor(&mut scene, Rect::new(1.0, 0.0, 2.0, 1.0), |_| -0.5);
    fill_obstacle(
        &mut scene,
        Rect::new(2.0, 0.0, 3.0, 1.0),
        obstacle::FURNITURE,
    );
    let labels = [
        RoomLabel::Corridor,
        RoomLabel::SmallRoom,
        RoomLabel::MediumRoom,
        RoomLabel::BigRoom,
    ];
    for (i, label) in labels.into_iter().enumerate() {
        let id = i as u16 + 1;
        scene.rooms.push(Room {
            id,
            label,
            door_ids: vec![],
            intersecting_corridors: vec![],
        });
        fill_room(
            &mut scene,
            Rect::new(2.0 * i as f64, 2.0, 2.0 * i as f64 + 2.0, 4.0),
            id,
        );
    }
    scene.victims.push(Victim {
        id: 1,
        position: Point2::new(5.0, 0.5),
        heat_c: 34.0,
        visible_size_m2: 0.5,
        buried_fraction: 0.0,
    });
    scene.victims.push(Victim {
        id: 2,
        position: Point2::new(6.0, 0.5),
        heat_c: 34.0,
        visible_size_m2: 0.5,
        buried_fraction: 0.8,
    });
    scene.heat_sources.push(HeatSource {
        id: 1,
        position: Point2::new(7.0, 0.5),
        heat_c: 60.0,
        size_m2: 0.2,
        kind: "radiator".into(),
    });
    scene.ground_truth.junctions.push(Junction {
        kind: JunctionKind::Crossing,
        position: Point2::new(4.0125, 1.5125),
    });
    scene.start_poses.push(Pose2::new(7.5, 1.5, 0.0));
    let opts = RenderOptions {
        px_per_cell: Some(4),
        ..RenderOptions::default()
    };
    let canvas = render_scene(&scene, &opts);
    let raised = cell_colour(&canvas, Cell::new(5, 5));
    let lowered = cell_colour(&canvas, Cell::new(15, 5));
    assert!(
        raised != palette::FLOOR && raised[0] > raised[2],
        "raised floor {raised:?}"
    );
    assert!(lowered[2] > lowered[0], "drop {lowered:?}");
    assert_eq!(cell_colour(&canvas, Cell::new(25, 5)), palette::FURNITURE);
    let tints: Vec<[u8; 3]> = (0..4)
        .map(|i| cell_colour(&canvas, Cell::new(20 * i + 10, 30)))
        .collect();
    for (i, a) in tints.iter().enumerate() {
        assert_ne!(*a, palette::FLOOR);
        for b in &tints[i + 1..] {
            assert_ne!(a, b, "label tints must differ: {tints:?}");
        }
    }
    // Exposed victim: filled red; buried victim: a ring, floor inside; heat source orange.
    let px = |p: Point2| {
        let (x, y) = canvas.to_px(p);
        canvas.pixel(x as u32, y as u32).unwrap()
    };
    assert_eq!(px(Point2::new(5.0, 0.5)), palette::VICTIM);
    assert_eq!(px(Point2::new(6.0, 0.5)), palette::FLOOR);
    assert_eq!(px(Point2::new(6.0 + 0.399, 0.5)), palette::VICTIM_BURIED);
    assert_eq!(px(Point2::new(7.0, 0.5)), palette::HEAT_SOURCE);
    assert_eq!(px(Point2::new(7.6, 1.5)), palette::START_POSE);
    // Junction crosses only when asked.
    assert_ne!(px(Point2::new(4.0125, 1.5125)), palette::JUNCTION);
    let with_gt = render_scene(
        &scene,
        &RenderOptions {
            show_ground_truth: true,
            ..opts
        },
    );
    let (x, y) = with_gt.to_px(Point2::new(4.0125, 1.5125));
    assert_eq!(with_gt.pixel(x as u32, y as u32), Some(palette::JUNCTION));
    // Without heights and labels the floor is plain.
    let plain = render_scene(
        &scene,
        &RenderOptions {
            show_heights: false,
            show_labels: false,
            ..opts
        },
    );
    assert_eq!(cell_colour(&plain, Cell::new(5, 5)), palette::FLOOR);
    assert_eq!(cell_colour(&plain, Cell::new(10, 30)), palette::FLOOR);
}

#[test]
fn doors_are_marked_across_the_opening() {
    let g = GridGeometry::new(40, 20, 0.1, Point2::new(0.0, 0.0));
    let mut scene = Scene::empty("door", g);
    // A wall in column 20 (x = 2.0..2.1) with a 0.8 m opening (rows 6..14) centred at y = 1.0.
    for row in (0..6).chain(14..20) {
        scene.obstacle[Cell::new(20, row)] = obstacle::WALL;
    }
    scene.doors.push(usar_world::Door {
        id: 1,
        position: Point2::new(2.05, 1.0),
        width_m: 0.8,
        rooms: [0, 0],
    });
    let canvas = render_scene(
        &scene,
        &RenderOptions {
            px_per_cell: Some(2),
            ..Default::default()
        },
    );
    for row in 6..14 {
        assert_eq!(
            cell_colour(&canvas, Cell::new(20, row)),
            palette::DOOR,
            "row {row}"
        );
    }
    assert_eq!(cell_colour(&canvas, Cell::new(21, 10)), palette::FLOOR);
}

#[test]
fn drawing_primitives_hit_the_expected_pixels() {
    let g = GridGeometry::new(10, 10, 1.0, Point2::new(0.0, 0.0));
    let mut c = Canvas::new(g, 1);
    c.draw_line(Point2::new(0.5, 0.5), Point2::new(9.5, 9.5), [1, 1, 1]);
    for i in 0..10 {
        assert_eq!(c.pixel(i, 9 - i), Some([1, 1, 1]), "diagonal pixel {i}");
    }
    c.draw_disc(Point2::new(5.0, 5.0), 2.0, [2, 2, 2]);
    assert_eq!(c.pixel(5, 5), Some([2, 2, 2]));
    assert_eq!(c.pixel(5, 8), Some([255, 255, 255]));
    c.draw_circle(Point2::new(5.0, 5.0), 4.0, [3, 3, 3]);
    assert_eq!(c.pixel(1, 5), Some([3, 3, 3]));
    c.draw_cross(Point2::new(1.5, 8.5), 1.0, [4, 4, 4]);
    assert_eq!(c.pixel(1, 1), Some([4, 4, 4]));
    c.draw_polyline(&[Point2::new(0.5, 0.5), Point2::new(9.5, 0.5)], [5, 5, 5]);
    assert!((0..10).all(|x| c.pixel(x, 9) == Some([5, 5, 5])));
    c.blend_cell(Cell::new(0, 9), [0, 0, 0], 0.5);
    let [r, g, b] = c.pixel(0, 0).unwrap();
    assert!(
        (127..=128).contains(&r) && r == g && g == b,
        "half-blended white: {r}"
    );
}

#[test]
fn save_png_writes_a_decodable_picture() {
    let dir = tempfile::tempdir().unwrap();
    let scene = read_ros_map(&ros_maps().join("tb3_sandbox.yaml")).unwrap();
    let canvas = render_scene(
        &scene,
        &RenderOptions {
            px_per_cell: Some(1),
            ..Default::default()
        },
    );
    let path = dir.path().join("tb3.png");
    canvas.save_png(&path).unwrap();
    let back = image::open(&path).unwrap().to_rgb8();
    assert_eq!(back, canvas.clone().into_image());
    let err = canvas
        .save_png(&dir.path().join("missing/x.png"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("missing/x.png"), "{err}");
}

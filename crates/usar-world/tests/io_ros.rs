//! ROS `map_server` and bare-image import/export, on the real maps of `shared/maps/ros/` and on
//! small synthetic images. Golden pixel counts were computed independently from the PGM bytes.

use std::path::{Path, PathBuf};
use usar_world::generate::draw::{fill_obstacle, wall_outline};
use usar_world::io::image_map::{
    ImageMapOptions, ThresholdConvention, ThresholdMode, deepest_free_cell, read_image_map,
};
use usar_world::io::ros::{read_ros_map, write_ros_map};
use usar_world::{Cell, GridGeometry, Point2, Rect, Scene, WorldError, obstacle};

fn ros_maps() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/maps/ros")
}

fn count(scene: &Scene, kind: u8) -> usize {
    scene
        .obstacle
        .as_slice()
        .iter()
        .filter(|&&o| o == kind)
        .count()
}

fn free_fraction(scene: &Scene) -> f64 {
    count(scene, obstacle::NONE) as f64 / scene.geometry().len() as f64
}

/// The single start pose lies on a free cell of the largest free region.
fn assert_start_pose_is_sound(scene: &Scene) {
    assert_eq!(scene.start_poses.len(), 1);
    let pose = scene.start_poses[0];
    assert_eq!(pose.theta, 0.0);
    let g = scene.geometry();
    let cell = g.world_to_cell(pose.position());
    assert!(
        !scene.is_obstacle(cell),
        "start pose {pose:?} on an obstacle"
    );
    assert_eq!(deepest_free_cell(&scene.obstacle), Some(cell));
    let reachable = scene
        .reachable_mask(cell)
        .as_slice()
        .iter()
        .filter(|&&m| m)
        .count();
    let largest = region_sizes(scene).into_iter().max().unwrap_or(0);
    assert_eq!(
        reachable, largest,
        "the start pose is not in the largest free region"
    );
}

/// Sizes of the 4-connected free regions (a plain flood fill, independent of the library's).
fn region_sizes(scene: &Scene) -> Vec<usize> {
    let g = *scene.geometry();
    let (w, h) = (g.width as i32, g.height as i32);
    let free: Vec<bool> = scene
        .obstacle
        .as_slice()
        .iter()
        .map(|&o| o == obstacle::NONE)
        .collect();
    let mut seen = vec![false; free.len()];
    let mut sizes = Vec::new();
    for start in 0..free.len() {
        if !free[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        let mut queue = std::collections::VecDeque::from([start]);
        let mut size = 0;
        while let Some(i) = queue.pop_front() {
            size += 1;
            let (c, r) = ((i % w as usize) as i32, (i / w as usize) as i32);
            for (nc, nr) in [(c + 1, r), (c - 1, r), (c, r + 1), (c, r - 1)] {
                if nc >= 0 && nr >= 0 && nc < w && nr < h {
                    let j = (nr * w + nc) as usize;
                    if free[j] && !seen[j] {
                        seen[j] = true;
                        queue.push_back(j);
                    }
                }
            }
        }
        sizes.push(size);
    }
    sizes
}

#[test]
fn depot_yaml_imports_with_its_own_free_threshold() {
    let scene = read_ros_map(&ros_maps().join("depot.yaml")).unwrap();
    let g = scene.geometry();
    assert_eq!((g.width, g.height), (604, 307));
    assert_eq!(g.resolution_m, 0.05);
    assert_eq!(g.origin, Point2::new(0.0, 0.0));
    // free_thresh 0.25: 254 and 205 are free, 0 occupied, nothing unknown.
    assert_eq!(count(&scene, obstacle::NONE), 179_481);
    assert_eq!(count(&scene, obstacle::WALL), 5_947);
    assert_eq!(scene.name, "depot");
    assert_eq!(scene.provenance.source, "import");
    assert!(
        scene.provenance.detail.contains("depot.yaml"),
        "{}",
        scene.provenance.detail
    );
    assert!(
        scene.provenance.detail.contains("depot.pgm"),
        "{}",
        scene.provenance.detail
    );
    assert!(scene.floor_height_m.as_slice().iter().all(|&h| h == 0.0));
    assert_start_pose_is_sound(&scene);
}

#[test]
fn depot_205_pixels_are_free_under_its_yaml_but_walls_under_the_ros_default() {
    // Image pixel (0, 0), the top-left corner, is 205: occupancy 50/255 = 0.196.
    let yaml = read_ros_map(&ros_maps().join("depot.yaml")).unwrap();
    let top_left = Cell::new(0, yaml.geometry().height as i32 - 1);
    assert!(!yaml.is_obstacle(top_left));
    let opts = ImageMapOptions {
        resolution_m: 0.05,
        ..ImageMapOptions::default()
    };
    let bare = read_image_map(&ros_maps().join("depot.pgm"), &opts).unwrap();
    assert!(bare.is_obstacle(top_left));
    assert_eq!(count(&bare, obstacle::NONE), 170_587);
    assert_eq!(
        bare.geometry().len() - count(&bare, obstacle::NONE),
        5_947 + 8_894
    );
}

#[test]
fn warehouse_yaml_imports_with_origin_and_free_thresh_0_1() {
    let scene = read_ros_map(&ros_maps().join("warehouse.yaml")).unwrap();
    let g = scene.geometry();
    assert_eq!((g.width, g.height), (1006, 1674));
    assert_eq!(g.resolution_m, 0.03);
    assert_eq!(g.origin, Point2::new(-15.1, -25.0));
    assert_eq!(count(&scene, obstacle::NONE), 1_422_292);
    assert!((0.8..0.9).contains(&free_fraction(&scene)));
    assert_start_pose_is_sound(&scene);
}

#[test]
fn tb3_sandbox_yaml_imports_a_small_free_area_in_unknown_space() {
    let scene = read_ros_map(&ros_maps().join("tb3_sandbox.yaml")).unwrap();
    let g = scene.geometry();
    assert_eq!((g.width, g.height), (384, 384));
    assert_eq!(g.origin, Point2::new(-10.0, -10.0));
    assert_eq!(count(&scene, obstacle::NONE), 7_903);
    assert!((0.03..0.1).contains(&free_fraction(&scene)));
    assert_start_pose_is_sound(&scene);
}

#[test]
fn willow_full_imports_as_a_bare_pgm_with_its_launch_parameters() {
    let opts = ImageMapOptions {
        resolution_m: 0.1,
        ..ImageMapOptions::default()
    };
    let scene = read_image_map(&ros_maps().join("willow-full.pgm"), &opts).unwrap();
    let g = scene.geometry();
    assert_eq!((g.width, g.height), (584, 526));
    assert_eq!(count(&scene, obstacle::NONE), 134_715);
    assert!((0.4..0.5).contains(&free_fraction(&scene)));
    assert_eq!(scene.name, "willow-full");
    assert_eq!(scene.provenance.detail, "willow-full.pgm");
    assert_start_pose_is_sound(&scene);
}

#[test]
fn threshold_conventions_agree_on_every_shared_map() {
    // No 8-bit value lies exactly on 0.65, 0.196, 0.25 or 0.1, so ROS 1 and Nav2 agree.
    for (file, free) in [
        ("depot.pgm", 0.25),
        ("tb3_sandbox.pgm", 0.196),
        ("willow-full.pgm", 0.196),
    ] {
        let ros1 = ImageMapOptions {
            free_thresh: free,
            ..ImageMapOptions::default()
        };
        let nav2 = ImageMapOptions {
            convention: ThresholdConvention::Nav2,
            ..ros1
        };
        let a = read_image_map(&ros_maps().join(file), &ros1).unwrap();
        let b = read_image_map(&ros_maps().join(file), &nav2).unwrap();
        assert_eq!(a.obstacle, b.obstacle, "{file}");
    }
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A P5 image of `w`×`h` free pixels (254) with the given (x, y from the top) pixels black.
fn p5(w: usize, h: usize, black: &[(usize, usize)]) -> Vec<u8> {
    let mut bytes = format!("P5\n{w} {h}\n255\n").into_bytes();
    let mut pixels = vec![254u8; w * h];
    for &(x, y) in black {
        pixels[y * w + x] = 0;
    }
    bytes.extend(pixels);
    bytes
}

#[test]
fn black_pixel_at_the_image_top_left_lands_in_the_northernmost_row() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "corner.pgm", &p5(5, 4, &[(0, 0)]));
    let opts = ImageMapOptions {
        resolution_m: 0.5,
        origin: Point2::new(-1.0, 2.0),
        ..Default::default()
    };
    let scene = read_image_map(&path, &opts).unwrap();
    assert_eq!(scene.obstacle[Cell::new(0, 3)], obstacle::WALL);
    assert_eq!(count(&scene, obstacle::WALL), 1);
    // The wall's centre is in the top-left corner of the world rectangle.
    let c = scene.geometry().cell_center(Cell::new(0, 3));
    assert_eq!(c, Point2::new(-0.75, 3.75));
}

#[test]
fn ascii_pgm_with_comments_everywhere_reads_like_the_binary_one() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        "P2\n# made by hand\n3 # width\n# height next\n2\n255\n# pixels\n0 254 254\n254 254 254\n";
    let ascii = read_image_map(
        &write(dir.path(), "a.pgm", text.as_bytes()),
        &Default::default(),
    )
    .unwrap();
    let binary = read_image_map(
        &write(dir.path(), "b.pgm", &p5(3, 2, &[(0, 0)])),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(ascii.obstacle, binary.obstacle);
}

#[test]
fn sixteen_bit_pgm_is_read_on_its_own_scale() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = b"P5 2 1 65535\n".to_vec();
    bytes.extend(0u16.to_be_bytes());
    bytes.extend(65000u16.to_be_bytes());
    let scene =
        read_image_map(&write(dir.path(), "deep.pgm", &bytes), &Default::default()).unwrap();
    assert_eq!(scene.obstacle.as_slice(), &[obstacle::WALL, obstacle::NONE]);
}

#[test]
fn png_colour_channels_are_averaged_and_transparency_is_unknown() {
    let dir = tempfile::tempdir().unwrap();
    // Row 0 (top): white opaque, black opaque; row 1: white transparent, grey RGB (255, 255, 0).
    let img = image::RgbaImage::from_raw(
        2,
        2,
        vec![
            255, 255, 255, 255, 0, 0, 0, 255, 255, 255, 255, 0, 255, 255, 0, 255,
        ],
    )
    .unwrap();
    let path = dir.path().join("rgba.png");
    img.save(&path).unwrap();
    let scene = read_image_map(&path, &Default::default()).unwrap();
    // Scene row 1 is image row 0.
    assert_eq!(scene.obstacle[Cell::new(0, 1)], obstacle::NONE);
    assert_eq!(scene.obstacle[Cell::new(1, 1)], obstacle::WALL);
    assert_eq!(
        scene.obstacle[Cell::new(0, 0)],
        obstacle::WALL,
        "transparent is unknown"
    );
    assert_eq!(
        scene.obstacle[Cell::new(1, 0)],
        obstacle::WALL,
        "mean 170 is unknown"
    );
    // The same picture as grey PNG (no alpha) reads the same where alpha was opaque.
    let grey = image::GrayImage::from_raw(2, 1, vec![255, 0]).unwrap();
    let grey_path = dir.path().join("grey.png");
    grey.save(&grey_path).unwrap();
    let scene = read_image_map(&grey_path, &Default::default()).unwrap();
    assert_eq!(scene.obstacle.as_slice(), &[obstacle::NONE, obstacle::WALL]);
}

#[test]
fn negate_and_scale_mode_change_the_reading() {
    let dir = tempfile::tempdir().unwrap();
    // Values 0, 140 (occupancy 0.45, above the band's midpoint) and 254.
    let mut bytes = b"P5\n3 1\n255\n".to_vec();
    bytes.extend([0u8, 140, 254]);
    let path = write(dir.path(), "m.pgm", &bytes);
    let trinary = read_image_map(&path, &Default::default()).unwrap();
    assert_eq!(trinary.obstacle.as_slice(), &[1, 1, 0]);
    let negated = read_image_map(
        &path,
        &ImageMapOptions {
            negate: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(negated.obstacle.as_slice(), &[0, 1, 1]);
    let scale = ImageMapOptions {
        mode: ThresholdMode::Scale,
        ..Default::default()
    };
    let scaled = read_image_map(&path, &scale).unwrap();
    assert_eq!(scaled.obstacle.as_slice(), &[1, 1, 0]);
    let mut bytes = b"P5\n1 2\n255\n".to_vec();
    bytes.extend([160u8, 254]);
    let scaled = read_image_map(&write(dir.path(), "s.pgm", &bytes), &scale).unwrap();
    assert_eq!(
        scaled.obstacle.as_slice(),
        &[0, 0],
        "occupancy 0.37 is below the midpoint"
    );
}

fn sample_scene() -> Scene {
    let g = GridGeometry::new(30, 20, 0.1, Point2::new(-1.5, 2.25));
    let mut scene = Scene::empty("sample", g);
    wall_outline(&mut scene, Rect::new(-1.5, 2.25, 1.5, 4.25), 0.1);
    fill_obstacle(
        &mut scene,
        Rect::new(-0.5, 3.0, 0.0, 3.3),
        obstacle::FURNITURE,
    );
    fill_obstacle(&mut scene, Rect::new(0.6, 2.3, 0.65, 3.9), obstacle::WALL);
    scene
}

#[test]
fn export_then_import_keeps_every_blocked_cell() {
    let dir = tempfile::tempdir().unwrap();
    let scene = sample_scene();
    assert!(count(&scene, obstacle::FURNITURE) > 0 && count(&scene, obstacle::WALL) > 0);
    let yaml = dir.path().join("sample.yaml");
    write_ros_map(&scene, &yaml).unwrap();
    assert!(dir.path().join("sample.pgm").is_file());
    let text = std::fs::read_to_string(&yaml).unwrap();
    assert!(text.contains("image: sample.pgm"), "{text}");
    let back = read_ros_map(&yaml).unwrap();
    assert_eq!(back.geometry(), scene.geometry());
    let blocked = |s: &Scene| s.obstacle.map(|&o| o != obstacle::NONE);
    assert_eq!(blocked(&back), blocked(&scene));
    // Furniture comes back as wall: the format has one kind of occupied pixel.
    assert_eq!(count(&back, obstacle::FURNITURE), 0);
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "no temporary files left"
    );
}

#[test]
fn real_map_round_trips_exactly_through_the_exporter() {
    let dir = tempfile::tempdir().unwrap();
    let scene = read_ros_map(&ros_maps().join("warehouse.yaml")).unwrap();
    let yaml = dir.path().join("copy.yaml");
    write_ros_map(&scene, &yaml).unwrap();
    let back = read_ros_map(&yaml).unwrap();
    assert_eq!(back.obstacle, scene.obstacle);
    assert_eq!(back.start_poses, scene.start_poses);
}

fn error_text(result: Result<Scene, WorldError>) -> String {
    result.expect_err("expected an error").to_string()
}

#[test]
fn empty_image_file_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "empty.pgm", b"");
    let msg = error_text(read_image_map(&path, &Default::default()));
    assert!(msg.contains(&path.display().to_string()), "{msg}");
    assert!(msg.contains("file is empty"), "{msg}");
}

#[test]
fn truncated_pgm_reports_header_size_and_available_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = b"P5\n# CREATOR: test\n584 526\n255\n".to_vec();
    bytes.extend(vec![254u8; 1000]);
    let path = write(dir.path(), "short.pgm", &bytes);
    let msg = error_text(read_image_map(&path, &Default::default()));
    assert!(msg.contains(&path.display().to_string()), "{msg}");
    assert!(
        msg.contains(
            "truncated: header says 584×526 = 307 184 pixels, file has 1 000 bytes of pixel data"
        ),
        "{msg}"
    );
    let ascii = write(dir.path(), "short-ascii.pgm", b"P2 3 3 255 0 0 0 0");
    let msg = error_text(read_image_map(&ascii, &Default::default()));
    assert!(
        msg.contains("truncated: header says 3×3 = 9 samples, file has 4"),
        "{msg}"
    );
}

#[test]
fn wrong_magic_is_an_error_naming_the_file_and_the_bytes_found() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "map.pgm", b"GIF89a\x01\x00\x01\x00");
    let msg = error_text(read_image_map(&path, &Default::default()));
    assert!(msg.contains(&path.display().to_string()), "{msg}");
    assert!(
        msg.contains("unknown image format") && msg.contains("GIF89a"),
        "{msg}"
    );
    let bitmap = write(dir.path(), "bits.pbm", b"P4\n1 1\n\x00");
    let msg = error_text(read_image_map(&bitmap, &Default::default()));
    assert!(msg.contains("P4 is not supported"), "{msg}");
}

#[test]
fn zero_size_and_all_occupied_images_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "zero.pgm", b"P5\n0 5\n255\n");
    let msg = error_text(read_image_map(&path, &Default::default()));
    assert!(
        msg.contains("zero.pgm") && msg.contains("zero-size image: 0×5"),
        "{msg}"
    );
    let path = write(
        dir.path(),
        "black.pgm",
        &p5(2, 2, &[(0, 0), (1, 0), (0, 1), (1, 1)]),
    );
    let msg = error_text(read_image_map(&path, &Default::default()));
    assert!(
        msg.contains("black.pgm") && msg.contains("no free pixel (4 occupied, 0 unknown)"),
        "{msg}"
    );
}

#[test]
fn sample_values_above_maxval_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = b"P5 2 1 100\n".to_vec();
    bytes.extend([0u8, 200]);
    let path = write(dir.path(), "over.pgm", &bytes);
    let msg = error_text(read_image_map(&path, &Default::default()));
    assert!(
        msg.contains("pixel 1 of row 0") && msg.contains("exceeds the header's maxval 100"),
        "{msg}"
    );
    let path = write(dir.path(), "over-ascii.pgm", b"P2 2 1 255 0 70000");
    let msg = error_text(read_image_map(&path, &Default::default()));
    let expected = "sample value 70000 of pixel 1 of row 0 exceeds the header's maxval 255";
    assert!(msg.contains(expected), "{msg}");
}

#[test]
fn bad_bare_image_options_name_the_ros_field() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "ok.pgm", &p5(2, 2, &[]));
    let bad = ImageMapOptions {
        resolution_m: 0.0,
        ..Default::default()
    };
    assert!(error_text(read_image_map(&path, &bad)).contains("field `resolution`: found 0"));
    let bad = ImageMapOptions {
        free_thresh: 0.7,
        ..Default::default()
    };
    assert!(error_text(read_image_map(&path, &bad)).contains("field `free_thresh`"));
    let bad = ImageMapOptions {
        occupied_thresh: 1.5,
        ..Default::default()
    };
    assert!(error_text(read_image_map(&path, &bad)).contains("field `occupied_thresh`: found 1.5"));
}

const GOOD_YAML: &str = "image: map.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n\
                         occupied_thresh: 0.65\nfree_thresh: 0.196\n";

#[test]
fn yaml_pointing_to_a_missing_image_is_a_missing_reference() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = write(dir.path(), "map.yaml", GOOD_YAML.as_bytes());
    let err = read_ros_map(&yaml).unwrap_err();
    assert!(
        matches!(err, WorldError::MissingReference { .. }),
        "{err:?}"
    );
    let msg = err.to_string();
    let image = dir.path().join("map.pgm");
    assert!(msg.starts_with(&yaml.display().to_string()), "{msg}");
    assert!(
        msg.contains("field `image`") && msg.contains(&image.display().to_string()),
        "{msg}"
    );
}

#[test]
fn yaml_with_negative_resolution_names_the_field() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "map.pgm", &p5(2, 2, &[]));
    let yaml = write(
        dir.path(),
        "map.yaml",
        GOOD_YAML.replace("0.05", "-0.05").as_bytes(),
    );
    let msg = error_text(read_ros_map(&yaml));
    assert!(
        msg.contains("map.yaml") && msg.contains("field `resolution`: found -0.05"),
        "{msg}"
    );
}

#[test]
fn yaml_missing_resolution_names_the_field() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "map.pgm", &p5(2, 2, &[]));
    let yaml = write(
        dir.path(),
        "map.yaml",
        GOOD_YAML.replace("resolution: 0.05\n", "").as_bytes(),
    );
    let msg = error_text(read_ros_map(&yaml));
    assert!(
        msg.contains("map.yaml") && msg.contains("field `resolution`: found nothing"),
        "{msg}"
    );
}

/// The map of a 3×2 image with its bottom-left pixel black, read with `origin`.
fn turned(origin: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "map.pgm", &p5(3, 2, &[(0, 1)]));
    let yaml = GOOD_YAML.replace("[0.0, 0.0, 0.0]", origin);
    read_ros_map(&write(dir.path(), "map.yaml", yaml.as_bytes())).unwrap()
}

#[test]
fn a_map_turned_half_round_with_yaw_3_14_is_the_image_turned_exactly() {
    // Real map repositories write 3.14 for π: the image turns about the origin, so it lies
    // south-west of it, and its bottom-left pixel becomes the top-right cell.
    let scene = turned("[1.0, 2.0, 3.14]");
    let g = scene.geometry();
    assert_eq!((g.width, g.height), (3, 2));
    assert!(
        (g.origin.x - 0.85).abs() < 1e-12 && (g.origin.y - 1.9).abs() < 1e-12,
        "{g:?}"
    );
    let walls: Vec<Cell> = (0..g.len())
        .map(|i| g.cell_of_index(i))
        .filter(|&c| scene.is_obstacle(c))
        .collect();
    assert_eq!(walls, vec![Cell::new(2, 1)]);
}

#[test]
fn a_quarter_turn_swaps_width_and_height() {
    // +π/2: image x runs north, image y runs west. The bottom-left pixel stays at the origin's
    // corner: the cell south-east of the turned grid.
    let scene = turned("[0.0, 0.0, 1.5708]");
    let g = scene.geometry();
    assert_eq!((g.width, g.height), (2, 3));
    assert!(
        (g.origin.x + 0.1).abs() < 1e-12 && g.origin.y.abs() < 1e-12,
        "{g:?}"
    );
    let walls: Vec<Cell> = (0..g.len())
        .map(|i| g.cell_of_index(i))
        .filter(|&c| scene.is_obstacle(c))
        .collect();
    assert_eq!(walls, vec![Cell::new(1, 0)]);
}

#[test]
fn an_oblique_turn_covers_the_turned_image_and_walls_the_corners() {
    let scene = turned("[0.0, 0.0, 0.5]");
    let g = scene.geometry();
    // Bounding box of a 3×2 rectangle turned by 0.5 rad: 3 cos + 2 sin ≈ 3.59, 3 sin + 2 cos ≈ 3.19.
    assert_eq!((g.width, g.height), (4, 4));
    let free = (0..g.len())
        .filter(|&i| !scene.is_obstacle(g.cell_of_index(i)))
        .count();
    assert!(
        (3..=6).contains(&free),
        "{free} free cells of 5 free pixels"
    );
}

#[test]
fn yaml_image_may_be_absolute_and_errors_in_it_name_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("images");
    std::fs::create_dir(&sub).unwrap();
    let image = write(&sub, "broken.pgm", b"P5\n4 4\n255\n\x00");
    let text = GOOD_YAML.replace("map.pgm", &image.display().to_string());
    let yaml = write(dir.path(), "abs.yaml", text.as_bytes());
    let msg = error_text(read_ros_map(&yaml));
    assert!(
        msg.starts_with(&image.display().to_string()) && msg.contains("truncated"),
        "{msg}"
    );
}

#[test]
fn write_ros_map_rejects_a_yaml_path_that_would_be_overwritten_by_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let err = write_ros_map(&sample_scene(), &dir.path().join("x.pgm"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("x.pgm") && err.contains("must not end in .pgm"),
        "{err}"
    );
}

/// A 1-bit greyscale PNG of `w`×`h` white pixels, built by hand (zlib stream of zero rows).
fn one_bit_png(w: u32, h: u32) -> Vec<u8> {
    use std::io::Write;
    fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
        out.extend((data.len() as u32).to_be_bytes());
        let mut crc = flate2::Crc::new();
        crc.update(kind);
        crc.update(data);
        out.extend(kind);
        out.extend(data);
        out.extend(crc.sum().to_be_bytes());
    }
    let mut ihdr = Vec::new();
    ihdr.extend(w.to_be_bytes());
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([1, 0, 0, 0, 0]); // bit depth 1, greyscale, deflate, no filter, no interlace
    let row = vec![0xffu8; 1 + (w as usize).div_ceil(8)];
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    for _ in 0..h {
        z.write_all(&[0]).unwrap();
        z.write_all(&row[1..]).unwrap();
    }
    let idat = z.finish().unwrap();
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(&mut out, b"IDAT", &idat);
    chunk(&mut out, b"IEND", &[]);
    out
}

#[test]
fn a_small_png_declaring_400_million_pixels_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let small = write(dir.path(), "small.png", &one_bit_png(40, 30));
    let opts = ImageMapOptions::default();
    assert_eq!(
        read_image_map(&small, &opts).unwrap().geometry().len(),
        1200
    );
    let bomb = one_bit_png(20_000, 20_000);
    assert!(bomb.len() < 200_000, "{} bytes", bomb.len());
    let path = write(dir.path(), "bomb.png", &bomb);
    let msg = error_text(read_image_map(&path, &opts));
    assert!(
        msg.contains("bomb.png") && msg.contains("20000×20000") && msg.contains("--max-cells"),
        "{msg}"
    );
    // The same for a PGM header.
    let pgm = write(dir.path(), "bomb.pgm", b"P5\n20000 20000\n255\n\x00");
    assert!(error_text(read_image_map(&pgm, &opts)).contains("--max-cells"));
}

#[test]
fn absurd_yaml_numbers_name_the_field_and_the_file() {
    for (from, to, field) in [
        ("[0.0, 0.0, 0.0]", "[1e308, -1e308, 0]", "origin"),
        ("resolution: 0.05", "resolution: 1e300", "resolution"),
        ("resolution: 0.05", "resolution: 1e-300", "resolution"),
        ("[0.0, 0.0, 0.0]", "[0.0, 0.0, 1e300]", "origin[2]"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "map.pgm", &p5(4, 4, &[]));
        let yaml = write(
            dir.path(),
            "map.yaml",
            GOOD_YAML.replace(from, to).as_bytes(),
        );
        let msg = error_text(read_ros_map(&yaml));
        assert!(
            msg.contains("map.yaml") && msg.contains(&format!("field `{field}`")),
            "{to}: {msg}"
        );
    }
    // A YAML NaN is refused by the parser, at its place.
    let dir = tempfile::tempdir().unwrap();
    let yaml = GOOD_YAML.replace("[0.0, 0.0, 0.0]", "[0.0, .nan, 0]");
    let msg = error_text(read_ros_map(&write(
        dir.path(),
        "map.yaml",
        yaml.as_bytes(),
    )));
    assert!(
        msg.contains("map.yaml: line 3") && msg.contains("non-finite"),
        "{msg}"
    );
    // A map whose far corner leaves the ±1 000 km box, though its origin is inside it.
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "map.pgm", &p5(4, 4, &[]));
    let yaml = GOOD_YAML.replace("[0.0, 0.0, 0.0]", "[999999.9, 0, 0]");
    let msg = error_text(read_ros_map(&write(
        dir.path(),
        "map.yaml",
        yaml.as_bytes(),
    )));
    assert!(msg.contains("field `origin`"), "{msg}");
}

#[test]
fn deeply_nested_yaml_is_refused_at_once() {
    // 100 000 nested `[` took 29 s with the old parser; the budget stops it at depth 32.
    let dir = tempfile::tempdir().unwrap();
    let text = format!("image: {}\n", "[".repeat(100_000));
    let yaml = write(dir.path(), "deep.yaml", text.as_bytes());
    let msg = error_text(read_ros_map(&yaml));
    assert!(
        msg.starts_with(&format!("{}: line", yaml.display())),
        "{msg}"
    );
    assert_eq!(msg.lines().count(), 1, "{msg}");
}

#[cfg(unix)]
#[test]
fn an_image_that_never_ends_is_refused_at_the_file_limit() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = GOOD_YAML.replace("image: map.pgm", "image: /dev/zero");
    let msg = error_text(read_ros_map(&write(
        dir.path(),
        "map.yaml",
        yaml.as_bytes(),
    )));
    assert!(
        msg.contains("/dev/zero") && msg.contains("file size"),
        "{msg}"
    );
}

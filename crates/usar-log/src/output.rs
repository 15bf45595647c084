//! What `usar map build --from-log` writes: the grid as a ROS `map_server` map (trinary PGM:
//! 0 occupied, 254 free, 205 unknown, as `map_saver` writes) and a picture with the paths.

use crate::mapping::LogMap;
use std::path::Path;
use usar_map::{CellClass, FrontierCluster};
use usar_world::render::Canvas;
use usar_world::{Point2, write_atomic};

/// The PGM grey of each class (ROS `map_saver`).
fn grey(class: CellClass) -> u8 {
    match class {
        CellClass::Occupied => 0,
        CellClass::Free => 254,
        CellClass::Unknown => 205,
    }
}

/// Writes the grid as `yaml_path` and `<stem>.pgm` beside it, both atomically.
pub fn write_ros_map(map: &LogMap, yaml_path: &Path) -> usar_world::Result<()> {
    let g = map.grid.geometry();
    let (w, h) = (g.width as usize, g.height as usize);
    let stem = yaml_path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("map");
    let image_name = format!("{stem}.pgm");
    let mut pgm = format!("P5\n# usar map build --from-log\n{w} {h}\n255\n").into_bytes();
    for row in (0..h).rev() {
        pgm.extend((0..w).map(|col| grey(map.grid.class_at_index(row * w + col))));
    }
    let yaml = format!(
        "image: {image_name}\nmode: trinary\nresolution: {:?}\norigin: [{:?}, {:?}, 0.0]\n\
         negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
        g.resolution_m, g.origin.x, g.origin.y
    );
    write_atomic(&yaml_path.with_file_name(&image_name), &pgm)?;
    write_atomic(yaml_path, yaml.as_bytes())
}

/// The grid (black occupied, white free, grey unknown) with the laser's path by odometry
/// (blue), by the estimate (red) and as the log stamps it (green, when it is not odometry),
/// `frontiers` (cyan) and their candidates (magenta crosses), its larger side at most
/// `max_side_px`.
pub fn picture(map: &LogMap, frontiers: &[FrontierCluster], max_side_px: u32) -> Canvas {
    let g = *map.grid.geometry();
    let mut canvas = Canvas::fit(g, max_side_px);
    for i in 0..g.len() {
        let v = grey(map.grid.class_at_index(i));
        if v != 254 {
            canvas.fill_cell(g.cell_of_index(i), [v; 3]);
        }
    }
    let path = |f: &dyn Fn(&crate::mapping::TrajectoryPoint) -> Option<Point2>| -> Vec<Point2> {
        map.trajectory.iter().filter_map(f).collect()
    };
    let start = map.trajectory[0];
    if map.drift.odometry_vs_logged.is_some() {
        // The log's poses, aligned at the first scan as the drift figures are.
        let aligned = |p| {
            usar_map::localization::compose(
                start.estimate,
                usar_map::localization::relative(start.logged.expect("logged"), p),
            )
        };
        canvas.draw_polyline(
            &path(&|t| t.logged.map(|p| aligned(p).position())),
            [0, 160, 0],
        );
    }
    canvas.draw_polyline(&path(&|t| Some(t.odometry.position())), [40, 80, 230]);
    canvas.draw_polyline(&path(&|t| Some(t.estimate.position())), [220, 30, 30]);
    for f in frontiers {
        for &c in &f.cells {
            canvas.fill_cell(c, [0, 190, 220]);
        }
        canvas.draw_cross(g.cell_center(f.candidate), 0.4, [200, 0, 200]);
    }
    canvas
}

//! Rotated maps: a ROS `map_server` origin carries a yaw, and real map repositories use it
//! (`origin: [x, y, 3.14]`). The image is turned about its lower-left corner into an
//! axis-aligned grid, since every usar grid is axis-aligned.

use super::image_map::PixelCounts;
use crate::error::Result;
use crate::geometry::Point2;
use crate::grid::GridGeometry;
use crate::scene::obstacle;
use std::path::Path;

/// Yaws within this many radians of a quarter turn are that quarter turn: real map files
/// write `3.14` for π, and a turn of exactly k·π/2 moves every pixel onto a cell unchanged.
pub const QUARTER_TURN_TOLERANCE_RAD: f64 = 0.01;

/// Turns an obstacle layer (rows south to north) about its lower-left corner by `yaw`
/// counter-clockwise into an axis-aligned grid of the same cell size covering the turned image.
///
/// Each new cell takes the pixel under its centre, p = R(−yaw)·(c − origin) / resolution
/// (nearest neighbour); cells outside the image are walls, as unknown pixels are. A yaw within
/// [`QUARTER_TURN_TOLERANCE_RAD`] of k·π/2 is taken as exactly k quarter turns, so the cells
/// are permuted, not resampled. The counts are of the turned grid (outside cells as occupied).
pub fn rotate_obstacles(
    geometry: &GridGeometry,
    obstacles: &[u8],
    yaw: f64,
    path: &Path,
) -> Result<(GridGeometry, Vec<u8>, PixelCounts)> {
    let quarter = (yaw / std::f64::consts::FRAC_PI_2).round();
    let (sin, cos) =
        if (yaw - quarter * std::f64::consts::FRAC_PI_2).abs() <= QUARTER_TURN_TOLERANCE_RAD {
            match quarter.rem_euclid(4.0) as u8 {
                0 => (0.0, 1.0),
                1 => (1.0, 0.0),
                2 => (0.0, -1.0),
                _ => (-1.0, 0.0),
            }
        } else {
            yaw.sin_cos()
        };
    let r = geometry.resolution_m;
    let (w, h) = (f64::from(geometry.width), f64::from(geometry.height));
    let corners = [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)].map(|(u, v)| {
        (u * cos - v * sin, u * sin + v * cos) // in cells, about the origin
    });
    let min_x = corners.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
    let min_y = corners.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
    let max_x = corners
        .iter()
        .map(|c| c.0)
        .fold(f64::NEG_INFINITY, f64::max);
    let max_y = corners
        .iter()
        .map(|c| c.1)
        .fold(f64::NEG_INFINITY, f64::max);
    // A hair below the next integer: exact quarter turns must not gain a row.
    let new_w = (max_x - min_x - 1e-9).ceil().max(1.0) as u64;
    let new_h = (max_y - min_y - 1e-9).ceil().max(1.0) as u64;
    crate::limits::check_cells(path, "image size after rotation by origin[2]", new_w, new_h)?;
    let origin = Point2::new(geometry.origin.x + min_x * r, geometry.origin.y + min_y * r);
    let turned = GridGeometry::new(new_w as u32, new_h as u32, r, origin);
    crate::scene::check_extent(origin, turned.extent_m(), "origin", path)?;
    let mut out = vec![obstacle::WALL; (new_w * new_h) as usize];
    let mut counts = PixelCounts::default();
    for row in 0..new_h {
        for col in 0..new_w {
            // Cell centre relative to the old origin, in cells; then into the image's frame.
            let (x, y) = (min_x + col as f64 + 0.5, min_y + row as f64 + 0.5);
            let (u, v) = (x * cos + y * sin, -x * sin + y * cos);
            let i = (row * new_w + col) as usize;
            if u >= 0.0 && v >= 0.0 && u < w && v < h {
                out[i] = obstacles[v as usize * geometry.width as usize + u as usize];
            }
            if out[i] == obstacle::NONE {
                counts.free += 1;
            } else {
                counts.occupied += 1;
            }
        }
    }
    Ok((turned, out, counts))
}

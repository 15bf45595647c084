//! Obstacle inflation: grow every obstacle by a robot's radius so that a planner may treat the
//! robot as a point (the configuration space of a disc robot, Lozano-Pérez 1983).

use usar_world::Grid;

/// Slack added to the squared radius in cells², so that a radius that is an exact multiple of
/// the resolution (0.3 m on a 0.1 m grid) includes the cells at exactly that distance despite
/// the rounding of `radius_m / resolution_m`.
const RADIUS_SLACK_CELLS2: f64 = 1e-9;

/// The blocked mask grown by `radius_m`: a cell is blocked when its centre lies within
/// `radius_m` (Euclidean, inclusive) of the centre of a blocked cell of `blocked`.
///
/// A radius that is negative, zero or NaN leaves the mask as it is; an infinite radius blocks
/// every cell as soon as one is blocked.
///
/// Only blocked cells with a free 4-neighbour stamp their disc: the blocked cell nearest to any
/// free cell always has one (its neighbour toward the free cell is closer, so it is free), so
/// the result is the same as stamping from every blocked cell. Each disc is stamped as one run
/// per row.
pub fn inflate(blocked: &Grid<bool>, radius_m: f64) -> Grid<bool> {
    let g = *blocked.geometry();
    let mut out = blocked.clone();
    if radius_m.is_nan() || radius_m <= 0.0 || g.is_empty() {
        return out;
    }
    let (w, h) = (g.width as usize, g.height as usize);
    // A disc larger than the grid's diagonal covers everything it can.
    let max_radius_cells = ((w * w + h * h) as f64).sqrt() + 1.0;
    let radius_cells = (radius_m / g.resolution_m).min(max_radius_cells);
    let radius2 = radius_cells * radius_cells + RADIUS_SLACK_CELLS2;
    let reach = radius2.sqrt().floor() as usize;
    // Half-width of the disc's run on each row offset `dy` (0..=reach).
    let half_widths: Vec<usize> = (0..=reach)
        .map(|dy| (radius2 - (dy * dy) as f64).max(0.0).sqrt().floor() as usize)
        .collect();

    let src = blocked.as_slice();
    let dst = out.as_mut_slice();
    for row in 0..h {
        let line = &src[row * w..(row + 1) * w];
        for (col, &is_blocked) in line.iter().enumerate() {
            if !is_blocked || !borders_free(src, w, h, col, row) {
                continue;
            }
            let row_lo = row.saturating_sub(reach);
            let row_hi = (row + reach).min(h - 1);
            for r in row_lo..=row_hi {
                let half = half_widths[r.abs_diff(row)];
                let lo = col.saturating_sub(half);
                let hi = (col + half).min(w - 1);
                dst[r * w + lo..=r * w + hi].fill(true);
            }
        }
    }
    out
}

/// True if a 4-neighbour of (col, row) is inside the grid and free.
#[inline]
fn borders_free(src: &[bool], w: usize, h: usize, col: usize, row: usize) -> bool {
    let i = row * w + col;
    (col > 0 && !src[i - 1])
        || (col + 1 < w && !src[i + 1])
        || (row > 0 && !src[i - w])
        || (row + 1 < h && !src[i + w])
}

#[cfg(test)]
mod tests {
    use super::*;
    use usar_world::{Cell, GridGeometry, Point2};

    #[test]
    fn single_obstacle_grows_into_an_exact_disc() {
        let g = GridGeometry::new(11, 11, 0.1, Point2::new(0.0, 0.0));
        let mut blocked = Grid::filled(g, false);
        blocked[Cell::new(5, 5)] = true;
        let out = inflate(&blocked, 0.3);
        // Cells whose centres are within 3 cells: 29 (the lattice points of a radius-3 disc).
        assert_eq!(out.as_slice().iter().filter(|&&b| b).count(), 29);
        assert!(out[Cell::new(8, 5)]);
        assert!(out[Cell::new(7, 7)]);
        assert!(!out[Cell::new(8, 6)]);
        assert_eq!(inflate(&blocked, 0.0), blocked);
        assert_eq!(inflate(&blocked, f64::NAN), blocked);
        assert!(
            inflate(&blocked, f64::INFINITY)
                .as_slice()
                .iter()
                .all(|&b| b)
        );
    }
}

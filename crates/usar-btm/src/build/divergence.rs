//! Divergence nodes (paper 004 §III-A-1, Fig. 2): Delaunay triangulation of the laser points
//! in the band Ω₁ = {(x, y) | D1 < x < D2} ahead, the nearest acute triangle whose sides are
//! all at least a robot width, its circumcentre; and the links leaving it: gaps wider than
//! the robot between the angle-sorted points inside the search circle.

use crate::model::subtype;
use spade::{DelaunayTriangulation, Triangulation};
use usar_world::{Point2, normalize_angle};

/// A triangle kept by the filters of Fig. 2 (d), in the frame of the points given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DivergenceTriangle {
    pub vertices: [Point2; 3],
    pub circumcentre: Point2,
    pub circumradius_m: f64,
}

/// The triangles of the Delaunay triangulation of `points` (robot frame) inside the band
/// `near_m < x < far_m`, |y| < `far_m`, that are neither obtuse (largest angle above
/// 90° + `obtuse_tolerance_rad`) nor have a side shorter than `min_side_m` (the robot
/// width); the one whose circumcentre is nearest the robot (the origin) first.
pub fn divergence_triangles(
    points: &[Point2],
    near_m: f64,
    far_m: f64,
    min_side_m: f64,
    obtuse_tolerance_rad: f64,
) -> Vec<DivergenceTriangle> {
    let band: Vec<spade::Point2<f64>> = points
        .iter()
        .filter(|p| p.x > near_m && p.x < far_m && p.y.abs() < far_m)
        .map(|p| spade::Point2::new(p.x, p.y))
        .collect();
    if band.len() < 3 {
        return Vec::new();
    }
    let Ok(triangulation) = DelaunayTriangulation::<spade::Point2<f64>>::bulk_load(band) else {
        return Vec::new();
    };
    let cos_limit = -obtuse_tolerance_rad.sin();
    let mut kept: Vec<DivergenceTriangle> = triangulation
        .inner_faces()
        .filter_map(|face| {
            let [a, b, c] = face.positions().map(|p| Point2::new(p.x, p.y));
            let mut sides = [a.distance(b), b.distance(c), c.distance(a)];
            sides.sort_by(f64::total_cmp);
            let [s0, s1, longest] = sides;
            if s0 < min_side_m {
                return None;
            }
            // Law of cosines for the angle opposite the longest side.
            let cos_max = (s0 * s0 + s1 * s1 - longest * longest) / (2.0 * s0 * s1);
            if cos_max < cos_limit {
                return None;
            }
            let (centre, radius) = circumcircle(a, b, c)?;
            Some(DivergenceTriangle {
                vertices: [a, b, c],
                circumcentre: centre,
                circumradius_m: radius,
            })
        })
        .collect();
    kept.sort_by(|p, q| {
        let (dp, dq) = (
            p.circumcentre.distance_squared(Point2::default()),
            q.circumcentre.distance_squared(Point2::default()),
        );
        dp.total_cmp(&dq)
            .then(p.circumcentre.x.total_cmp(&q.circumcentre.x))
    });
    kept
}

/// Centre and radius of the circle through three points, `None` when they are collinear.
pub fn circumcircle(a: Point2, b: Point2, c: Point2) -> Option<(Point2, f64)> {
    let (bx, by) = (b.x - a.x, b.y - a.y);
    let (cx, cy) = (c.x - a.x, c.y - a.y);
    let d = 2.0 * (bx * cy - by * cx);
    if d.abs() < 1e-12 {
        return None;
    }
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    let ux = (cy * b2 - by * c2) / d;
    let uy = (bx * c2 - cx * b2) / d;
    Some((Point2::new(a.x + ux, a.y + uy), ux.hypot(uy)))
}

/// The open directions around `centre` (Fig. 2 f): the points within `radius_m` sorted by
/// angle; wherever two neighbours are further apart than `min_gap_m` (the robot width) a
/// passage leaves, in the direction of the midpoint of the two points. Directions in
/// radians, counter-clockwise from +x, ascending in [0, 2π). Empty when fewer than two
/// points lie in the circle (nothing to tell openings apart).
pub fn open_directions(
    points: &[Point2],
    centre: Point2,
    radius_m: f64,
    min_gap_m: f64,
) -> Vec<f64> {
    let mut around: Vec<(f64, Point2)> = points
        .iter()
        .filter(|p| p.distance_squared(centre) <= radius_m * radius_m)
        .map(|&p| (centre.bearing_to(p).rem_euclid(std::f64::consts::TAU), p))
        .collect();
    if around.len() < 2 {
        return Vec::new();
    }
    around.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = around.len();
    let mut directions: Vec<f64> = (0..n)
        .filter_map(|i| {
            let (p, q) = (around[i].1, around[(i + 1) % n].1);
            (p.distance(q) > min_gap_m).then(|| {
                let mid = Point2::new((p.x + q.x) / 2.0, (p.y + q.y) / 2.0);
                let mut dir = centre.bearing_to(mid);
                // The midpoint of a gap spanning more than half the circle lies behind the
                // centre: take the bisector of the angular gap instead.
                let (a0, a1) = (around[i].0, around[(i + 1) % n].0);
                let span = (a1 - a0).rem_euclid(std::f64::consts::TAU);
                if span > std::f64::consts::PI {
                    dir = a0 + span / 2.0;
                }
                dir.rem_euclid(std::f64::consts::TAU)
            })
        })
        .collect();
    directions.sort_by(f64::total_cmp);
    directions
}

/// Margin on each side of the robot of the lane checked by
/// [`crate::locomotion::lane_open_m`] for a link.
pub const LINK_LANE_MARGIN_M: f64 = 0.05;

/// The divergence subtype for a set of open directions: one is a dead end, two a corner
/// (unless nearly opposite: a plain passage, `None`), three a T junction, more a crossing.
pub fn divergence_subtype(directions: &[f64], straight_tolerance_rad: f64) -> Option<&'static str> {
    match directions.len() {
        0 => None,
        1 => Some(subtype::DEAD_END),
        2 => {
            let turn = normalize_angle(directions[1] - directions[0]).abs();
            if turn > std::f64::consts::PI - straight_tolerance_rad {
                None
            } else {
                Some(subtype::CORNER)
            }
        }
        3 => Some(subtype::T_JUNCTION),
        _ => Some(subtype::CROSSING),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Wall points every 2 cm along a segment.
    fn wall(a: Point2, b: Point2) -> Vec<Point2> {
        let n = (a.distance(b) / 0.02).ceil() as usize;
        (0..=n)
            .map(|i| {
                let t = i as f64 / n as f64;
                Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y))
            })
            .collect()
    }

    /// A T junction ahead of a robot at the origin heading +x: the stem (1.6 m wide) ends at
    /// x = 3.2 in a crossbar along y.
    fn t_junction() -> Vec<Point2> {
        let p = Point2::new;
        [
            wall(p(0.0, 0.8), p(2.4, 0.8)),
            wall(p(0.0, -0.8), p(2.4, -0.8)),
            wall(p(2.4, 0.8), p(2.4, 5.0)),
            wall(p(2.4, -0.8), p(2.4, -5.0)),
            wall(p(4.0, -5.0), p(4.0, 5.0)),
        ]
        .concat()
    }

    #[test]
    fn the_nearest_triangle_of_a_t_junction_has_its_circumcentre_near_the_junction_centre() {
        let tris = divergence_triangles(&t_junction(), 0.3, 6.0, 0.45, 8f64.to_radians());
        let best = tris.first().expect("a triangle");
        assert!(
            best.circumcentre.distance(Point2::new(3.2, 0.0)) < 0.5,
            "{best:?}"
        );
    }

    #[test]
    fn a_plain_passage_has_no_divergence_triangle() {
        let p = Point2::new;
        let pts = [
            wall(p(0.0, 0.8), p(4.0, 0.8)),
            wall(p(0.0, -0.8), p(4.0, -0.8)),
        ]
        .concat();
        assert!(divergence_triangles(&pts, 0.3, 4.0, 0.45, 8f64.to_radians()).is_empty());
    }

    #[test]
    fn open_directions_of_a_t_junction_are_back_left_and_right() {
        let dirs = open_directions(&t_junction(), Point2::new(3.2, 0.0), 1.5, 0.45);
        assert_eq!(dirs.len(), 3, "{dirs:?}");
        let expect = [
            std::f64::consts::FRAC_PI_2,
            std::f64::consts::PI,
            1.5 * std::f64::consts::PI,
        ];
        for (d, e) in dirs.iter().zip(expect) {
            assert!(normalize_angle(d - e).abs() < 0.2, "{dirs:?}");
        }
        assert_eq!(divergence_subtype(&dirs, 0.6), Some(subtype::T_JUNCTION));
    }

    #[test]
    fn a_dead_end_has_one_open_direction() {
        let p = Point2::new;
        let pts = [
            wall(p(0.0, 0.8), p(3.0, 0.8)),
            wall(p(0.0, -0.8), p(3.0, -0.8)),
            wall(p(3.0, -0.8), p(3.0, 0.8)),
        ]
        .concat();
        let tris = divergence_triangles(&pts, 0.3, 4.0, 0.45, 8f64.to_radians());
        let best = tris.first().expect("a triangle");
        assert!(best.circumcentre.distance(p(2.2, 0.0)) < 0.3, "{best:?}");
        let dirs = open_directions(&pts, best.circumcentre, best.circumradius_m + 0.5, 0.45);
        assert_eq!(
            divergence_subtype(&dirs, 0.6),
            Some(subtype::DEAD_END),
            "{dirs:?}"
        );
    }

    #[test]
    fn circumcircle_of_a_right_triangle_is_centred_on_its_hypotenuse() {
        let (c, r) = circumcircle(
            Point2::new(0.0, 0.0),
            Point2::new(2.0, 0.0),
            Point2::new(0.0, 2.0),
        )
        .unwrap();
        assert!((c.x - 1.0).abs() < 1e-12 && (c.y - 1.0).abs() < 1e-12);
        assert!((r - 2f64.sqrt()).abs() < 1e-12);
        assert!(
            circumcircle(
                Point2::new(0.0, 0.0),
                Point2::new(1.0, 1.0),
                Point2::new(2.0, 2.0)
            )
            .is_none()
        );
    }
}

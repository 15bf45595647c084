//! The horizontal laser scan in the robot frame (x forward, y left) and the measures taken on
//! it: the minimum lateral distances L_l and L_r inside a grey strip (paper 004 Figs. 3, 9)
//! and ranges along a bearing.

use usar_readings::LaserScan;
use usar_world::Point2;

/// One scan as points in the robot frame. Built only from the ranges and the beam angles
/// relative to the heading: the simulator's true pose stored in the scan is never read.
#[derive(Clone, Debug, Default)]
pub struct ScanView {
    /// Per beam: the return in the robot frame, or `None` when the beam met nothing.
    pub beams: Vec<Option<Point2>>,
    /// The returns only, in beam order.
    pub points: Vec<Point2>,
    pub angle_min_rad: f64,
    pub angle_increment_rad: f64,
    pub max_range_m: f64,
}

/// Minimum lateral distances on the left (L_l) and right (L_r), metres; the laser's maximum
/// range when a side has no point in the strip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideClearance {
    pub left_m: f64,
    pub right_m: f64,
}

impl SideClearance {
    /// L_l + L_r: the free width across the strip.
    pub fn width_m(&self) -> f64 {
        self.left_m + self.right_m
    }
}

impl ScanView {
    pub fn from_scan(scan: &LaserScan) -> Self {
        let mut view = ScanView {
            beams: Vec::with_capacity(scan.ranges_m.len()),
            points: Vec::with_capacity(scan.ranges_m.len()),
            angle_min_rad: scan.angle_min_rad,
            angle_increment_rad: scan.angle_increment_rad,
            max_range_m: scan.max_range_m,
        };
        for (i, &r) in scan.ranges_m.iter().enumerate() {
            let r = f64::from(r);
            if r.is_finite() {
                let a = scan.angle_min_rad + i as f64 * scan.angle_increment_rad;
                let p = Point2::new(r * a.cos(), r * a.sin());
                view.beams.push(Some(p));
                view.points.push(p);
            } else {
                view.beams.push(None);
            }
        }
        view
    }

    /// L_l and L_r among the points with `x_min ≤ x ≤ x_max` (robot frame), ignoring points
    /// for which `keep` is false.
    pub fn side_clearance_where(
        &self,
        x_min: f64,
        x_max: f64,
        keep: impl Fn(Point2) -> bool,
    ) -> SideClearance {
        let mut c = SideClearance {
            left_m: self.max_range_m,
            right_m: self.max_range_m,
        };
        for &p in &self.points {
            if p.x < x_min || p.x > x_max || !keep(p) {
                continue;
            }
            if p.y >= 0.0 {
                c.left_m = c.left_m.min(p.y);
            } else {
                c.right_m = c.right_m.min(-p.y);
            }
        }
        c
    }

    /// L_l and L_r in the strip `x_min ≤ x ≤ x_max`.
    pub fn side_clearance(&self, x_min: f64, x_max: f64) -> SideClearance {
        self.side_clearance_where(x_min, x_max, |_| true)
    }

    /// The shortest range among beams within `half_width_rad` of `bearing_rad` (robot frame);
    /// the maximum range when none returned.
    pub fn min_range_near(&self, bearing_rad: f64, half_width_rad: f64) -> f64 {
        let n = self.beams.len();
        if n == 0 || self.angle_increment_rad <= 0.0 {
            return self.max_range_m;
        }
        let centre = (usar_world::normalize_angle(bearing_rad - self.angle_min_rad)
            / self.angle_increment_rad)
            .round() as i64;
        let k = (half_width_rad / self.angle_increment_rad).ceil() as i64;
        let mut best = self.max_range_m;
        for j in centre - k..=centre + k {
            if let Some(p) = self.beams[j.rem_euclid(n as i64) as usize] {
                best = best.min(p.x.hypot(p.y));
            }
        }
        best
    }

    /// Distance to the nearest point inside the corridor swept by a robot of `half_width_m`
    /// driving straight ahead (x > 0, |y| ≤ half width), or the maximum range.
    pub fn front_clearance(&self, half_width_m: f64) -> f64 {
        self.nearest_ahead(half_width_m)
            .map_or(self.max_range_m, |p| p.x.min(self.max_range_m))
    }

    /// The nearest point (smallest x) ahead of the robot within `half_width_m` of its axis.
    pub fn nearest_ahead(&self, half_width_m: f64) -> Option<Point2> {
        self.points
            .iter()
            .filter(|p| p.x > 0.0 && p.y.abs() <= half_width_m)
            .min_by(|a, b| a.x.total_cmp(&b.x))
            .copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn corridor_scan() -> LaserScan {
        // A robot in the middle of a 1.6 m corridor along x: walls at y = ±0.8.
        let n = 360;
        let inc = 2.0 * PI / n as f64;
        let ranges = (0..n)
            .map(|i| {
                let a = -PI + i as f64 * inc;
                let s = a.sin().abs();
                if s < 1e-6 {
                    f32::INFINITY
                } else {
                    (0.8 / s) as f32
                }
            })
            .collect();
        LaserScan {
            pose: Default::default(),
            angle_min_rad: -PI,
            angle_increment_rad: inc,
            max_range_m: 20.0,
            ranges_m: ranges,
        }
    }

    #[test]
    fn side_clearance_in_a_corridor_is_half_its_width_each_side() {
        let view = ScanView::from_scan(&corridor_scan());
        let c = view.side_clearance(0.0, 0.8);
        assert!((c.left_m - 0.8).abs() < 1e-3, "{c:?}");
        assert!((c.right_m - 0.8).abs() < 1e-3, "{c:?}");
        assert!((c.width_m() - 1.6).abs() < 1e-3);
        assert_eq!(view.front_clearance(0.3), 20.0);
        assert!((view.min_range_near(PI / 2.0, 0.02) - 0.8).abs() < 1e-3);
    }
}

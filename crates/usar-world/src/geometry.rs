//! Points, poses and angles in the world frame.
//!
//! World frame (shared by every crate): x to the right (east), y up (north), angles in radians
//! counter-clockwise from +x. "North" is +y.

use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// A point in the world frame, metres.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Point2 {
    pub x: f64,
    pub y: f64,
}

impl Point2 {
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }

    pub fn distance(self, other: Point2) -> f64 {
        (self.x - other.x).hypot(self.y - other.y)
    }

    pub fn distance_squared(self, other: Point2) -> f64 {
        let (dx, dy) = (self.x - other.x, self.y - other.y);
        dx * dx + dy * dy
    }

    /// Bearing from `self` to `other`, radians counter-clockwise from +x.
    pub fn bearing_to(self, other: Point2) -> f64 {
        (other.y - self.y).atan2(other.x - self.x)
    }

    /// The point `range_m` away from `self` in direction `angle_rad`.
    pub fn offset(self, angle_rad: f64, range_m: f64) -> Point2 {
        Point2::new(
            self.x + range_m * angle_rad.cos(),
            self.y + range_m * angle_rad.sin(),
        )
    }
}

/// A planar pose: position and heading (radians, counter-clockwise from +x).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pose2 {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

impl Pose2 {
    pub const fn new(x: f64, y: f64, theta: f64) -> Self {
        Self { x, y, theta }
    }

    pub fn position(self) -> Point2 {
        Point2::new(self.x, self.y)
    }

    /// Transforms a point given in this pose's body frame (x forward, y left) to the world frame.
    pub fn to_world(self, body: Point2) -> Point2 {
        self.body_to_world().apply(body)
    }

    /// [`Pose2::to_world`] with the heading's sine and cosine computed once, for many points.
    pub fn body_to_world(self) -> BodyToWorld {
        let (s, c) = self.theta.sin_cos();
        BodyToWorld {
            x: self.x,
            y: self.y,
            s,
            c,
        }
    }

    /// Transforms a world point into this pose's body frame (x forward, y left).
    pub fn to_body(self, world: Point2) -> Point2 {
        let (s, c) = self.theta.sin_cos();
        let (dx, dy) = (world.x - self.x, world.y - self.y);
        Point2::new(c * dx + s * dy, -s * dx + c * dy)
    }
}

/// Wraps an angle to (−π, π].
pub fn normalize_angle(angle_rad: f64) -> f64 {
    let mut a = angle_rad % TAU;
    if a <= -PI {
        a += TAU;
    } else if a > PI {
        a -= TAU;
    }
    a
}

/// An axis-aligned rectangle in world coordinates, metres.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rect {
    pub min: Point2,
    pub max: Point2,
}

impl Rect {
    pub fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Self {
            min: Point2::new(x0.min(x1), y0.min(y1)),
            max: Point2::new(x0.max(x1), y0.max(y1)),
        }
    }

    pub fn width(&self) -> f64 {
        self.max.x - self.min.x
    }

    pub fn height(&self) -> f64 {
        self.max.y - self.min.y
    }

    pub fn area(&self) -> f64 {
        self.width() * self.height()
    }

    pub fn center(&self) -> Point2 {
        Point2::new(
            (self.min.x + self.max.x) / 2.0,
            (self.min.y + self.max.y) / 2.0,
        )
    }

    pub fn contains(&self, p: Point2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }
}

/// A pose's body-to-world transform ([`Pose2::body_to_world`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyToWorld {
    x: f64,
    y: f64,
    s: f64,
    c: f64,
}

impl BodyToWorld {
    /// The world point of `body` (x forward, y left in the pose's frame).
    #[inline]
    pub fn apply(&self, body: Point2) -> Point2 {
        Point2::new(
            self.x + self.c * body.x - self.s * body.y,
            self.y + self.s * body.x + self.c * body.y,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_angle_wraps_into_half_open_interval() {
        assert!((normalize_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((normalize_angle(-PI) - PI).abs() < 1e-12);
        assert!((normalize_angle(0.5) - 0.5).abs() < 1e-12);
        assert!((normalize_angle(-7.0) - (-7.0 + TAU)).abs() < 1e-12);
    }

    #[test]
    fn body_and_world_frames_are_inverse() {
        let pose = Pose2::new(1.0, -2.0, 0.7);
        let p = Point2::new(3.0, 4.0);
        let back = pose.to_world(pose.to_body(p));
        assert!(back.distance(p) < 1e-12);
        // Forward of a north-facing robot is +y.
        let north = Pose2::new(0.0, 0.0, PI / 2.0).to_world(Point2::new(1.0, 0.0));
        assert!(north.distance(Point2::new(0.0, 1.0)) < 1e-12);
    }
}

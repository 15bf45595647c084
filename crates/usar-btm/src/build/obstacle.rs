//! Obstacle nodes (paper 004 §III-A-2, Figs. 4–5): the laser tilted down by θ returns the
//! range L on level floor and l₁ < L on an obstacle, whose height is (L − l₁)·cos θ. While
//! the robot drives across, these heights against the odometric distance form the obstacle
//! profile; a least-squares line through a piece of it tells a slope (small residual
//! variance) from stairs (variance above V_max).

use usar_sim::sensors::{TiltedLaserSpec, TiltedScan};

/// One tilted-laser return in the robot frame: forward and lateral distance of the hit on
/// the floor, and its height above the floor under the robot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorHit {
    pub forward_m: f64,
    pub lateral_m: f64,
    pub height_m: f64,
}

/// The returns of one tilted sweep. Beam i lies in the tilted plane at yaw φᵢ; with
/// p = π/2 − θ its pitch below the horizon is asin(sin p·cos φᵢ), so a range r hits at height
/// H − r·sin(pitch) — for the central beam H − r·cos θ = (L − r)·cos θ (Fig. 5).
pub fn floor_hits(spec: &TiltedLaserSpec, scan: &TiltedScan) -> Vec<FloorHit> {
    let p = std::f64::consts::FRAC_PI_2 - spec.tilt_from_vertical_rad;
    let (sp, cp) = p.sin_cos();
    scan.ranges_m
        .iter()
        .enumerate()
        .filter_map(|(i, &r)| {
            let r = f64::from(r);
            if !r.is_finite() {
                return None;
            }
            let phi = scan.yaw_min_rad + i as f64 * scan.yaw_increment_rad;
            let (sphi, cphi) = phi.sin_cos();
            Some(FloorHit {
                forward_m: r * cphi * cp,
                lateral_m: r * sphi,
                height_m: spec.mount_height_m - r * cphi * sp,
            })
        })
        .collect()
}

/// Median forward distance and height of the hits under the robot's own track
/// (|lateral| ≤ `half_width_m`), or `None` when there are none.
pub fn track_sample(
    hits: impl IntoIterator<Item = FloorHit>,
    half_width_m: f64,
) -> Option<FloorHit> {
    let mut on_track: Vec<FloorHit> = hits
        .into_iter()
        .filter(|h| h.lateral_m.abs() <= half_width_m)
        .collect();
    if on_track.is_empty() {
        return None;
    }
    let mid = on_track.len() / 2;
    on_track.sort_by(|a, b| a.height_m.total_cmp(&b.height_m));
    let height_m = on_track[mid].height_m;
    on_track.sort_by(|a, b| a.forward_m.total_cmp(&b.forward_m));
    Some(FloorHit {
        forward_m: on_track[mid].forward_m,
        lateral_m: 0.0,
        height_m,
    })
}

/// Kind of an obstacle piece.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObstacleShape {
    Slope,
    Stairs,
}

/// A non-level piece of the profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstaclePiece {
    /// Where it starts and where the last return on it lies, metres along the path.
    pub start_m: f64,
    pub end_m: f64,
    /// Whether the floor rises in the direction of travel.
    pub rising: bool,
    pub shape: ObstacleShape,
    /// Inclination of the least-squares line, radians (both shapes).
    pub inclination_rad: f64,
    /// Standard deviation of the residuals about that line, metres (√V).
    pub residual_sd_m: f64,
    /// Highest riser seen, metres (stairs only).
    pub step_height_m: Option<f64>,
}

/// Whether the robot may drive onto the obstacle ahead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Passability {
    /// Not enough of the obstacle seen yet.
    Undecided,
    Passable,
    /// Steeper or higher than the robot can climb; the estimate that said so.
    Impassable {
        inclination_rad: f64,
        step_m: Option<f64>,
    },
}

/// Width of the bins the profile is reduced to, metres.
const BIN_M: f64 = 0.05;
/// A riser is a height change of more than this within [`RISER_RUN_M`]; lower ones are the
/// roughness of a ramp on a grid (a 20° ramp on a 0.1 m grid rises 3.6 cm per cell).
const RISER_MIN_M: f64 = 0.05;
/// Shortest run over which a grade is taken for the passability judgement, metres.
const GRADE_BASE_M: f64 = 0.1;
/// Horizontal window within which a riser's height is measured: about a vertical face.
const RISER_RUN_M: f64 = 0.06;

/// The obstacle profile of Fig. 4 seen from level floor: (distance along the path, height
/// above the floor the robot stands on) pairs. Only returns taken while the robot stands
/// level are exact (the tilted laser's plane is fixed to the body), so the robot observes
/// an obstacle from the level floor before it, and the next from the level top of it.
#[derive(Clone, Debug, Default)]
pub struct ObstacleProfile {
    points: Vec<(f64, f64)>,
}

impl ObstacleProfile {
    pub fn push(&mut self, along_m: f64, height_m: f64) {
        if along_m.is_finite() && height_m.is_finite() {
            self.points.push((along_m, height_m));
        }
    }

    /// The (distance, height) points as recorded.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The profile reduced to the median height per [`BIN_M`] bin, ascending in distance.
    fn bins(&self) -> Vec<(f64, f64)> {
        let mut pts = self.points.clone();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out = Vec::new();
        let mut i = 0;
        while i < pts.len() {
            let bin = (pts[i].0 / BIN_M).floor();
            let mut zs = Vec::new();
            let mut j = i;
            while j < pts.len() && (pts[j].0 / BIN_M).floor() == bin {
                zs.push(pts[j].1);
                j += 1;
            }
            zs.sort_by(f64::total_cmp);
            out.push(((bin + 0.5) * BIN_M, zs[zs.len() / 2]));
            i = j;
        }
        out
    }

    /// The highest riser among the points beyond `from_m`: the largest height range, about
    /// the points' least-squares line, inside any window [`RISER_RUN_M`] long, if above
    /// [`RISER_MIN_M`]. (Taken about the line, a ramp's rise across the window is not a
    /// riser.)
    fn max_riser(&self, from_m: f64) -> Option<f64> {
        let mut pts: Vec<(f64, f64)> = self
            .points
            .iter()
            .copied()
            .filter(|p| p.0 >= from_m)
            .collect();
        let slope = line_fit(&pts).map_or(0.0, |f| f.slope);
        for p in &mut pts {
            p.1 -= slope * p.0;
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best: f64 = 0.0;
        let mut j = 0;
        for i in 0..pts.len() {
            j = j.max(i);
            while j + 1 < pts.len() && pts[j + 1].0 - pts[i].0 <= RISER_RUN_M {
                j += 1;
            }
            let (lo, hi) = pts[i..=j]
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.1), hi.max(p.1))
                });
            best = best.max(hi - lo);
        }
        (best > RISER_MIN_M).then_some(best)
    }

    /// Judges the obstacle ahead for a robot that climbs `max_inclination_rad` and steps of
    /// `max_step_m`, from the part of the profile beyond `from_m` (where it was detected).
    pub fn passability(
        &self,
        from_m: f64,
        judge_length_m: f64,
        max_inclination_rad: f64,
        max_step_m: f64,
    ) -> Passability {
        let seen: Vec<(f64, f64)> = self.bins().into_iter().filter(|b| b.0 >= from_m).collect();
        let Some((first, last)) = seen.first().copied().zip(seen.last().copied()) else {
            return Passability::Undecided;
        };
        let riser = self.max_riser(from_m);
        let step = riser.unwrap_or(0.0);
        let fit = line_fit(&seen);
        if step > max_step_m {
            return Passability::Impassable {
                inclination_rad: fit.map_or(0.0, |f| f.slope.atan().abs()),
                step_m: Some(step),
            };
        }
        if last.0 - first.0 < judge_length_m {
            return Passability::Undecided;
        }
        // Without risers, the steepest grade between bins at least a grid cell apart: a short
        // view of a ramp on a grid may hold too few cells for a fair line.
        let mut steepest: f64 = fit.map_or(0.0, |f| f.slope.abs());
        for (i, a) in seen.iter().enumerate() {
            for b in &seen[i + 1..] {
                if b.0 - a.0 >= GRADE_BASE_M {
                    steepest = steepest.max(((b.1 - a.1) / (b.0 - a.0)).abs());
                }
            }
        }
        if riser.is_none() && steepest.atan() > max_inclination_rad {
            return Passability::Impassable {
                inclination_rad: steepest.atan(),
                step_m: None,
            };
        }
        Passability::Passable
    }

    /// Describes the obstacle in this observation: the points from the first one off the
    /// level by more than `detect_height_m / 2` on. The standard deviation of their residuals
    /// about a least-squares line (√V) above `stairs_min_residual_sd_m` makes it stairs,
    /// whose step height is its highest riser (the paper saves "the maximum height of the
    /// stairs"); the inclination is the slope of the line through the 5 cm bins of the
    /// profile.
    /// `None` when less than `min_length_m` of obstacle was seen.
    pub fn piece(
        &self,
        detect_height_m: f64,
        stairs_min_residual_sd_m: f64,
        min_length_m: f64,
    ) -> Option<ObstaclePiece> {
        let start_m = self
            .points
            .iter()
            .filter(|p| p.1.abs() > detect_height_m / 2.0)
            .map(|p| p.0)
            .reduce(f64::min)?;
        let part: Vec<(f64, f64)> = self
            .points
            .iter()
            .copied()
            .filter(|p| p.0 >= start_m)
            .collect();
        let end_m = part.iter().map(|p| p.0).fold(start_m, f64::max);
        if end_m - start_m < min_length_m {
            return None;
        }
        let fit = line_fit(&part)?;
        // The inclination from the binned profile, every 5 cm weighing the same: the laser
        // sees the far part of each grid cell of a ramp more often than the near part.
        let part_bins: Vec<(f64, f64)> =
            self.bins().into_iter().filter(|b| b.0 >= start_m).collect();
        let slope = line_fit(&part_bins).map_or(fit.slope, |f| f.slope);
        let mean_z = part.iter().map(|p| p.1).sum::<f64>() / part.len() as f64;
        let shape = if fit.residual_sd > stairs_min_residual_sd_m {
            ObstacleShape::Stairs
        } else {
            ObstacleShape::Slope
        };
        let step_height_m = (shape == ObstacleShape::Stairs).then(|| {
            self.max_riser(start_m)
                .unwrap_or_else(|| part.iter().map(|p| p.1.abs()).fold(0.0, f64::max))
        });
        Some(ObstaclePiece {
            start_m,
            end_m,
            rising: mean_z > 0.0,
            shape,
            inclination_rad: slope.atan().abs(),
            residual_sd_m: fit.residual_sd,
            step_height_m,
        })
    }
}

/// A least-squares line z = a + slope·x and the standard deviation of its residuals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineFit {
    pub intercept: f64,
    pub slope: f64,
    pub residual_sd: f64,
}

/// Least-squares line through (x, z) points; `None` for fewer than two distinct x.
pub fn line_fit(points: &[(f64, f64)]) -> Option<LineFit> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let (mx, mz) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx < 1e-12 {
        return None;
    }
    let sxz: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - mz)).sum();
    let slope = sxz / sxx;
    let intercept = mz - slope * mx;
    let var = points
        .iter()
        .map(|p| (p.1 - intercept - slope * p.0).powi(2))
        .sum::<f64>()
        / n;
    Some(LineFit {
        intercept,
        slope,
        residual_sd: var.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile(f: impl Fn(f64) -> f64, to_m: f64) -> ObstacleProfile {
        let mut p = ObstacleProfile::default();
        let mut x = 0.0;
        while x < to_m {
            p.push(x, f(x));
            x += 0.01;
        }
        p
    }

    #[test]
    fn a_ramp_is_a_slope_of_its_inclination() {
        let t = 20f64.to_radians().tan();
        // Level up to 1 m, then a ramp on a 0.1 m grid, seen up to 1.6 m.
        let p = profile(
            |x| {
                let cell = ((x - 1.0) / 0.1).floor() * 0.1 + 0.05;
                if x < 1.0 { 0.0 } else { t * cell }
            },
            1.6,
        );
        let s = p.piece(0.04, 0.02, 0.1).expect("a piece");
        assert_eq!(s.shape, ObstacleShape::Slope);
        assert!(s.rising);
        assert!((s.inclination_rad.to_degrees() - 20.0).abs() < 1.5, "{s:?}");
        assert!((s.start_m - 1.0).abs() < 0.15, "{s:?}");
        assert!(profile(|_| 0.003, 2.0).piece(0.04, 0.02, 0.1).is_none());
    }

    #[test]
    fn stairs_have_a_large_residual_and_their_step_height() {
        // Level up to 1 m, then steps of 0.15 m every 0.3 m.
        let p = profile(
            |x| {
                if x < 1.0 {
                    0.0
                } else {
                    (((x - 1.0) / 0.3).floor() + 1.0) * 0.15
                }
            },
            1.7,
        );
        let s = p.piece(0.04, 0.02, 0.1).expect("a piece");
        assert_eq!(s.shape, ObstacleShape::Stairs, "{s:?}");
        assert!((s.step_height_m.unwrap() - 0.15).abs() < 0.02, "{s:?}");
    }

    #[test]
    fn passability_follows_the_robot_limits() {
        let t = 20f64.to_radians().tan();
        let ramp = profile(|x| t * x.max(0.0), 0.5);
        let crawler = ramp.passability(0.0, 0.25, 35f64.to_radians(), 0.2);
        assert_eq!(crawler, Passability::Passable);
        let wheeled = ramp.passability(0.0, 0.25, 15f64.to_radians(), 0.05);
        assert!(
            matches!(wheeled, Passability::Impassable { .. }),
            "{wheeled:?}"
        );
        let step = profile(|x| if x < 0.2 { 0.0 } else { 0.15 }, 0.4);
        assert!(matches!(
            step.passability(0.0, 0.25, 35f64.to_radians(), 0.05),
            Passability::Impassable {
                step_m: Some(_),
                ..
            }
        ));
        assert_eq!(
            step.passability(0.0, 0.25, 35f64.to_radians(), 0.2),
            Passability::Passable
        );
    }

    #[test]
    fn the_central_beam_height_is_l_minus_l1_times_cos_theta() {
        let spec = TiltedLaserSpec {
            beams: 1,
            fov_rad: 0.0,
            ..TiltedLaserSpec::default()
        };
        let l = spec.flat_floor_range_m();
        let scan = TiltedScan {
            pose: Default::default(),
            yaw_min_rad: 0.0,
            yaw_increment_rad: 0.0,
            ranges_m: vec![(l - 0.2) as f32],
        };
        let h = floor_hits(&spec, &scan)[0];
        let expect = 0.2 * spec.tilt_from_vertical_rad.cos();
        assert!((h.height_m - expect).abs() < 1e-6, "{h:?}");
    }
}

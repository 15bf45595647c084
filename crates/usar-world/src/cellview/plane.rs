//! Least-squares plane fit of a height profile (paper 000 §IV-A-4: "the slope and smoothness of a
//! rubble pile is categorized by fitting a plane to its 3-D sensory data using a least squares
//! method").

/// The fitted plane `z = a·x + b·y + c` and what the classification reads from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneFit {
    /// ∂z/∂x of the plane.
    pub a: f64,
    /// ∂z/∂y of the plane.
    pub b: f64,
    /// Height of the plane at x = y = 0.
    pub c: f64,
    /// Inclination of the plane against the horizontal: `atan(√(a² + b²))`, radians.
    pub slope_rad: f64,
    /// Direction in which the plane rises (`atan2(b, a)`), radians; 0 on a level plane.
    pub uphill_rad: f64,
    /// Root mean square of the residuals `z_i − (a·x_i + b·y_i + c)`, metres.
    pub roughness_m: f64,
    /// Number of points fitted.
    pub points: u32,
}

/// Running sums of a least-squares fit of the plane `z = a·x + b·y + c` to points `(x_i, y_i, z_i)`.
///
/// The fit minimises `Σ (z_i − a·x_i − b·y_i − c)²`. With the means `x̄, ȳ, z̄` and the centred
/// sums `Sxx = Σ(x−x̄)²`, `Sxy = Σ(x−x̄)(y−ȳ)`, `Syy`, `Sxz`, `Syz`, `Szz`, the normal equations are
///
/// ```text
/// ⎡Sxx Sxy⎤ ⎡a⎤   ⎡Sxz⎤
/// ⎣Sxy Syy⎦ ⎣b⎦ = ⎣Syz⎦ ,   c = z̄ − a·x̄ − b·ȳ ,
/// ```
///
/// the slope is `atan(√(a² + b²))` and the roughness is `√((Szz − a·Sxz − b·Syz) / n)`, the RMS
/// residual. When the points lie on a line (the matrix is singular) only the direction along the
/// line is fitted; with a single point the plane is level.
///
/// Adding points allocates nothing, so a caller can fit thousands of cells per frame. Keep the
/// coordinates local (e.g. relative to the cell centre) for the best precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LeastSquaresPlane {
    n: u32,
    sx: f64,
    sy: f64,
    sz: f64,
    sxx: f64,
    sxy: f64,
    syy: f64,
    sxz: f64,
    syz: f64,
    szz: f64,
}

impl LeastSquaresPlane {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one point.
    #[inline]
    pub fn push(&mut self, x: f64, y: f64, z: f64) {
        self.n += 1;
        self.sx += x;
        self.sy += y;
        self.sz += z;
        self.sxx += x * x;
        self.sxy += x * y;
        self.syy += y * y;
        self.sxz += x * z;
        self.syz += y * z;
        self.szz += z * z;
    }

    /// Number of points added.
    pub fn len(&self) -> u32 {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The least-squares plane, or `None` without points.
    pub fn fit(&self) -> Option<PlaneFit> {
        if self.n == 0 {
            return None;
        }
        let n = f64::from(self.n);
        let (mx, my, mz) = (self.sx / n, self.sy / n, self.sz / n);
        // Centred second moments; clamp the variances, which rounding may push below zero.
        let cxx = (self.sxx - n * mx * mx).max(0.0);
        let cyy = (self.syy - n * my * my).max(0.0);
        let cxy = self.sxy - n * mx * my;
        let cxz = self.sxz - n * mx * mz;
        let cyz = self.syz - n * my * mz;
        let czz = (self.szz - n * mz * mz).max(0.0);
        let det = cxx * cyy - cxy * cxy;
        // Relative tolerance: the points are collinear when det is tiny against cxx·cyy.
        let scale = cxx * cyy;
        let (a, b) = if det > 1e-12 * scale && det > 0.0 {
            ((cxz * cyy - cyz * cxy) / det, (cyz * cxx - cxz * cxy) / det)
        } else if cxx + cyy > 0.0 {
            // Collinear points: fit z along the line's direction (ux, uy) only.
            let len = (cxx + cyy).sqrt();
            let (ux, uy) = if cxx >= cyy {
                (cxx.sqrt() / len, cxy.signum() * cyy.sqrt() / len)
            } else {
                (cxy.signum() * cxx.sqrt() / len, cyy.sqrt() / len)
            };
            let ctt = cxx * ux * ux + 2.0 * cxy * ux * uy + cyy * uy * uy;
            let ctz = cxz * ux + cyz * uy;
            let k = if ctt > 0.0 { ctz / ctt } else { 0.0 };
            (k * ux, k * uy)
        } else {
            (0.0, 0.0)
        };
        let c = mz - a * mx - b * my;
        let residual = (czz - a * cxz - b * cyz).max(0.0);
        let gradient = a.hypot(b);
        Some(PlaneFit {
            a,
            b,
            c,
            slope_rad: gradient.atan(),
            uphill_rad: if gradient > 0.0 { b.atan2(a) } else { 0.0 },
            roughness_m: (residual / n).sqrt(),
            points: self.n,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_on_a_line_fit_the_slope_along_the_line() {
        let mut fit = LeastSquaresPlane::new();
        for i in 0..10 {
            let t = f64::from(i) * 0.1;
            fit.push(t, 0.0, 0.5 * t + 1.0);
        }
        let p = fit.fit().unwrap();
        assert!((p.a - 0.5).abs() < 1e-12 && p.b.abs() < 1e-12, "{p:?}");
        assert!((p.c - 1.0).abs() < 1e-12);
        assert!(p.roughness_m < 1e-9);
    }

    #[test]
    fn single_point_is_level_and_empty_fit_is_none() {
        assert!(LeastSquaresPlane::new().fit().is_none());
        let mut fit = LeastSquaresPlane::new();
        fit.push(1.0, 2.0, 3.0);
        let p = fit.fit().unwrap();
        assert_eq!((p.a, p.b, p.c, p.slope_rad), (0.0, 0.0, 3.0, 0.0));
    }

    #[test]
    fn symmetric_noise_gives_its_rms_as_roughness() {
        // z = ±0.03 in a checkerboard: level plane, RMS residual 0.03.
        let mut fit = LeastSquaresPlane::new();
        for i in 0..10 {
            for j in 0..10 {
                let z = if (i + j) % 2 == 0 { 0.03 } else { -0.03 };
                fit.push(f64::from(i) * 0.1, f64::from(j) * 0.1, z);
            }
        }
        let p = fit.fit().unwrap();
        assert!(p.slope_rad < 1e-9, "{p:?}");
        assert!((p.roughness_m - 0.03).abs() < 1e-9, "{p:?}");
    }
}

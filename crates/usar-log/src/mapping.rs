//! An occupancy grid from a log, with scan matching.
//!
//! The matcher ([`Matcher`]) places each scan against everything drawn before, from the pose
//! odometry predicts: by default Olson's correlative scan matching ([`crate::matcher`]), an
//! exhaustive search of a window of poses on a likelihood grid; or the point-to-line ICP of
//! usar's simulated robots ([`usar_map::localization::Localizer`] with its map); or odometry
//! alone. The laser's own frame is tracked (the robot's odometry composed with the laser's
//! mount), so a laser ahead of the robot's centre moves as it does. Every matcher here is
//! incremental, without loop closure: what it drifts is reported, not hidden.
//!
//! The grid is made in two passes: first every pose is estimated, then the grid is sized to
//! what the scans saw and every scan is drawn at its estimate: a return nearer than
//! [`MapParams::usable_range_m`] as free space up to an occupied cell, a farther one as free
//! space up to that range (GMapping's `maxUrange`), a beam with no return as free space up to
//! the laser's maximum (capped by the usable range: it saw nothing nearer), a beam with no
//! reading not at all.

use crate::matcher::{MatcherParams, Tracker};
use crate::no_return::{self, NoReturn, Reading};
use crate::{LogError, RobotLog, ScanAt};
use serde::Serialize;
use usar_map::localization::{Localizer, ScanView, compose, relative};
use usar_map::{OccupancyGrid, OccupancyParams};
use usar_readings::LaserScan;
use usar_world::{GridGeometry, Point2, Pose2, normalize_angle};

/// How a map is built from a log.
#[derive(Clone, Debug, PartialEq)]
pub struct MapParams {
    /// Cell size of the grid, metres.
    pub resolution_m: f64,
    /// Returns beyond this are drawn as free space up to it, metres; no-return beams reach
    /// no farther either.
    pub usable_range_m: f64,
    /// How odometry is corrected.
    pub matcher: Matcher,
    /// The no-return threshold (`None`: from the log, [`no_return::estimate`]).
    pub no_return_m: Option<f64>,
    /// Only the scans up to this time (the map as it was then); `None`: all.
    pub until_s: Option<f64>,
}

impl Default for MapParams {
    fn default() -> Self {
        Self {
            resolution_m: 0.05,
            usable_range_m: 20.0,
            matcher: Matcher::Correlative(MatcherParams::default()),
            no_return_m: None,
            until_s: None,
        }
    }
}

impl MapParams {
    /// Refuses values that cannot make a map.
    pub fn check(&self) -> Result<(), String> {
        if !(self.resolution_m.is_finite() && (0.005..=1.0).contains(&self.resolution_m)) {
            return Err(format!(
                "resolution {} m (expected 0.005 to 1 m)",
                self.resolution_m
            ));
        }
        if !(self.usable_range_m.is_finite() && (0.5..=200.0).contains(&self.usable_range_m)) {
            return Err(format!(
                "usable range {} m (expected 0.5 to 200 m)",
                self.usable_range_m
            ));
        }
        if self
            .no_return_m
            .is_some_and(|m| !(m.is_finite() && m > 0.0))
        {
            return Err("no-return threshold: expected a positive number of metres".into());
        }
        Ok(())
    }
}

/// How a log's odometry is corrected.
#[derive(Clone, Debug, PartialEq)]
pub enum Matcher {
    /// Correlative scan matching against a likelihood grid (Olson 2009).
    Correlative(MatcherParams),
    /// usar's point-to-line ICP against its map of scan outlines, as the simulated robots use.
    Icp,
    /// Odometry alone.
    Odometry,
}

impl Matcher {
    pub const NAMES: [&'static str; 3] = ["correlative", "icp", "odometry"];

    pub fn name(&self) -> &'static str {
        match self {
            Self::Correlative(_) => "correlative",
            Self::Icp => "icp",
            Self::Odometry => "odometry",
        }
    }

    /// The matcher called `name`, with its default parameters.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "correlative" => Some(Self::Correlative(MatcherParams::default())),
            "icp" => Some(Self::Icp),
            "odometry" => Some(Self::Odometry),
            _ => None,
        }
    }
}

/// One scan's poses: the laser's, by odometry, by the estimate and as the log stamps it.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TrajectoryPoint {
    pub t_s: f64,
    pub odometry: Pose2,
    pub estimate: Pose2,
    pub logged: Option<Pose2>,
}

/// How far one trajectory is from another, after aligning them at the first scan.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Deviation {
    pub mean_m: f64,
    pub max_m: f64,
    pub final_m: f64,
    pub mean_heading_deg: f64,
    pub max_heading_deg: f64,
}

/// Drift figures of a map built from a log.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Drift {
    /// Path length by odometry, metres.
    pub path_m: f64,
    /// The estimate against odometry: what scan matching changed.
    pub estimate_vs_odometry: Deviation,
    /// Odometry and the estimate against the log's own poses, when they are not its odometry
    /// (a corrected log's SLAM poses): how far each drifts from that reference.
    pub odometry_vs_logged: Option<Deviation>,
    pub estimate_vs_logged: Option<Deviation>,
}

/// A map built from a log.
pub struct LogMap {
    pub grid: OccupancyGrid,
    pub trajectory: Vec<TrajectoryPoint>,
    pub drift: Drift,
    pub no_return: NoReturn,
    /// Scans matched, and scans whose match was rejected (odometry kept).
    pub matched: u64,
    pub rejected: u64,
    /// Scans drawn.
    pub scans: usize,
}

impl LogMap {
    /// The scans drawn (as the mapper saw them: metres, +∞ no return within the usable range,
    /// NaN no reading), each stamped with its estimated pose — what a builder that works on
    /// poses and scans (a passive BTM) takes. `log` and `params` must be those of the map.
    pub fn drawn_scans(
        &self,
        log: &RobotLog,
        params: &MapParams,
    ) -> Result<Vec<LaserScan>, LogError> {
        let threshold = self.no_return.threshold_m;
        Ok(log
            .scans()?
            .into_iter()
            .filter(|s| params.until_s.is_none_or(|t| s.scan.t_s <= t))
            .zip(&self.trajectory)
            .map(|(s, at)| usable_scan(&s, threshold, params.usable_range_m, at.estimate))
            .collect())
    }

    /// The frontiers of the map (free cells beside unknown ones, 8-connected clusters of at
    /// least `min_length_m`), each with its candidate cell, as the explorers see them.
    pub fn frontiers(&self, min_length_m: f64) -> Vec<usar_map::FrontierCluster> {
        let cells = (min_length_m / self.grid.geometry().resolution_m)
            .ceil()
            .max(1.0) as usize;
        usar_map::FrontierTracker::new(&self.grid).clusters(&self.grid, cells)
    }
}

/// A log's scan as the mapper sees it: ranges in metres, +∞ for no return within the usable
/// range, NaN for no reading.
fn usable_scan(s: &ScanAt<'_>, threshold: Option<f64>, usable_m: f64, pose: Pose2) -> LaserScan {
    LaserScan {
        pose,
        angle_min_rad: s.scan.angle_min_rad,
        angle_increment_rad: s.scan.angle_increment_rad,
        // A beam with no return saw nothing nearer than the laser's maximum.
        max_range_m: threshold.map_or(usable_m, |t| t.min(usable_m)),
        ranges_m: s
            .scan
            .ranges_m
            .iter()
            .map(|&r| match no_return::classify(f64::from(r), threshold) {
                Reading::Return(r) if r < usable_m => r as f32,
                Reading::Return(_) | Reading::NoReturn => f32::INFINITY,
                Reading::Invalid => f32::NAN,
            })
            .collect(),
    }
}

/// Builds the map of `log`.
pub fn build_map(log: &RobotLog, params: &MapParams) -> Result<LogMap, LogError> {
    let scans: Vec<ScanAt<'_>> = log
        .scans()?
        .into_iter()
        .filter(|s| params.until_s.is_none_or(|t| s.scan.t_s <= t))
        .collect();
    if scans.is_empty() {
        return Err(LogError::NoScans {
            path: log.path.clone(),
        });
    }
    let no_return = match params.no_return_m {
        Some(m) => no_return::with_threshold(
            scans
                .iter()
                .flat_map(|s| s.scan.ranges_m.iter().map(|&r| f64::from(r))),
            Some(m),
            no_return::Source::Given,
        ),
        None => no_return::estimate(log),
    };
    let threshold = no_return.threshold_m;
    let usable = params.usable_range_m;

    // Pass 1: the laser's poses.
    let (trajectory, matched, rejected) = match &params.matcher {
        Matcher::Correlative(m) => correlative(&scans, threshold, usable, m),
        Matcher::Icp | Matcher::Odometry => {
            icp(&scans, threshold, usable, params.matcher == Matcher::Icp)
        }
    };

    // Pass 2: the grid around what was seen, every scan drawn at its estimate.
    let geometry = extent(&scans, &trajectory, threshold, usable, params.resolution_m);
    let mut grid = OccupancyGrid::new(geometry, OccupancyParams::default());
    for (s, at) in scans.iter().zip(&trajectory) {
        grid.integrate_scan(&usable_scan(s, threshold, usable, at.estimate));
    }
    let drift = drift(&trajectory);
    Ok(LogMap {
        grid,
        drift,
        no_return,
        matched,
        rejected,
        scans: trajectory.len(),
        trajectory,
    })
}

/// The laser's poses by correlative matching; scans matched and rejected.
fn correlative(
    scans: &[ScanAt<'_>],
    threshold: Option<f64>,
    usable: f64,
    params: &MatcherParams,
) -> (Vec<TrajectoryPoint>, u64, u64) {
    let mut tracker = Tracker::new(Some(params.clone()));
    let mut trajectory = Vec::with_capacity(scans.len());
    for s in scans {
        let odometry = s.laser_odometry();
        let view = ScanView::from_scan(&usable_scan(s, threshold, usable, odometry));
        let pose = tracker.update(odometry, &view.points);
        trajectory.push(TrajectoryPoint {
            t_s: s.scan.t_s,
            odometry,
            estimate: pose,
            logged: s.scan.logged_pose,
        });
    }
    (trajectory, tracker.matched, tracker.rejected)
}

/// The laser's poses by usar's ICP localizer (or odometry alone); scans matched and rejected.
fn icp(
    scans: &[ScanAt<'_>],
    threshold: Option<f64>,
    usable: f64,
    scan_matching: bool,
) -> (Vec<TrajectoryPoint>, u64, u64) {
    let start = scans[0].laser_odometry();
    let mut localizer = Localizer::new(start, start, scan_matching, 1.0, 0.5).with_map();
    let mut trajectory = Vec::with_capacity(scans.len());
    for s in scans {
        let odometry = s.laser_odometry();
        localizer.predict(odometry);
        let scan = usable_scan(s, threshold, usable, localizer.pose());
        localizer.correct(&ScanView::from_scan(&scan), false);
        trajectory.push(TrajectoryPoint {
            t_s: s.scan.t_s,
            odometry,
            estimate: localizer.pose(),
            logged: s.scan.logged_pose,
        });
    }
    (trajectory, localizer.matched, localizer.rejected)
}

/// The grid that holds every estimated pose and every return drawn, with a 1 m margin.
fn extent(
    scans: &[ScanAt<'_>],
    trajectory: &[TrajectoryPoint],
    threshold: Option<f64>,
    usable_m: f64,
    resolution_m: f64,
) -> GridGeometry {
    let (mut lo, mut hi) = (
        Point2::new(f64::INFINITY, f64::INFINITY),
        Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    let mut take = |p: Point2| {
        lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
    };
    for (s, at) in scans.iter().zip(trajectory) {
        take(at.estimate.position());
        for (i, &r) in s.scan.ranges_m.iter().enumerate() {
            if let Reading::Return(r) = no_return::classify(f64::from(r), threshold) {
                let a = at.estimate.theta
                    + s.scan.angle_min_rad
                    + i as f64 * s.scan.angle_increment_rad;
                let r = r.min(usable_m);
                take(Point2::new(
                    at.estimate.x + r * a.cos(),
                    at.estimate.y + r * a.sin(),
                ));
            }
        }
    }
    let margin = 1.0;
    let width = ((hi.x - lo.x + 2.0 * margin) / resolution_m).ceil() as u32;
    let height = ((hi.y - lo.y + 2.0 * margin) / resolution_m).ceil() as u32;
    GridGeometry::new(
        width.max(1),
        height.max(1),
        resolution_m,
        Point2::new(lo.x - margin, lo.y - margin),
    )
}

/// `path` against `reference`, both aligned at their first pose.
pub fn deviation(path: &[Pose2], reference: &[Pose2]) -> Deviation {
    let (Some(&p0), Some(&r0)) = (path.first(), reference.first()) else {
        return Deviation::default();
    };
    let mut d = Deviation::default();
    let n = path.len().min(reference.len());
    for (p, r) in path.iter().zip(reference) {
        // The path in the reference's frame, its first pose on the reference's first.
        let aligned = compose(r0, relative(p0, *p));
        let off = aligned.position().distance(r.position());
        let turn = normalize_angle(aligned.theta - r.theta).abs().to_degrees();
        d.mean_m += off / n as f64;
        d.max_m = d.max_m.max(off);
        d.final_m = off;
        d.mean_heading_deg += turn / n as f64;
        d.max_heading_deg = d.max_heading_deg.max(turn);
    }
    d
}

fn drift(trajectory: &[TrajectoryPoint]) -> Drift {
    let odometry: Vec<Pose2> = trajectory.iter().map(|t| t.odometry).collect();
    let estimate: Vec<Pose2> = trajectory.iter().map(|t| t.estimate).collect();
    let logged: Option<Vec<Pose2>> = trajectory.iter().map(|t| t.logged).collect();
    // The log's poses are a reference only where they are not its odometry.
    let logged = logged.filter(|l| deviation(&odometry, l).max_m > 1e-3);
    Drift {
        path_m: odometry
            .windows(2)
            .map(|w| w[0].position().distance(w[1].position()))
            .sum(),
        estimate_vs_odometry: deviation(&estimate, &odometry),
        odometry_vs_logged: logged.as_ref().map(|l| deviation(&odometry, l)),
        estimate_vs_logged: logged.as_ref().map(|l| deviation(&estimate, l)),
    }
}

//! A BTM built passively from a path already driven (a real robot's log, a teleoperated run):
//! the robot's poses and scans are given, nothing is driven. Paper 004 builds a BTM while its
//! behaviours drive; here the same detectors watch a path chosen by someone else, and a node
//! is made where the path passes a feature:
//!
//! - **divergence** (§III-A-1, Fig. 2): the nearest acute Delaunay triangle in the band ahead
//!   ([`divergence_triangles`]) makes a candidate at its circumcentre (in world coordinates,
//!   its open directions [`open_directions`] refreshed at each sighting as the robot nears);
//!   when the path comes within [`BuildConfig::merge_radius_m`] of it the node is made, typed
//!   by its directions ([`divergence_subtype`]; a straight passage makes none). A candidate
//!   the path leaves behind farther than the band is dropped;
//! - **free space** (Fig. 3): entrance when L_l or L_r exceeds C₁ in the strip, exit when both
//!   sides have stayed closer for the confirm distance ([`ExitTracker`]);
//! - **terminal** nodes at the first and the last pose.
//!
//! Consecutive nodes on the path are joined by a searched link with the length, minimum width
//! and path measured between them ([`LinkRecorder`]); a node's other open directions stay
//! un-searched links. Coming back within the merge radius of a known node closes a loop onto
//! it: the link driven ends there, and the un-searched links of both ends that point along it
//! are used up. A log has no tilted laser and no attitude: no obstacle nodes, no inclinations.

use super::BuildConfig;
use super::divergence::{divergence_subtype, divergence_triangles, open_directions};
use super::free_space::{ExitTracker, is_free_space};
use super::links::{LinkRecorder, LinkSample, MapWriter};
use crate::model::{Btm, kind, subtype};
use crate::store::{BtmError, BtmStore};
use usar_map::localization::ScanView;
use usar_world::{Point2, Pose2, normalize_angle};

/// Two directions of at most this apart are one passage (a link's ends, a stub and a path).
const SAME_DIRECTION_RAD: f64 = std::f64::consts::FRAC_PI_4;
/// Directions leaving a node are measured to the path this far from it.
const DIRECTION_REACH_M: f64 = 0.75;
/// Directions of a divergence nearer than this are one (tolerance of a straight passage, as
/// the explorer's).
const STRAIGHT_TOLERANCE_RAD: f64 = 0.35;

/// A divergence seen ahead, not yet reached.
struct Candidate {
    centre: Point2,
    directions: Vec<f64>,
}

/// See the [module documentation](self).
pub struct PassiveBuilder<'s> {
    cfg: BuildConfig,
    /// The narrowest gap taken for a passage.
    passage_m: f64,
    map: MapWriter<'s>,
    /// The node the path last passed.
    node: Option<u32>,
    rec: LinkRecorder,
    driven_m: f64,
    last: Option<Pose2>,
    candidate: Option<Candidate>,
    in_free_space: bool,
    exit: ExitTracker,
}

impl<'s> PassiveBuilder<'s> {
    /// A builder for a robot `robot_width_m` wide (gaps narrower than it plus the configured
    /// margin are not passages), writing to `store` when given.
    pub fn new(cfg: BuildConfig, robot_width_m: f64, store: Option<&'s BtmStore>) -> Self {
        Self {
            passage_m: robot_width_m + cfg.passage_margin_m,
            cfg,
            map: MapWriter::new(store),
            node: None,
            rec: LinkRecorder::default(),
            driven_m: 0.0,
            last: None,
            candidate: None,
            in_free_space: false,
            exit: ExitTracker::default(),
        }
    }

    /// The BTM so far.
    pub fn btm(&self) -> &Btm {
        &self.map.btm
    }

    /// The path reached `pose` and took `view` (points in the sensor frame at `pose`).
    pub fn observe(&mut self, pose: Pose2, view: &ScanView) -> Result<(), BtmError> {
        let here = pose.position();
        let step = self.last.map_or(0.0, |p| p.position().distance(here));
        self.driven_m += step;
        self.last = Some(pose);
        let strip = view.side_clearance(
            -self.cfg.free_space_strip_half_m,
            self.cfg.free_space_strip_half_m,
        );
        let beside = view.side_clearance(-0.1, 0.1);
        self.rec.push(LinkSample {
            driven_m: self.driven_m,
            position: here,
            width_m: beside.width_m().min(view.max_range_m),
            inclination_rad: 0.0,
        });
        let Some(node) = self.node else {
            let start = self
                .map
                .add_node(here, kind::TERMINAL, Some(subtype::START), |_| {})?;
            self.node = Some(start);
            self.rec = LinkRecorder::default();
            return Ok(());
        };

        // A known node reached again: a loop closed onto it.
        if let Some(known) = self.known_node_near(here, node) {
            self.arrive(known, &[])?;
            return Ok(());
        }
        self.watch_divergence(pose, view);
        if let Some(c) = &self.candidate
            && here.distance(c.centre) <= self.cfg.merge_radius_m
        {
            let Candidate { centre, directions } = self.candidate.take().expect("a candidate");
            if let Some(sub) = divergence_subtype(&directions, STRAIGHT_TOLERANCE_RAD) {
                let id = self
                    .map
                    .add_node(centre, kind::DIVERGENCE, Some(sub), |_| {})?;
                self.arrive(id, &directions)?;
            }
            return Ok(());
        }

        // Free space: entrance, then exit.
        if !self.in_free_space && is_free_space(strip, self.cfg.free_space_clearance_m) {
            let id = self
                .map
                .add_node(here, kind::FREE_SPACE, Some(subtype::ENTRANCE), |_| {})?;
            self.arrive(id, &[])?;
            self.in_free_space = true;
            self.exit = ExitTracker::default();
        } else if self.in_free_space
            && let Some(at) = self.exit.update(
                beside,
                self.cfg.free_space_clearance_m,
                step,
                here,
                self.cfg.free_space_exit_confirm_m,
            )
        {
            let id = self
                .map
                .add_node(at, kind::FREE_SPACE, Some(subtype::EXIT), |_| {})?;
            self.arrive(id, &[])?;
            self.in_free_space = false;
        }
        Ok(())
    }

    /// Ends the path: the terminal end node; returns the BTM.
    pub fn finish(mut self) -> Result<Btm, BtmError> {
        if let (Some(_), Some(last)) = (self.node, self.last) {
            let id =
                self.map
                    .add_node(last.position(), kind::TERMINAL, Some(subtype::END), |_| {})?;
            self.arrive(id, &[])?;
        }
        Ok(self.map.btm)
    }

    /// A node other than `current` within the merge radius of `here`, not just left.
    fn known_node_near(&self, here: Point2, current: u32) -> Option<u32> {
        let current_at = self.map.node_position(current)?;
        if current_at.distance(here) <= self.cfg.merge_radius_m * 2.0 {
            // Still leaving the node just made or reached.
            return None;
        }
        self.map
            .btm
            .nodes
            .iter()
            .filter(|n| n.id != current && n.kind != kind::TERMINAL)
            .map(|n| (Point2::new(n.x_m, n.y_m).distance(here), n.id))
            .filter(|(d, _)| *d <= self.cfg.merge_radius_m)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, id)| id)
    }

    /// Keeps the nearest divergence ahead as the candidate, or drops one left behind.
    fn watch_divergence(&mut self, pose: Pose2, view: &ScanView) {
        let cfg = &self.cfg;
        let here = pose.position();
        let triangles = divergence_triangles(
            &view.points,
            cfg.band_near_m,
            cfg.band_far_m,
            self.passage_m,
            cfg.obtuse_tolerance_rad,
        );
        let near_known = |p: Point2| {
            self.map
                .btm
                .nodes
                .iter()
                .any(|n| Point2::new(n.x_m, n.y_m).distance(p) <= cfg.merge_radius_m)
        };
        let seen = triangles.first().and_then(|t| {
            let centre = pose.to_world(t.circumcentre);
            (!near_known(centre)).then(|| {
                let world: Vec<Point2> = view.points.iter().map(|&p| pose.to_world(p)).collect();
                let directions = open_directions(
                    &world,
                    centre,
                    t.circumradius_m + cfg.search_margin_m,
                    self.passage_m,
                );
                Candidate { centre, directions }
            })
        });
        match (&self.candidate, seen) {
            // The same junction seen again, nearer: its directions as seen now.
            (Some(c), Some(s)) if c.centre.distance(s.centre) <= cfg.merge_radius_m => {
                self.candidate = Some(s);
            }
            (None, Some(s)) => self.candidate = Some(s),
            (Some(c), _) if here.distance(c.centre) > cfg.band_far_m => self.candidate = None,
            _ => {}
        }
    }

    /// The path reached node `id` (new, with open `directions`, or known): the link from the
    /// last node is searched, the stubs along it used up, the others added.
    fn arrive(&mut self, id: u32, directions: &[f64]) -> Result<(), BtmError> {
        let Some(from) = self.node else { return Ok(()) };
        let (Some(a), Some(b)) = (self.map.node_position(from), self.map.node_position(id)) else {
            return Ok(());
        };
        let rec = std::mem::take(&mut self.rec);
        let measures = rec.measures(a, b);
        // Leaving `from` and arriving at `id`, as the path went.
        let leaving = bearing_along(&measures.path, a, DIRECTION_REACH_M);
        let arriving = bearing_along(
            &measures.path.iter().rev().copied().collect::<Vec<_>>(),
            b,
            DIRECTION_REACH_M,
        );
        let stub = self.stub_towards(from, leaving);
        let link = match stub {
            Some(s) => s,
            None => self.map.add_unsearched(from, leaving)?,
        };
        self.map.close_link(link, id, measures)?;
        if let Some(back) = self.stub_towards(id, arriving) {
            self.map.remove_unsearched(back)?;
        }
        for &d in directions {
            if normalize_angle(d - arriving).abs() > SAME_DIRECTION_RAD {
                self.map.add_unsearched(id, d)?;
            }
        }
        self.node = Some(id);
        Ok(())
    }

    /// Node `id`'s un-searched link nearest `direction`, within [`SAME_DIRECTION_RAD`].
    fn stub_towards(&self, id: u32, direction: f64) -> Option<u32> {
        self.map
            .btm
            .links
            .iter()
            .filter(|l| l.start == id && !l.searched)
            .map(|l| (normalize_angle(l.direction_rad - direction).abs(), l.id))
            .filter(|(d, _)| *d <= SAME_DIRECTION_RAD)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, l)| l)
    }
}

/// The bearing from `from` to the first point of `path` at least `reach_m` from it after the
/// path's closest approach to it (the path may reach a node's merge radius before it passes
/// the node); the last point when none is.
fn bearing_along(path: &[Point2], from: Point2, reach_m: f64) -> f64 {
    let closest = (1..path.len())
        .min_by(|&i, &j| path[i].distance(from).total_cmp(&path[j].distance(from)))
        .unwrap_or(0);
    let to = path[closest..]
        .iter()
        .find(|p| p.distance(from) >= reach_m)
        .or(path.last())
        .copied()
        .unwrap_or(from);
    from.bearing_to(to)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    use usar_sim::sensors::LaserScan;

    /// The scan at `pose` of an L-shaped corridor 2 m wide: along x from x = −5 to 10, then
    /// up (y) from x = 8–10; walls as segments.
    fn scan(pose: Pose2) -> ScanView {
        let walls = [
            ((-5.0, -1.0), (10.0, -1.0)),
            ((-5.0, 1.0), (8.0, 1.0)),
            ((8.0, 1.0), (8.0, 15.0)),
            ((10.0, -1.0), (10.0, 15.0)),
            ((-5.0, -1.0), (-5.0, 1.0)),
        ];
        let n = 360;
        let ranges = (0..n)
            .map(|i| {
                let a = pose.theta - PI + f64::from(i) * TAU / f64::from(n);
                let (s, c) = a.sin_cos();
                let mut best = f64::INFINITY;
                for ((ax, ay), (bx, by)) in walls {
                    let (ex, ey) = (bx - ax, by - ay);
                    let (wx, wy) = (ax - pose.x, ay - pose.y);
                    let det = ex * s - ey * c;
                    if det.abs() < 1e-12 {
                        continue;
                    }
                    let t = (ex * wy - ey * wx) / det;
                    let u = (c * wy - s * wx) / det;
                    if t > 0.0 && (0.0..=1.0).contains(&u) {
                        best = best.min(t);
                    }
                }
                best as f32
            })
            .collect();
        ScanView::from_scan(&LaserScan {
            pose,
            angle_min_rad: -PI,
            angle_increment_rad: TAU / f64::from(n),
            max_range_m: 20.0,
            ranges_m: ranges,
        })
    }

    #[test]
    fn a_path_round_a_corner_makes_start_corner_and_end_joined_by_searched_links() {
        let mut b = PassiveBuilder::new(BuildConfig::default(), 0.45, None);
        let mut poses: Vec<Pose2> = (0..90)
            .map(|k| Pose2::new(-3.0 + 0.135 * f64::from(k), 0.0, 0.0))
            .collect();
        poses.extend((0..60).map(|k| Pose2::new(9.0, 0.5 + 0.15 * f64::from(k), FRAC_PI_2)));
        for p in poses {
            b.observe(p, &scan(p)).unwrap();
        }
        let btm = b.finish().unwrap();
        let kinds: Vec<(&str, Option<&str>)> = btm
            .nodes
            .iter()
            .map(|n| (n.kind.as_str(), n.subtype.as_deref()))
            .collect();
        assert_eq!(
            kinds,
            vec![
                (kind::TERMINAL, Some(subtype::START)),
                (kind::DIVERGENCE, Some(subtype::CORNER)),
                (kind::TERMINAL, Some(subtype::END)),
            ],
            "{btm:?}"
        );
        let corner = &btm.nodes[1];
        assert!(
            Point2::new(corner.x_m, corner.y_m).distance(Point2::new(9.0, 0.0)) < 0.8,
            "{corner:?}"
        );
        // Two searched links, no stub left at the corner (both its passages were driven).
        assert_eq!(
            btm.links.iter().filter(|l| l.searched).count(),
            2,
            "{:?}",
            btm.links
        );
        assert!(
            btm.links.iter().all(|l| l.start != corner.id || l.searched),
            "{corner:?} {:?}",
            btm.links
        );
        let first = btm.links.iter().find(|l| l.searched).unwrap();
        assert!((first.length_m.unwrap() - 12.0).abs() < 1.0, "{first:?}");
    }
}

//! `usar ros2 explore`: usar's frontier explorer as a ROS 2 node on a robot's `/scan` and
//! `/odom`. Each scan is placed by odometry corrected by correlative scan matching (or by
//! odometry alone) and drawn into an occupancy grid; its frontiers (free cells beside unknown
//! ones, 8-connected clusters as long as the robot is wide) are kept up to date incrementally.
//! The goal is the candidate cell of the frontier nearest the robot in a straight line (usar's
//! nearest-frontier rule; explore_lite weighs distance against frontier size instead).
//!
//! | topic | type | QoS | when |
//! |---|---|---|---|
//! | `/goal_pose` | `geometry_msgs/PoseStamped` (`map`), facing the frontier | reliable | when it moves by more than 0.5 m, and every 5 s |
//! | `/map` | `nav_msgs/OccupancyGrid`: the explorer's grid | transient local | every 2 s |
//! | `/markers` | `visualization_msgs/MarkerArray`: the candidates | reliable | every second |
//!
//! The grid is a square of `size_m` centred on the first odometry reading, in the odometry
//! frame, which is taken as `map`; the laser is taken to sit at the robot's centre.

use crate::msgs::{self, Header, LaserScan, Marker, MarkerArray, PoseStamped};
use crate::{
    Bridge, BridgeError, BridgeOptions, SensorFeed, StopFlag, Topics, qos, scan_reading, stopped,
    types,
};
use std::time::{Duration, Instant};
use usar_log::matcher::{MatcherParams, Tracker};
use usar_map::localization::ScanView;
use usar_map::{FrontierCluster, FrontierTracker, OccupancyGrid, OccupancyParams};
use usar_world::{GridGeometry, Point2, Pose2};

/// How the explorer runs.
#[derive(Clone, Debug, PartialEq)]
pub struct ExploreOptions {
    /// Side of the square grid, metres.
    pub size_m: f64,
    pub resolution_m: f64,
    /// Shortest frontier that is a goal, metres.
    pub min_frontier_m: f64,
    /// Correct odometry by correlative scan matching.
    pub scan_matching: bool,
    /// Stop after this many wall seconds (`None`: when stopped).
    pub duration_s: Option<f64>,
}

impl Default for ExploreOptions {
    fn default() -> Self {
        Self {
            size_m: 100.0,
            resolution_m: 0.05,
            min_frontier_m: 0.5,
            scan_matching: true,
            duration_s: None,
        }
    }
}

/// The explorer's state, fed scan by scan (no DDS here).
pub struct FrontierExplorer {
    options: ExploreOptions,
    grid: Option<OccupancyGrid>,
    frontiers: Option<FrontierTracker>,
    tracker: Tracker,
    pose: Pose2,
    /// Scans drawn.
    pub scans: u64,
}

impl FrontierExplorer {
    pub fn new(options: ExploreOptions) -> Self {
        let tracker = Tracker::new(options.scan_matching.then(|| MatcherParams {
            resolution_m: options.resolution_m,
            ..MatcherParams::default()
        }));
        Self {
            options,
            grid: None,
            frontiers: None,
            tracker,
            pose: Pose2::default(),
            scans: 0,
        }
    }

    /// Draws `scan` taken at `odometry` (the robot's); returns the pose it was placed at.
    pub fn observe(&mut self, odometry: Pose2, scan: &LaserScan) -> Pose2 {
        let reading = scan_reading(scan, odometry);
        let view = ScanView::from_scan(&reading);
        self.pose = self.tracker.update(odometry, &view.points);
        let o = &self.options;
        let grid = self.grid.get_or_insert_with(|| {
            let cells = (o.size_m / o.resolution_m).ceil() as u32;
            let half = o.size_m / 2.0;
            let g = GridGeometry::new(
                cells,
                cells,
                o.resolution_m,
                Point2::new(odometry.x - half, odometry.y - half),
            );
            OccupancyGrid::new(g, OccupancyParams::default())
        });
        grid.integrate_scan(&usar_sim::sensors::LaserScan {
            pose: self.pose,
            ..reading
        });
        let frontiers = self
            .frontiers
            .get_or_insert_with(|| FrontierTracker::new(grid));
        frontiers.update(grid);
        self.scans += 1;
        self.pose
    }

    /// Where the robot is now (the last scan's pose).
    pub fn pose(&self) -> Pose2 {
        self.pose
    }

    pub fn grid(&self) -> Option<&OccupancyGrid> {
        self.grid.as_ref()
    }

    /// The frontier clusters now.
    pub fn clusters(&mut self) -> Vec<FrontierCluster> {
        match (&mut self.frontiers, &self.grid) {
            (Some(f), Some(g)) => {
                let cells = (self.options.min_frontier_m / g.geometry().resolution_m)
                    .ceil()
                    .max(1.0);
                f.clusters(g, cells as usize)
            }
            _ => Vec::new(),
        }
    }

    /// The goal among `clusters` (from [`FrontierExplorer::clusters`]): the candidate of the
    /// frontier nearest the robot, facing it from the robot.
    pub fn goal(&self, clusters: &[FrontierCluster]) -> Option<Pose2> {
        let here = self.pose.position();
        let g = *self.grid.as_ref()?.geometry();
        let best = clusters
            .iter()
            .map(|c| g.cell_center(c.candidate))
            .min_by(|a, b| a.distance(here).total_cmp(&b.distance(here)))?;
        Some(Pose2::new(best.x, best.y, here.bearing_to(best)))
    }
}

/// What a run of the explorer node did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExploreReport {
    pub scans: u64,
    pub goals: u64,
    pub last_goal: Option<Pose2>,
}

/// Runs the node until `stop` is set or the duration is reached.
pub fn run_explore(
    options: &ExploreOptions,
    bridge: &BridgeOptions,
    topics: &Topics,
    stop: &StopFlag,
) -> Result<ExploreReport, BridgeError> {
    let mut node = Bridge::new("usar_explore", bridge)?;
    let mut feed = SensorFeed::new(&mut node, topics)?;
    let goal_pub =
        node.publisher::<PoseStamped>(&topics.goal, types::POSE_STAMPED, qos::reliable())?;
    let map_pub =
        node.publisher::<msgs::OccupancyGrid>(&topics.map, types::OCCUPANCY_GRID, qos::map())?;
    let markers =
        node.publisher::<MarkerArray>(&topics.markers, types::MARKER_ARRAY, qos::reliable())?;
    let mut explorer = FrontierExplorer::new(options.clone());
    let mut report = ExploreReport::default();
    let started = Instant::now();
    let (mut next_goal, mut next_map) = (Duration::ZERO, Duration::ZERO);
    let mut stamp = 0.0;
    while !stopped(stop)
        && options
            .duration_s
            .is_none_or(|d| started.elapsed().as_secs_f64() < d)
    {
        let busy = feed.poll(|at, scan| {
            explorer.observe(at, scan);
            stamp = scan.header.stamp.as_s();
            report.scans += 1;
        });
        let now = started.elapsed();
        if report.scans > 0 && now >= next_goal {
            next_goal = now + Duration::from_secs(1);
            let clusters = explorer.clusters();
            publish_candidates(&markers, stamp, &explorer, &clusters)?;
            if let Some(goal) = explorer.goal(&clusters) {
                let moved = report
                    .last_goal
                    .is_none_or(|g| g.position().distance(goal.position()) > 0.5);
                if moved || report.goals % 5 == 0 {
                    goal_pub
                        .publish(PoseStamped {
                            header: Header::new(stamp, "map"),
                            pose: msgs::Pose::planar(goal),
                        })
                        .map_err(crate::dds)?;
                    report.goals += 1;
                    report.last_goal = Some(goal);
                }
            }
        }
        if now >= next_map
            && let Some(grid) = explorer.grid()
        {
            next_map = now + Duration::from_secs(2);
            map_pub
                .publish(msgs::OccupancyGrid::from_grid(stamp, grid))
                .map_err(crate::dds)?;
        }
        if !busy {
            std::thread::sleep(Duration::from_millis(5));
        }
    }
    Ok(report)
}

fn publish_candidates(
    markers: &ros2_client::Publisher<MarkerArray>,
    t: f64,
    explorer: &FrontierExplorer,
    clusters: &[FrontierCluster],
) -> Result<(), BridgeError> {
    let Some(g) = explorer.grid().map(|g| *g.geometry()) else {
        return Ok(());
    };
    let mut all = vec![Marker::delete_all(t, "frontiers")];
    all.extend(clusters.iter().enumerate().map(|(k, c)| {
        let p = g.cell_center(c.candidate);
        Marker::sphere(
            t,
            "frontiers",
            k as i32,
            (p.x, p.y),
            0.3,
            [0.0, 0.75, 0.85, 1.0],
        )
    }));
    markers
        .publish(MarkerArray { markers: all })
        .map_err(crate::dds)
}

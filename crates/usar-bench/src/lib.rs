//! `usar-bench`: the speed of the hot loops, as `usar bench` reports it. The figures are taken
//! on a 1000 × 1000 building grid (a generated 100 m × 100 m office at 0.1 m, [`bench_scene`]),
//! single-threaded; each is the median of repeated runs. [`run`] measures them all and returns a
//! [`BenchReport`] (serialisable; its [`Display`](std::fmt::Display) is the table `usar bench`
//! prints).

pub mod laser_reference;
pub mod recording;
pub mod scaling;

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::Serialize;
use std::fmt;
use std::time::Instant;
use usar_map::planning::{Connectivity, DistanceField, GridAStar, GridAlgorithm, NavGrid, inflate};
use usar_map::{FrontierTracker, OccupancyGrid, OccupancyParams};
use usar_sim::RobotSpec;
use usar_sim::sensors::{LaserModel, LaserScan, LaserSpec, SensingWorld};
use usar_world::generate::{BuildingParams, generate_office};
use usar_world::{Cell, Pose2, Scene};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// Every figure of one benchmark run (the JSON `usar bench --json` prints).
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    /// The floor the figures were taken on.
    pub grid: String,
    /// Laser scans per second, each with the free-space update of an occupancy grid.
    pub lidar_scans_per_s: f64,
    /// 4-connected A* from corner to corner.
    pub astar4_ms: f64,
    pub astar4_expanded: usize,
    /// 8-connected planning as `GridAStar::plan` does it: jump point search.
    pub astar8_ms: f64,
    /// Jump points expanded.
    pub astar8_expanded: usize,
    /// Cells the jumps stepped over.
    pub astar8_scanned: usize,
    /// Plain 8-connected A*, for comparison.
    pub astar8_plain_ms: f64,
    pub astar8_plain_expanded: usize,
    /// Length of the corner-to-corner path.
    pub path_length_m: f64,
    /// Distance field from one corner, 8-connected.
    pub distance_field_ms: f64,
    /// The same, 4-connected.
    pub distance_field4_ms: f64,
    /// Incremental frontier update after one scan.
    pub frontier_update_ms: f64,
    /// Frontier clustering.
    pub frontier_clusters_ms: f64,
    /// Paper 000's cell view (§V: one cell per robot footprint, classified from the fine
    /// heights) of the whole 1000 × 1000 floor.
    pub cell_view_ms: f64,
    /// The campaign engine's own cost per run (see [`campaign_overhead_ms`]).
    pub campaign_overhead_ms_per_run: f64,
    /// One run per commit (see [`campaign_overhead_ms`]).
    pub campaign_commit_alone_ms: f64,
    /// Paper 002: simulated ÷ wall time of one 20-minute run of 8 robots (S-MCDM + MRv1, big
    /// rooms) on the generated office floor (office-1), one core; the median of the runs.
    pub team_realtime_factor: f64,
    pub team_run_wall_s: f64,
    /// MAXQ-Q training on paper-000 rubble scenes: primitive steps per second, one core,
    /// exploration utility (eq. 7-10 and the path search), map and state updates, hand-offs
    /// and hierarchy bookkeeping included; the trials are prepared before the clock starts
    /// (scene generation and every sensor reading, as training prepares them ahead of the
    /// learner).
    pub maxq_steps_per_s: f64,
    /// The same with the preparation of the trials counted (one new scene per trial).
    pub maxq_steps_per_s_with_scene_generation: f64,
    /// The target of each figure that has one.
    pub targets: serde_json::Value,
}

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The campaign engine failed (its design, its database).
    #[error(transparent)]
    Campaign(#[from] usar_campaign::CampaignError),
    /// The team mission could not start.
    #[error(transparent)]
    Team(#[from] usar_team::MissionError),
    /// A temporary folder could not be made.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// The Python laser reference could not run or printed no rate.
    #[error("laser reference: {0}")]
    Reference(String),
    /// The mission of the recording benchmark could not run or be recorded.
    #[error("{0}")]
    Mission(String),
}

/// The number of stages [`run_observed`] reports, for a progress bar.
pub const STAGES: u64 = 6;

/// The median of the values (the upper one of an even count).
///
/// # Panics
/// On an empty list.
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The wall time of `f` in milliseconds.
pub fn time_ms(f: impl FnOnce()) -> f64 {
    let t = Instant::now();
    f();
    t.elapsed().as_secs_f64() * 1e3
}

/// The benchmark floor: a seeded 100 m × 100 m office.
pub fn bench_scene() -> Scene {
    generate_office(
        1,
        &BuildingParams {
            width_m: 100.0,
            height_m: 100.0,
            resolution_m: 0.1,
            ..BuildingParams::office()
        },
    )
}

/// Free poses spread over the scene, drawn with a fixed seed.
pub fn free_poses(scene: &Scene, n: usize) -> Vec<Pose2> {
    let g = scene.geometry();
    let mut rng = Pcg64Mcg::seed_from_u64(42);
    let mut poses = Vec::with_capacity(n);
    while poses.len() < n {
        let c = Cell::new(
            rng.random_range(0..g.width as i32),
            rng.random_range(0..g.height as i32),
        );
        if !scene.is_obstacle(c) {
            let p = g.cell_center(c);
            poses.push(Pose2::new(p.x, p.y, rng.random_range(-3.1..3.1)));
        }
    }
    poses
}

/// Opposite corners: the free cells nearest the lower-left and the upper-right corners.
///
/// # Panics
/// When no cell is passable.
pub fn corners(grid: &NavGrid) -> (Cell, Cell) {
    let g = *grid.geometry();
    let nearest = |target: Cell| {
        (0..g.len())
            .map(|i| g.cell_of_index(i))
            .filter(|&c| grid.is_passable(c))
            .min_by_key(|&c| ((c.col - target.col).pow(2) + (c.row - target.row).pow(2), c))
            .expect("a passable cell")
    };
    (
        nearest(Cell::new(0, 0)),
        nearest(Cell::new(g.width as i32 - 1, g.height as i32 - 1)),
    )
}

/// Laser scans per second with the default laser at 500 free poses of `scene`, each scan
/// integrated into one occupancy grid: the median of `reps` passes of `scans_per_rep` scans.
pub fn laser_scans_per_s(scene: &Scene, reps: usize, scans_per_rep: usize) -> f64 {
    let laser = LaserModel::new(LaserSpec::default());
    let mut rng = Pcg64Mcg::seed_from_u64(7);
    laser_rate(scene, &laser, &mut rng, reps, scans_per_rep)
}

fn laser_rate(
    scene: &Scene,
    laser: &LaserModel,
    rng: &mut Pcg64Mcg,
    reps: usize,
    scans_per_rep: usize,
) -> f64 {
    let world = SensingWorld::new(scene);
    let poses = free_poses(scene, 500);
    let mut grid = OccupancyGrid::new(*scene.geometry(), OccupancyParams::default());
    let mut scan = LaserScan::default();
    let rates: Vec<f64> = (0..reps)
        .map(|_| {
            let t = Instant::now();
            for k in 0..scans_per_rep {
                laser.scan_into(&world, poses[k % poses.len()], 0.0, rng, &mut scan);
                grid.integrate_scan(&scan);
            }
            scans_per_rep as f64 / t.elapsed().as_secs_f64()
        })
        .collect();
    median(rates)
}

/// MAXQ-Q training speed (see [`BenchReport::maxq_steps_per_s`]): a learner warmed up on 100
/// trials, then timed over 64 further scenes, median of three passes. Returns the steps per
/// second without and with the preparation of the trials.
pub fn maxq_training_speed() -> (f64, f64) {
    use usar_rescue::training::{PreparedTrial, TrainConfig, prepare_trial, train, trial_seed};
    use usar_rescue::{RescueDomain, RescueHierarchy};
    let config = TrainConfig {
        trials: 100,
        flat: false,
        ..TrainConfig::default()
    };
    let (mut learner, _) = train(&config, |_| {});
    let h = RescueHierarchy::new();
    let mut rng = Pcg64Mcg::seed_from_u64(7);
    let mut learn = |trials: &[PreparedTrial], base: u32| -> u64 {
        let mut steps = 0;
        for (k, trial) in trials.iter().enumerate() {
            let s = trial_seed(99, base + k as u32);
            let operator =
                usar_rescue::operator::SimulatedOperator::new(config.operator.clone(), s);
            let mut d = RescueDomain::with_perception(
                &trial.scene,
                trial.start,
                config.weights.clone(),
                config.domain.clone(),
                operator,
                s,
                trial.perception.clone(),
            );
            let s0 = d.state();
            steps += learner.learn_episode(&h, &mut d, s0, &mut rng).steps;
        }
        steps
    };
    let mut prepared = Vec::new();
    let mut with_generation = Vec::new();
    for pass in 0..3u32 {
        let t = Instant::now();
        let trials: Vec<_> = (0..64).map(|k| prepare_trial(99, pass * 64 + k)).collect();
        let generation_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let steps = learn(&trials, pass * 64) as f64;
        let learning_s = t.elapsed().as_secs_f64();
        prepared.push(steps / learning_s);
        with_generation.push(steps / (learning_s + generation_s));
    }
    (median(prepared), median(with_generation))
}

/// The experiment engine's own cost per run: a design of 2 000 no-op runs, run on one thread
/// into a fresh result database (expanding, scheduling, committing to SQLite; runs that finish
/// together share a commit). Second: one run per transaction (the case of runs that take long),
/// the median over 200 commits — mostly the fsync of SQLite's journal.
pub fn campaign_overhead_ms() -> Result<(f64, f64), BenchError> {
    use usar_campaign::{Design, NoopRunner, Shard, Store, run_design};
    let levels: Vec<String> = (0..100).map(|a| a.to_string()).collect();
    let text = format!(
        "name = \"overhead\"\nrunner = \"noop\"\nruns = 10\n[factors]\na = [{}]\nb = [\"x\", \"y\"]\n",
        levels.join(", ")
    );
    let design = Design::parse(&text, "bench", &NoopRunner)?;
    let dir = tempfile::tempdir()?;
    let started = Instant::now();
    let mut store = Store::open_or_create(dir.path(), &design)?;
    let report = run_design(&design, &NoopRunner, &mut store, Shard::ALL, 1, |_, _| {})?;
    let per_run = started.elapsed().as_secs_f64() * 1e3 / report.done as f64;
    let alone_dir = tempfile::tempdir()?;
    let mut alone = Store::open_or_create(alone_dir.path(), &design)?;
    let commits: Vec<f64> = design
        .runs()
        .take(200)
        .map(|spec| {
            let config = design.configs[spec.config_index].clone();
            let output =
                usar_campaign::Runner::run(&NoopRunner, &config, spec.seed).expect("no-op runs");
            let finished = usar_campaign::store::Finished {
                id: spec.id,
                config_index: spec.config_index,
                repetition: spec.repetition,
                seed: spec.seed,
                config,
                output,
                wall_time_s: 0.0,
            };
            time_ms(|| alone.insert(&[finished]).expect("commit"))
        })
        .collect();
    Ok((per_run, median(commits)))
}

/// One paper-002 mission (see [`BenchReport::team_realtime_factor`]): wall seconds.
pub fn team_run_wall_s() -> Result<f64, BenchError> {
    use usar_team::coordination::Coordination;
    use usar_team::{Exploration, Strategy, TeamConfig, TeamMission};
    let scene = std::sync::Arc::new(usar_world::generate::generate(
        usar_world::generate::SceneKind::Office,
        1,
    ));
    let exploration = Exploration {
        strategy: Strategy::SMcdm,
        coordination: Coordination::Mrv1,
        ..Exploration::default()
    };
    let config = TeamConfig::paper_002(8, 20.0, exploration);
    let mission = TeamMission::new(scene, config, 1)?;
    let t = Instant::now();
    let outcome = mission.run(|_| {});
    let wall = t.elapsed().as_secs_f64();
    std::hint::black_box(outcome);
    Ok(wall)
}

/// Every benchmark: 11 repetitions, or 3 when `quick` (a quick look, noisier).
pub fn run(quick: bool) -> Result<BenchReport, BenchError> {
    run_observed(quick, || {})
}

/// [`run`], calling `stage_done` after each of its [`STAGES`] stages.
pub fn run_observed(quick: bool, mut stage_done: impl FnMut()) -> Result<BenchReport, BenchError> {
    let reps = if quick { 3 } else { 11 };
    let scene = bench_scene();
    let g = *scene.geometry();

    // Laser scans with the free-space update of an occupancy grid.
    let world = SensingWorld::new(&scene);
    let laser = LaserModel::new(LaserSpec::default());
    let mut rng = Pcg64Mcg::seed_from_u64(7);
    let scans_per_rep = if quick { 2_000 } else { 10_000 };
    let lidar_scans_per_s = laser_rate(&scene, &laser, &mut rng, reps.min(5), scans_per_rep);
    stage_done();

    // A* and distance fields on the floor inflated for a wheeled robot.
    let blocked = inflate(
        &scene.obstacle.map(|&o| o != 0),
        RobotSpec::wheeled().circumscribed_radius_m(),
    );
    let nav = NavGrid::from_blocked(&blocked);
    let (start, goal) = corners(&nav);
    let mut astar = GridAStar::new();
    let mut path_length_m = 0.0;
    let mut scanned = 0;
    let mut plan = |conn, algorithm| {
        let ms = median(
            (0..reps)
                .map(|_| {
                    time_ms(|| {
                        let p = astar
                            .plan_with(&nav, start, goal, conn, algorithm)
                            .expect("corners are connected");
                        path_length_m = p.length_m(g.resolution_m);
                    })
                })
                .collect(),
        );
        scanned = astar.scanned();
        (ms, astar.expanded())
    };
    let (astar4_ms, astar4_expanded) = plan(Connectivity::Four, GridAlgorithm::AStar);
    let (astar8_plain_ms, astar8_plain_expanded) = plan(Connectivity::Eight, GridAlgorithm::AStar);
    let (astar8_ms, astar8_expanded) = plan(Connectivity::Eight, GridAlgorithm::JumpPoint);
    let astar8_scanned = scanned;
    stage_done();
    let mut field = DistanceField::new();
    let mut field_ms = |conn| {
        median(
            (0..reps)
                .map(|_| time_ms(|| field.compute(&nav, &[start], conn)))
                .collect(),
        )
    };
    let distance_field_ms = field_ms(Connectivity::Eight);
    let distance_field4_ms = field_ms(Connectivity::Four);
    stage_done();

    // Incremental frontier update after one scan, along a walk through the floor.
    let mut grid = OccupancyGrid::new(g, OccupancyParams::default());
    let mut tracker = FrontierTracker::new(&grid);
    let walk = free_poses(&scene, 400);
    let mut scan = LaserScan::default();
    let mut updates = Vec::with_capacity(walk.len());
    let mut clusters = Vec::new();
    for (k, &pose) in walk.iter().enumerate() {
        laser.scan_into(&world, pose, 0.0, &mut rng, &mut scan);
        grid.integrate_scan(&scan);
        updates.push(time_ms(|| tracker.update(&mut grid)));
        if k % 20 == 0 {
            clusters.push(time_ms(|| {
                tracker.clusters(&grid, 3);
            }));
        }
    }
    let frontier_update_ms = median(updates);
    let frontier_clusters_ms = median(clusters);
    let params = usar_world::cellview::CellViewParams::default();
    let cell_view_ms = median(
        (0..reps)
            .map(|_| {
                time_ms(|| {
                    std::hint::black_box(usar_world::cellview::CellView::from_scene(
                        &scene, &params,
                    ));
                })
            })
            .collect(),
    );
    stage_done();
    let (campaign_overhead_ms_per_run, campaign_commit_alone_ms) = campaign_overhead_ms()?;
    let (maxq_steps_per_s, maxq_steps_per_s_with_scene_generation) = maxq_training_speed();
    stage_done();
    let team_run_wall_s = median(
        (0..if quick { 1 } else { 3 })
            .map(|_| team_run_wall_s())
            .collect::<Result<Vec<f64>, _>>()?,
    );
    stage_done();

    Ok(BenchReport {
        grid: format!(
            "office 100 x 100 m at {} m ({} x {} cells), inflated by the wheeled robot's radius",
            g.resolution_m, g.width, g.height
        ),
        lidar_scans_per_s,
        astar4_ms,
        astar4_expanded,
        astar8_ms,
        astar8_expanded,
        astar8_scanned,
        astar8_plain_ms,
        astar8_plain_expanded,
        path_length_m,
        distance_field_ms,
        distance_field4_ms,
        frontier_update_ms,
        frontier_clusters_ms,
        cell_view_ms,
        campaign_overhead_ms_per_run,
        maxq_steps_per_s,
        maxq_steps_per_s_with_scene_generation,
        campaign_commit_alone_ms,
        team_realtime_factor: 1200.0 / team_run_wall_s,
        team_run_wall_s,
        targets: serde_json::json!({
            "team_realtime_factor": ">= 600",
            "lidar_scans_per_s": ">= 20000", "astar4_ms": "<= 10", "astar8_ms": "<= 10",
            "distance_field_ms": "<= 10", "frontier_update_ms": "<= 0.3",
            "campaign_overhead_ms_per_run": "< 1",
            "maxq_steps_per_s": ">= 1000000"
        }),
    })
}

/// The table `usar bench` prints: one line per figure with its target.
impl fmt::Display for BenchReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.grid)?;
        writeln!(
            f,
            "  laser scans + occupancy update  {:>10.0} scans/s   (target ≥ 20 000)",
            self.lidar_scans_per_s
        )?;
        writeln!(
            f,
            "  MAXQ training primitive steps   {:>10.0} steps/s   (target ≥ 1 000 000; {:.0} with scene generation)",
            self.maxq_steps_per_s, self.maxq_steps_per_s_with_scene_generation
        )?;
        writeln!(
            f,
            "  A* 4-connected corner to corner {:>10.2} ms       (target ≤ 10; {} expanded)",
            self.astar4_ms, self.astar4_expanded
        )?;
        writeln!(
            f,
            "  A* 8-connected corner to corner {:>10.2} ms       (target ≤ 10; jump point search: {} expanded, {} cells scanned)",
            self.astar8_ms, self.astar8_expanded, self.astar8_scanned
        )?;
        writeln!(
            f,
            "  plain A* 8-connected            {:>10.2} ms       ({} expanded)",
            self.astar8_plain_ms, self.astar8_plain_expanded
        )?;
        writeln!(
            f,
            "  distance field, 8-connected     {:>10.2} ms       (target ≤ 10)",
            self.distance_field_ms
        )?;
        writeln!(
            f,
            "  distance field, 4-connected     {:>10.2} ms",
            self.distance_field4_ms
        )?;
        writeln!(
            f,
            "  frontier update after one scan  {:>10.3} ms       (target ≤ 0.3)",
            self.frontier_update_ms
        )?;
        writeln!(
            f,
            "  frontier clustering             {:>10.3} ms",
            self.frontier_clusters_ms
        )?;
        writeln!(
            f,
            "  paper-000 cell view of the floor {:>9.2} ms",
            self.cell_view_ms
        )?;
        writeln!(
            f,
            "  campaign engine, per no-op run  {:>10.3} ms       (target < 1)",
            self.campaign_overhead_ms_per_run
        )?;
        writeln!(
            f,
            "  campaign, one run per commit    {:>10.3} ms",
            self.campaign_commit_alone_ms
        )?;
        write!(
            f,
            "  team run, 8 robots, 20 min      {:>10.0} × real time (target ≥ 600; {:.2} s)",
            self.team_realtime_factor, self.team_run_wall_s
        )
    }
}

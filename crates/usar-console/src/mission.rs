//! The live mission: three threads around one [`MissionClock`].
//!
//! - the team's simulation thread ([`crate::team_hook::ConsoleHook`]) steps paper 002's
//!   mission at the chosen speed, moves the clock, carries out commands and publishes frames;
//! - the MAXQ robot's thread ([`crate::operator::run_rescue_robot`]) runs learning episodes,
//!   one primitive per 1.5 simulated seconds, waiting on the clock and on its operator;
//! - the BTM builder's thread (paper 004) drives its own crawler through the same scene,
//!   once per simulated second waiting on the clock; its store is read back for the overlay.
//!
//! Frames and maps go out through `tokio::sync::watch` channels: publishing replaces the
//! latest value and never waits for a viewer.

use crate::ConsoleError;
use crate::clock::MissionClock;
use crate::config::MissionConfig;
use crate::operator::run_rescue_robot;
use crate::protocol::ClientMessage;
use crate::scene_setup::{default_scene, starting_at, with_team_starts, with_zones};
use crate::snapshot::{BtmLinkView, BtmNodeView, HandOffView};
use crate::team_hook::{ConsoleHook, strategy};
use std::collections::BTreeMap;
use std::sync::atomic::AtomicU64;
use std::sync::mpsc;
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tokio::sync::{oneshot, watch};
use usar_rescue::policy::PolicyFile;
use usar_rescue::training::{TrainConfig, train};
use usar_rescue::{DomainConfig, RescueScene, VictimMark};
use usar_sim::CellAction;
use usar_team::{Exploration, TeamConfig, TeamMission};
use usar_world::{Cell, Scene};

/// A control message for the mission thread and where its result goes.
pub(crate) type Command = (ClientMessage, oneshot::Sender<Result<(), String>>);

/// What the console's operator answers the MAXQ robot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OperatorAnswer {
    Victim { handoff: u64, tag: bool },
    Drive(CellAction),
}

/// The MAXQ robot as the other threads see it.
pub(crate) struct RescueShared {
    pub cell: Cell,
    pub heading: u8,
    pub pose: [f64; 3],
    pub mode: &'static str,
    pub task: String,
    /// Possible victims by cell: their mark and measured probability; a tag is never undone.
    pub victims: BTreeMap<(i32, i32), (VictimMark, Option<f64>)>,
    pub cell_map: Vec<u8>,
    pub cell_map_version: u64,
    pub cell_cols: u32,
    pub cell_rows: u32,
    pub cell_size_m: f64,
    pub cell_origin: [f64; 2],
    pub handoff: Option<HandOffView>,
    pub weights: [f64; 3],
    pub weights_changed: Option<[f64; 3]>,
    pub episodes: u32,
    /// Tags the robot's domain has carried out (its own and the operator's), all episodes.
    pub tags: u32,
}

/// Per hand-off: its thermal and depth images (PNG).
pub(crate) type HandOffImages = BTreeMap<u64, (Vec<u8>, Vec<u8>)>;

/// The BTM overlay.
#[derive(Default)]
pub(crate) struct BtmShared {
    pub nodes: Vec<BtmNodeView>,
    pub links: Vec<BtmLinkView>,
    pub status: String,
    /// The crawler building the BTM, while it drives: x, y, θ.
    pub crawler: Option<[f64; 3]>,
}

/// State shared by the mission threads and the server.
pub struct Shared {
    pub clock: MissionClock,
    pub(crate) rescue: Mutex<RescueShared>,
    pub(crate) btm: Mutex<BtmShared>,
    pub(crate) images: Mutex<HandOffImages>,
    pub(crate) next_handoff: AtomicU64,
    /// Simulation steps of the team so far.
    pub steps: AtomicU64,
    pub(crate) frame_tx: watch::Sender<Arc<str>>,
    pub(crate) map_tx: watch::Sender<Arc<str>>,
    operator_tx: mpsc::Sender<OperatorAnswer>,
    commands_tx: mpsc::Sender<Command>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Shared {
    pub(crate) fn lock_rescue(&self) -> MutexGuard<'_, RescueShared> {
        lock(&self.rescue)
    }

    pub(crate) fn lock_btm(&self) -> MutexGuard<'_, BtmShared> {
        lock(&self.btm)
    }

    pub(crate) fn lock_images(&self) -> MutexGuard<'_, HandOffImages> {
        lock(&self.images)
    }

    pub(crate) fn answer(&self, answer: OperatorAnswer) -> Result<(), String> {
        self.operator_tx
            .send(answer)
            .map_err(|_| "the MAXQ robot is no longer running".to_string())
    }

    /// A hand-off image: `thermal` or `depth` of hand-off `id`.
    pub fn image(&self, id: u64, which: &str) -> Option<Vec<u8>> {
        let images = self.lock_images();
        let (thermal, depth) = images.get(&id)?;
        match which {
            "thermal.png" => Some(thermal.clone()),
            "depth.png" => Some(depth.clone()),
            _ => None,
        }
    }

    /// Sends a validated control message to the mission and waits for its result.
    pub async fn control(&self, message: ClientMessage) -> Result<(), String> {
        let (tx, rx) = oneshot::channel();
        self.commands_tx
            .send((message, tx))
            .map_err(|_| "the mission has stopped".to_string())?;
        match tokio::time::timeout(Duration::from_secs(5), rx).await {
            Ok(Ok(result)) => result,
            Ok(Err(_)) => Err("the mission has stopped".into()),
            Err(_) => Err("the mission did not answer within 5 s".into()),
        }
    }

    pub fn frame_receiver(&self) -> watch::Receiver<Arc<str>> {
        self.frame_tx.subscribe()
    }

    pub fn map_receiver(&self) -> watch::Receiver<Arc<str>> {
        self.map_tx.subscribe()
    }
}

/// A running mission; stops its threads when dropped.
pub struct Mission {
    pub shared: Arc<Shared>,
    threads: Vec<JoinHandle<()>>,
}

impl Mission {
    /// Stops the threads and waits for them.
    pub fn stop(&mut self) {
        self.shared.clock.stop();
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

impl Drop for Mission {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Panic payload that ends the BTM build when the mission stops (see [`run_btm`]).
struct StopBuild;

/// Builds the BTM beside the mission, paced by the clock; the overlay is taken from the map
/// being built at most twice per wall-clock second. The first start pose the crawler fits on
/// is used. When the mission stops, the build is ended by unwinding out of its progress
/// callback (the builder has no other way to be interrupted).
fn run_btm(shared: Arc<Shared>, scene: Scene, seed: u64) {
    use usar_btm::build::{BuildConfig, BuildError, build_btm_observed};
    let config = BuildConfig::default();
    for k in 0..scene.start_poses.len() {
        let mut last_overlay = Instant::now();
        let clock_shared = shared.clone();
        let mut on_progress = |t: f64, pose: usar_world::Pose2, btm: &usar_btm::Btm| {
            if !clock_shared.clock.wait_until(t) {
                std::panic::resume_unwind(Box::new(StopBuild));
            }
            clock_shared.lock_btm().crawler = Some([pose.x, pose.y, pose.theta]);
            if last_overlay.elapsed() >= Duration::from_millis(500) {
                last_overlay = Instant::now();
                set_overlay(&clock_shared, btm, "building");
            }
        };
        let scene_k = Arc::new(starting_at(&scene, k));
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            build_btm_observed(
                scene_k,
                usar_sim::RobotSpec::crawler(),
                &config,
                seed,
                None,
                &mut on_progress,
            )
        }));
        match result {
            Err(_) => return,
            Ok(Err(BuildError::Placement { .. })) => continue,
            Ok(Err(e)) => {
                shared.lock_btm().status = format!("BTM build: {e}");
                return;
            }
            Ok(Ok(outcome)) => {
                set_overlay(&shared, &outcome.btm, "built");
                return;
            }
        }
    }
    shared.lock_btm().status = "BTM: the crawler fits on no start pose".into();
}

fn set_overlay(shared: &Shared, btm: &usar_btm::Btm, status: &str) {
    let mut o = shared.lock_btm();
    o.nodes = btm
        .nodes
        .iter()
        .map(|n| BtmNodeView {
            id: n.id,
            x: n.x_m,
            y: n.y_m,
            kind: n.kind.clone(),
        })
        .collect();
    o.links = btm
        .links
        .iter()
        .map(|l| BtmLinkView {
            start: l.start,
            end: l.end,
            searched: l.searched,
            direction_rad: l.direction_rad,
        })
        .collect();
    o.status = status.into();
}

/// Sets up the scene, the policy and the team, and starts the threads.
pub fn launch(config: MissionConfig) -> Result<Mission, ConsoleError> {
    config.validate()?;
    let scene = with_zones(
        config
            .scene
            .clone()
            .unwrap_or_else(|| default_scene(config.seed, config.floor_cell_m2)),
    );
    let learner = match &config.policy {
        Some(path) => PolicyFile::load(path)?.learner,
        None => {
            let train_config = TrainConfig {
                seed: config.seed,
                trials: config.train_trials,
                flat: false,
                ..TrainConfig::default()
            };
            train(&train_config, |_| {}).0
        }
    };
    let rescue_scene = Arc::new(RescueScene::new(scene.clone()));
    let view = &rescue_scene.view;
    let exploration = Exploration {
        strategy: strategy(&config.strategy).unwrap_or(usar_team::Strategy::SMcdm),
        hypothesis: usar_team::criteria::Hypothesis::named(&config.hypothesis)
            .unwrap_or_else(usar_team::criteria::Hypothesis::big_rooms),
        ..Exploration::default()
    };
    let mut team_config = TeamConfig::paper_002(config.team_robots, config.minutes, exploration);
    if let Some(robot) = usar_sim::RobotSpec::preset(&config.team_robot) {
        team_config.robot = robot;
    }
    let team_scene = Arc::new(with_team_starts(&scene, &team_config));
    let team = TeamMission::new(team_scene, team_config, config.seed)?;

    let (frame_tx, _) = watch::channel(Arc::<str>::from("{}"));
    let (map_tx, _) = watch::channel(Arc::<str>::from("{}"));
    let (operator_tx, operator_rx) = mpsc::channel();
    let (commands_tx, commands_rx) = mpsc::channel();
    let origin = view.geometry.origin;
    let shared = Arc::new(Shared {
        clock: MissionClock::new(),
        rescue: Mutex::new(RescueShared {
            cell: Cell::new(0, 0),
            heading: 0,
            pose: [0.0; 3],
            mode: "autonomous",
            task: "starting".into(),
            victims: BTreeMap::new(),
            cell_map: vec![0; view.classes.len()],
            cell_map_version: 0,
            cell_cols: view.cols,
            cell_rows: view.rows,
            cell_size_m: view.geometry.resolution_m,
            cell_origin: [origin.x, origin.y],
            handoff: None,
            weights: config.weights,
            weights_changed: None,
            episodes: 0,
            tags: 0,
        }),
        btm: Mutex::new(BtmShared::default()),
        images: Mutex::new(BTreeMap::new()),
        next_handoff: AtomicU64::new(1),
        steps: AtomicU64::new(0),
        frame_tx,
        map_tx,
        operator_tx,
        commands_tx,
    });
    let mut threads = Vec::new();
    let domain = DomainConfig {
        slip_probability: config.slip_probability,
        stuck_after_slips: config.stuck_after_slips,
        ..DomainConfig::default()
    };
    {
        let shared = shared.clone();
        let seed = config.seed;
        threads.push(std::thread::spawn(move || {
            run_rescue_robot(shared, rescue_scene, learner, domain, operator_rx, seed)
        }));
    }
    if config.btm {
        let shared = shared.clone();
        let (scene, seed) = (scene.clone(), config.seed);
        threads.push(std::thread::spawn(move || run_btm(shared, scene, seed)));
    } else {
        shared.lock_btm().status = "off".into();
    }
    {
        let shared = shared.clone();
        let mut hook = ConsoleHook::new(
            shared,
            commands_rx,
            config.speed,
            &config.hypothesis,
            config.team_robots,
        );
        threads.push(std::thread::spawn(move || {
            let outcome = team.run_live(|_| {}, &mut hook);
            let finish = format!("{:?}", outcome.finish).to_lowercase();
            hook.after_mission(&finish);
        }));
    }
    Ok(Mission { shared, threads })
}

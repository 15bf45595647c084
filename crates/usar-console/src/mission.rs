//! The live mission: one thread runs the whole mission of `usar mission run`
//! ([`usar_mission::run_mission_live`]) — the team, the crawler and the rescuer as controllers
//! on one host, one physics — with the console's [`ConsoleHook`] beside it, and the person at
//! the console as the mission's operator ([`Operator::Person`]): every hand-off waits for their
//! answer.
//!
//! Frames and maps go out through `tokio::sync::watch` channels: publishing replaces the
//! latest value and never waits for a viewer.

use crate::ConsoleError;
use crate::clock::MissionClock;
use crate::config::MissionConfig;
use crate::hook::ConsoleHook;
use crate::protocol::ClientMessage;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;
use std::sync::atomic::AtomicU64;
use std::sync::mpsc;
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Duration;
use tokio::sync::{oneshot, watch};
use usar_mission::{Operator, run_mission_live};
use usar_record::{MissionRecorder, Recording};
use usar_world::partial_path;

/// A control message for the mission thread and where its result goes.
pub(crate) type Command = (ClientMessage, oneshot::Sender<Result<(), String>>);

/// Per hand-off: its thermal and depth images (PNG).
pub(crate) type HandOffImages = BTreeMap<u64, (Vec<u8>, Vec<u8>)>;

/// State shared by the mission thread and the server.
pub struct Shared {
    pub clock: MissionClock,
    pub(crate) images: Mutex<HandOffImages>,
    /// Simulation steps so far.
    pub steps: AtomicU64,
    pub(crate) frame_tx: watch::Sender<Arc<str>>,
    pub(crate) map_tx: watch::Sender<Arc<str>>,
    commands_tx: mpsc::Sender<Command>,
}

impl Shared {
    pub(crate) fn lock_images(&self) -> MutexGuard<'_, HandOffImages> {
        self.images.lock().unwrap_or_else(|e| e.into_inner())
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

/// A running mission; stops its thread when dropped.
pub struct Mission {
    pub shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl Mission {
    /// Stops the thread and waits for it.
    pub fn stop(&mut self) {
        self.shared.clock.stop();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Mission {
    fn drop(&mut self) {
        self.stop();
    }
}

/// A recorder writing to `path`'s partial file (renamed when the mission has ended).
fn start_recording(path: &Path) -> Result<MissionRecorder<BufWriter<File>>, ConsoleError> {
    let fail = |message: String| ConsoleError::Record {
        path: path.into(),
        message,
    };
    let file = File::create(partial_path(path)).map_err(|e| fail(e.to_string()))?;
    let recording = Recording::new(BufWriter::new(file)).map_err(|e| fail(e.to_string()))?;
    Ok(MissionRecorder::new(recording))
}

/// Completes the recording and gives it its name; a failed one leaves no file.
fn finish_recording(recorder: MissionRecorder<BufWriter<File>>, path: &Path) -> Result<(), String> {
    let partial = partial_path(path);
    let done = recorder
        .finish()
        .map_err(|e| e.to_string())
        .and_then(|_| std::fs::rename(&partial, path).map_err(|e| e.to_string()));
    if let Err(e) = &done {
        let _ = std::fs::remove_file(&partial);
        return Err(format!("recording {} failed: {e}", path.display()));
    }
    Ok(())
}

/// Sets the mission up (its scene, its robots, the rescuer's policy) and starts it; returns
/// once its first step is taken, or with the reason it could not be set up.
pub fn launch(config: MissionConfig) -> Result<Mission, ConsoleError> {
    config.validate()?;
    let scene = Arc::new(config.scene()?);
    let (frame_tx, _) = watch::channel(Arc::<str>::from("{}"));
    let (map_tx, _) = watch::channel(Arc::<str>::from("{}"));
    let (commands_tx, commands_rx) = mpsc::channel();
    let shared = Arc::new(Shared {
        clock: MissionClock::new(),
        images: Mutex::new(BTreeMap::new()),
        steps: AtomicU64::new(0),
        frame_tx,
        map_tx,
        commands_tx,
    });
    let mut recorder = match &config.record {
        Some(path) => Some(start_recording(path)?),
        None => None,
    };
    let (ready_tx, ready_rx) = mpsc::sync_channel(1);
    let thread = {
        let shared = shared.clone();
        std::thread::spawn(move || {
            let m = &config.mission;
            let weights =
                usar_rescue::exploration::ExplorationWeights::named_factors(&m.rescuer.weights)
                    .unwrap_or([1.0; 3]);
            let mut hook = ConsoleHook::new(
                shared,
                commands_rx,
                ready_tx,
                config.speed,
                &m.team.hypothesis,
                weights,
            );
            let run = |hook: &mut dyn usar_mission::MissionHook| {
                run_mission_live(scene, m, config.seed, None, Operator::Person, |_| {}, hook)
            };
            let result = match recorder.as_mut() {
                Some(r) => run(&mut (&mut hook, r)),
                None => run(&mut hook),
            };
            // The recording is complete when the mission ends.
            let recorded = match (recorder, &config.record) {
                (Some(r), Some(path)) => finish_recording(r, path),
                _ => Ok(()),
            };
            match result {
                Ok(outcome) => {
                    let finish = if outcome.time_s + 1e-9 >= m.minutes * 60.0 {
                        "time limit"
                    } else {
                        "stopped"
                    };
                    match recorded {
                        Ok(()) => hook.after_mission(finish),
                        Err(e) => hook.after_mission(&format!("{finish}; {e}")),
                    }
                }
                Err(e) => {
                    if let Some(e) = hook.failed(e) {
                        hook.after_mission(&format!("failed: {e}"));
                    }
                }
            }
        })
    };
    match ready_rx.recv() {
        Ok(Ok(())) => Ok(Mission {
            shared,
            thread: Some(thread),
        }),
        Ok(Err(e)) => {
            let _ = thread.join();
            Err(e.into())
        }
        Err(_) => {
            let _ = thread.join();
            Err(ConsoleError::Field {
                field: "mission".into(),
                message: "its thread ended before the first step".into(),
            })
        }
    }
}

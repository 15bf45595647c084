//! Records ten simulated seconds of the built-in mission into an MCAP file and says what it
//! holds: open the file in Foxglove (or Lichtblick, Rerun) to watch the robots.
//!
//! `cargo run -p usar-record --example record_a_mission [FILE.mcap]`

use std::sync::Arc;
use usar_mission::{MissionConfig, Operator, run_mission_live};
use usar_record::{MissionRecorder, Recording};
use usar_world::generate::{SceneKind, generate};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = tempfile::tempdir()?;
    let path = std::env::args()
        .nth(1)
        .map_or_else(|| dir.path().join("mission.mcap"), Into::into);
    let scene = Arc::new(generate(SceneKind::Office, 1));
    let mut config = MissionConfig {
        minutes: 10.0 / 60.0,
        ..MissionConfig::default()
    };
    config.rescuer.train_trials = 50;
    let file = std::io::BufWriter::new(std::fs::File::create(&path)?);
    let mut recorder = MissionRecorder::new(Recording::new(file)?);
    let outcome = run_mission_live(
        scene,
        &config,
        1,
        None,
        Operator::Simulated,
        |_| {},
        &mut recorder,
    )?;
    let messages = recorder.finish()?;
    println!(
        "{messages} messages over {:.0} simulated seconds in {} ({} bytes)",
        outcome.time_s,
        path.display(),
        std::fs::metadata(&path)?.len()
    );
    Ok(())
}

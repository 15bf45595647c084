//! `usar demo`: the main job on built-in defaults — the whole mission in one world, as `usar
//! mission run` runs the built-in mission: four wheeled robots explore the relevant areas of a
//! generated office floor with S-MCDM + MRv1, a crawler builds a Behavioral Trace Map and shares
//! it over the radio, a MAXQ robot searches a zone of the floor, and one simulated operator
//! answers every hand-off; the report folder is written.

use super::mission::execute;
use crate::cli::{DemoArgs, ImageArgs, MissionRunArgs};
use crate::failure::CmdResult;
use std::time::Instant;
use usar_mission::MissionConfig;

pub fn run(args: DemoArgs) -> CmdResult {
    let started = Instant::now();
    let config = MissionConfig {
        scene_seed: args.seed,
        ..MissionConfig::default()
    };
    if !args.json {
        eprintln!(
            "demo: the built-in mission on office floor {} — {} wheeled robots ({} + {}), a crawler building a BTM, a MAXQ robot in a {} × {} cell zone, one operator; {} simulated minutes",
            args.seed,
            config.team.robots,
            config.team.strategy,
            config.team.coordination,
            config.rescuer.zone_cells,
            config.rescuer.zone_cells,
            config.minutes
        );
    }
    let mission = MissionRunArgs {
        file: None,
        seed: args.seed,
        minutes: None,
        out: Some(args.out),
        btm: None,
        record: args.record,
        image: ImageArgs::none(),
        json: args.json,
    };
    execute(&config, &mission, started)
}

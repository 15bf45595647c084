//! The runners campaigns can name: each wraps a controller of the library crates as a
//! [`usar_campaign::Runner`] and lives in the controller's crate (`explore` and `team` in
//! `usar-team`, `maxq-eval` in `usar-rescue`, `mission` in `usar-mission`); here they are named
//! and the presets kept.

use usar_campaign::Runner;

static EXPLORE: usar_team::runner::ExploreRunner = usar_team::runner::ExploreRunner::new();
static TEAM: usar_team::runner::TeamRunner = usar_team::runner::TeamRunner::new();
static MAXQ_EVAL: usar_rescue::runner::MaxqEvalRunner = usar_rescue::runner::MaxqEvalRunner::new();
static MISSION: usar_mission::runner::MissionRunner = usar_mission::runner::MissionRunner::new();

/// Every runner, by the name campaign files use.
pub fn all() -> [&'static dyn Runner; 4] {
    [&EXPLORE, &TEAM, &MAXQ_EVAL, &MISSION]
}

/// The runner a campaign names, if there is one.
pub fn named(name: &str) -> Option<&'static dyn Runner> {
    all().into_iter().find(|r| r.name() == name)
}

/// The built-in campaign presets: name and file text (the files live in `campaigns/`).
pub const PRESETS: [(&str, &str); 10] = [
    ("smoke", include_str!("../../../../campaigns/smoke.toml")),
    (
        "team-tables",
        include_str!("../../../../campaigns/team-tables.toml"),
    ),
    (
        "team-fig5",
        include_str!("../../../../campaigns/team-fig5.toml"),
    ),
    (
        "team-fig12",
        include_str!("../../../../campaigns/team-fig12.toml"),
    ),
    (
        "team-fig13-14",
        include_str!("../../../../campaigns/team-fig13-14.toml"),
    ),
    (
        "team-fig15",
        include_str!("../../../../campaigns/team-fig15.toml"),
    ),
    (
        "team-oracles",
        include_str!("../../../../campaigns/team-oracles.toml"),
    ),
    (
        "maxq-eval",
        include_str!("../../../../campaigns/maxq-eval.toml"),
    ),
    (
        "mission",
        include_str!("../../../../campaigns/mission.toml"),
    ),
    (
        "rescuer-put-down",
        include_str!("../../../../campaigns/rescuer-put-down.toml"),
    ),
];

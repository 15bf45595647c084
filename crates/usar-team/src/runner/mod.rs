//! The campaign runners of this crate, each a [`usar_campaign::Runner`]: `explore` (the
//! baseline nearest-frontier explorer) and `team` (paper 002's semantically-informed team).

mod explore;
mod team;

pub use self::explore::{ExploreRunner, SceneCache, scene_for};
pub use self::team::TeamRunner;

use crate::tuning::Tuning;
use usar_campaign::{Config, FactorSpec};

/// The fields of [`Tuning`] as factors (by their field names, defaults as they are).
pub(crate) fn tuning_factors() -> Vec<FactorSpec> {
    Tuning::fields()
        .into_iter()
        .map(|(name, default)| {
            let help = "tuning of driving, recovery or allocation (usar_team::tuning::Tuning)";
            match default.as_i64() {
                Some(n) => FactorSpec::int(&name, (0, 1_000_000), n, help),
                None => FactorSpec::float(&name, (0.0, 1e6), default.as_f64().unwrap_or(0.0), help),
            }
        })
        .collect()
}

/// The tuning a configuration sets.
pub(crate) fn tuning_of(config: &Config) -> Result<Tuning, String> {
    Tuning::default().with(|name| config.float(name))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;
    use usar_campaign::{Config, Level, Runner};

    /// The runner's defaults with `minutes` simulated minutes and two robots.
    fn config(runner: &dyn Runner, minutes: f64) -> Config {
        let mut levels: BTreeMap<String, Level> = runner
            .factors()
            .into_iter()
            .map(|f| (f.name, f.default))
            .collect();
        levels.insert("minutes".into(), Level::Float(minutes));
        levels.insert("robots".into(), Level::Int(2));
        Config(levels)
    }

    #[test]
    fn both_runners_run_a_configuration_as_a_pure_function_of_it_and_the_seed() {
        let runners: [&dyn Runner; 2] = [&ExploreRunner::new(), &TeamRunner::new()];
        for runner in runners {
            let config = config(runner, 0.5);
            assert_eq!(runner.check(&config), Ok(()), "{}", runner.name());
            let a = runner.run(&config, 3).unwrap();
            assert_eq!(a, runner.run(&config, 3).unwrap(), "{}", runner.name());
            for m in runner.metrics() {
                assert!(
                    a.metrics.contains_key(&m.name),
                    "{}: {}",
                    runner.name(),
                    m.name
                );
            }
        }
    }
}

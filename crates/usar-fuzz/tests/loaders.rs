//! One test per loader: its seeds load, and a bounded session of mutations finds nothing.

use usar_fuzz::{fuzz, loaders::loader};

fn seconds() -> f64 {
    std::env::var("USAR_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(15.0)
}

fn seed() -> u64 {
    std::env::var("USAR_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1)
}

fn fuzz_loader(name: &str) {
    let loader = loader(name).expect("a loader of that name");
    let seeds = (loader.seeds)();
    assert!(!seeds.is_empty(), "{name}: no seed files found");
    for (i, s) in seeds.iter().enumerate() {
        assert_eq!((loader.load)(s), Ok(()), "{name}: seed {i} does not load");
    }
    let report = fuzz(loader, seconds(), seed());
    eprintln!(
        "fuzz {name}: {} inputs, {} accepted, {} findings",
        report.inputs,
        report.accepted,
        report.findings.len()
    );
    assert!(report.findings.is_empty(), "{name}: {:#?}", report.findings);
    assert!(report.inputs > seeds.len() as u64);
}

macro_rules! fuzz_tests {
    ($($test:ident => $name:literal),* $(,)?) => {
        $(#[test] fn $test() { fuzz_loader($name); })*

        #[test]
        fn every_loader_has_a_test() {
            let tested = [$($name),*];
            for l in usar_fuzz::loaders::LOADERS {
                assert!(tested.contains(&l.name), "{} has no fuzz test", l.name);
            }
        }
    };
}

fuzz_tests! {
    image => "image",
    ros_yaml => "ros-yaml",
    movingai_map => "movingai-map",
    movingai_scen => "movingai-scen",
    scene_json => "scene-json",
    robot_toml => "robot-toml",
    mission_toml => "mission-toml",
    campaign_toml => "campaign-toml",
    policy_json => "policy-json",
    btm_sqlite => "btm-sqlite",
    btm_json => "btm-json",
    btm_wire => "btm-wire",
}

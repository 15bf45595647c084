//! Every loader of usar, with the real files its mutations start from. A loader returns
//! `Ok` or `Err` for any input; a panic, runaway memory or a slow input is a finding.

use std::path::{Path, PathBuf};

/// One loader under test.
pub struct Loader {
    /// Its name (`usar-fuzz` runs one by name).
    pub name: &'static str,
    /// Real files to mutate.
    pub seeds: fn() -> Vec<Vec<u8>>,
    /// Reads an input; the error text is discarded.
    pub load: fn(&[u8]) -> Result<(), String>,
}

/// Every loader, in a stable order.
pub const LOADERS: &[Loader] = &[
    Loader {
        name: "image",
        seeds: image_seeds,
        load: load_image,
    },
    Loader {
        name: "ros-yaml",
        seeds: ros_yaml_seeds,
        load: load_ros_yaml,
    },
    Loader {
        name: "movingai-map",
        seeds: movingai_map_seeds,
        load: load_movingai_map,
    },
    Loader {
        name: "movingai-scen",
        seeds: movingai_scen_seeds,
        load: load_movingai_scen,
    },
    Loader {
        name: "scene-json",
        seeds: scene_json_seeds,
        load: load_scene_json,
    },
    Loader {
        name: "robot-toml",
        seeds: robot_toml_seeds,
        load: load_robot_toml,
    },
    Loader {
        name: "mission-toml",
        seeds: mission_toml_seeds,
        load: load_mission_toml,
    },
    Loader {
        name: "campaign-toml",
        seeds: campaign_toml_seeds,
        load: load_campaign_toml,
    },
    Loader {
        name: "policy-json",
        seeds: policy_json_seeds,
        load: load_policy_json,
    },
    Loader {
        name: "btm-sqlite",
        seeds: btm_sqlite_seeds,
        load: load_btm_sqlite,
    },
    Loader {
        name: "btm-json",
        seeds: btm_json_seeds,
        load: load_btm_json,
    },
    Loader {
        name: "btm-wire",
        seeds: btm_wire_seeds,
        load: load_btm_wire,
    },
];

/// The loader called `name`.
pub fn loader(name: &str) -> Option<&'static Loader> {
    LOADERS.iter().find(|l| l.name == name)
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Files of `../shared/maps/DIR` (beside the workspace) by name; missing ones are skipped, so
/// the harness still runs on the other seeds and on random bytes.
fn shared(dir: &str, names: &[&str]) -> Vec<Vec<u8>> {
    let base = workspace().join("../shared/maps").join(dir);
    names
        .iter()
        .filter_map(|n| std::fs::read(base.join(n)).ok())
        .collect()
}

fn text(s: &str) -> Vec<u8> {
    s.as_bytes().to_vec()
}

/// A per-thread scratch file for loaders that read a path.
fn scratch(ext: &str, bytes: &[u8]) -> Result<PathBuf, String> {
    let path = std::env::temp_dir().join(format!(
        "usar-fuzz-{}-{:?}.{ext}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::write(&path, bytes).map_err(|e| e.to_string())?;
    Ok(path)
}

fn utf8(bytes: &[u8]) -> Result<&str, String> {
    std::str::from_utf8(bytes).map_err(|e| e.to_string())
}

fn fuzz_path(ext: &str) -> PathBuf {
    PathBuf::from(format!("fuzz.{ext}"))
}

fn image_seeds() -> Vec<Vec<u8>> {
    let mut seeds = shared("ros", &["depot.pgm", "tb3_sandbox.pgm"]);
    seeds.extend(shared(
        "segmentation",
        &[
            "lab_intel.png",
            "training_intel.png",
            "lab_intel_original.png",
        ],
    ));
    seeds.push(text("P2\n3 2\n255\n0 254 205\n254 0 254\n"));
    seeds
}

fn load_image(bytes: &[u8]) -> Result<(), String> {
    use usar_world::io::image_map::{ImageMapOptions, decode_image, obstacle_layer};
    let image = decode_image(bytes, &fuzz_path("png")).map_err(|e| e.to_string())?;
    obstacle_layer(&image, &ImageMapOptions::default());
    Ok(())
}

fn ros_yaml_seeds() -> Vec<Vec<u8>> {
    let mut seeds = shared("ros", &["depot.yaml", "tb3_sandbox.yaml", "warehouse.yaml"]);
    seeds.push(text(
        "image: m.pgm\nmode: scale\nresolution: 0.05\norigin: [-10, -10, 3.14]\nnegate: 1\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n",
    ));
    seeds
}

fn load_ros_yaml(bytes: &[u8]) -> Result<(), String> {
    let meta = usar_world::io::ros::parse_ros_yaml(utf8(bytes)?, &fuzz_path("yaml"))
        .map_err(|e| e.to_string())?;
    // A valid header must also describe a grid that can be turned and built.
    let opts = meta.image_options();
    let image = b"P5\n3 2\n255\n\x00\xfe\xfe\xfe\xfe\xcd";
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let (pgm, yaml) = (dir.path().join("m.pgm"), dir.path().join("m.yaml"));
    std::fs::write(&pgm, image).map_err(|e| e.to_string())?;
    let text = format!(
        "image: m.pgm\nresolution: {:?}\norigin: [{:?}, {:?}, {:?}]\nnegate: {}\n\
         occupied_thresh: {:?}\nfree_thresh: {:?}\nmode: {}\n",
        opts.resolution_m,
        opts.origin.x,
        opts.origin.y,
        opts.yaw_rad,
        u8::from(opts.negate),
        opts.occupied_thresh,
        opts.free_thresh,
        meta.mode.as_str()
    );
    std::fs::write(&yaml, text).map_err(|e| e.to_string())?;
    usar_world::io::ros::read_ros_map(&yaml).map_err(|e| e.to_string())?;
    Ok(())
}

fn movingai_map_seeds() -> Vec<Vec<u8>> {
    shared("movingai", &["maze-32-32-2.map", "room-32-32-4.map"])
}

fn load_movingai_map(bytes: &[u8]) -> Result<(), String> {
    let map = usar_world::io::movingai::parse_movingai_map(utf8(bytes)?, &fuzz_path("map"))
        .map_err(|e| e.to_string())?;
    map.to_scene("fuzz", 1.0).map_err(|e| e.to_string())?;
    Ok(())
}

fn movingai_scen_seeds() -> Vec<Vec<u8>> {
    shared(
        "movingai",
        &["maze-32-32-2-random-1.scen", "room-32-32-4-random-1.scen"],
    )
}

fn load_movingai_scen(bytes: &[u8]) -> Result<(), String> {
    usar_world::io::movingai::parse_scenarios(utf8(bytes)?, &fuzz_path("scen"))
        .map_err(|e| e.to_string())?;
    Ok(())
}

fn scene_json_seeds() -> Vec<Vec<u8>> {
    use usar_world::generate::{RubbleParams, generate_rubble};
    let scene = generate_rubble(1, &RubbleParams::default());
    vec![text(&usar_world::scene::scene_to_json(&scene))]
}

fn load_scene_json(bytes: &[u8]) -> Result<(), String> {
    let scene = usar_world::scene::scene_from_json(utf8(bytes)?, &fuzz_path("json"))
        .map_err(|e| e.to_string())?;
    // What every command does next with a scene.
    scene.info();
    Ok(())
}

fn robot_toml_seeds() -> Vec<Vec<u8>> {
    vec![
        text("preset = \"wheeled\"\nwidth_m = 0.7\n[laser]\nbeams = 180\nfov_rad = 3.14\n"),
        text(
            "preset = \"crawler\"\nmax_step_m = 0.2\n[depth]\nrows = 8\ncols = 8\n\
             [noise]\nattitude_sd_rad = 0.01\n[infrared]\ndirections_rad = [0.0, 1.57]\n",
        ),
    ]
}

fn load_robot_toml(bytes: &[u8]) -> Result<(), String> {
    usar_sim::RobotSpec::from_toml(utf8(bytes)?, &fuzz_path("toml")).map_err(|e| e.to_string())?;
    Ok(())
}

fn mission_toml_seeds() -> Vec<Vec<u8>> {
    // A mission file of `usar mission run`, as the console reads it.
    vec![text(
        "scene = \"office\"\nminutes = 5\n[team]\nrobots = 4\nrobot = \"wheeled\"\n\
         strategy = \"s-mcdm\"\nhypothesis = \"big\"\n[crawler]\nshare_period_s = 10.0\n\
         [rescuer]\ntrain_trials = 300\nzone_cells = 10\n[operator]\n",
    )]
}

fn load_mission_toml(bytes: &[u8]) -> Result<(), String> {
    let path = scratch("toml", bytes)?;
    let result = usar_console::MissionConfig::from_file(&path).map_err(|e| e.to_string());
    let _ = std::fs::remove_file(&path);
    result.map(|_| ())
}

fn campaign_toml_seeds() -> Vec<Vec<u8>> {
    // Campaigns of the engine's own `noop` runner (the presets name runners of the binary).
    vec![
        text(
            "name = \"fuzz\"\nrunner = \"noop\"\nruns = 3\nbase_seed = 1\n[factors]\na = [1, 2]\n\
             b = [\"x\", \"y\"]\n[report]\nrows = \"a\"\ncolumns = \"b\"\n",
        ),
        text(
            "# a comment\nname = \"fuzz-2\"\ndescription = \"d\"\nrunner = \"noop\"\nruns = 10\n\
             [factors]\nb = [\"x\", \"y\", \"z\"]\n[fixed]\na = 7\n[report]\nrows = \"b\"\n\
             metrics = [\"value\"]\nseries = [\"value\"]\n[[report.compare]]\nmetric = \"value\"\n\
             factor = \"b\"\ntest = \"welch\"\ngroups = [\"x\", \"y\"]\ntails = \"greater\"\n",
        ),
    ]
}

fn load_campaign_toml(bytes: &[u8]) -> Result<(), String> {
    use usar_campaign::{Design, NoopRunner, Runner, design::runner_named};
    static NOOP: NoopRunner = NoopRunner;
    let text = utf8(bytes)?;
    let runner = runner_named(text, "fuzz.toml", |_| Some(&NOOP as &'static dyn Runner))
        .map_err(|e| e.to_string())?;
    Design::parse(text, "fuzz.toml", runner).map_err(|e| e.to_string())?;
    Ok(())
}

fn policy_json_seeds() -> Vec<Vec<u8>> {
    use usar_rescue::policy::{PolicyFile, TrainingInfo};
    use usar_rescue::training::{TrainConfig, train};
    let mut config = TrainConfig {
        trials: 2,
        flat: false,
        ..TrainConfig::default()
    };
    config.params.max_steps_per_episode = 200;
    let (learner, _) = train(&config, |_| {});
    let file = PolicyFile::new(learner, TrainingInfo { seed: 1, trials: 2 });
    vec![serde_json::to_vec(&file).expect("a policy serialises")]
}

fn load_policy_json(bytes: &[u8]) -> Result<(), String> {
    let path = scratch("json", bytes)?;
    let result = usar_rescue::policy::PolicyFile::load(&path).map_err(|e| e.to_string());
    let _ = std::fs::remove_file(&path);
    result.map(|_| ())
}

/// A small map with every kind of record: a start, a junction, a dead end, a slope with an
/// extension attribute, searched and un-searched links.
fn sample_btm() -> usar_btm::Btm {
    use usar_btm::model::{kind, subtype};
    use usar_btm::{Btm, Link, Node};
    let mut start = Node::new(1, 0.0, 0.0, kind::TERMINAL, Some(subtype::START));
    start.operator_note = Some("dust".into());
    let mut slope = Node::new(4, 9.0, 0.0, kind::OBSTACLE, Some(subtype::SLOPE));
    slope.slope_inclination_rad = Some(0.35);
    slope.extra.insert("surface".into(), "gravel".into());
    let link = |id, from, to, len| Link {
        searched: true,
        end: Some(to),
        length_m: Some(len),
        min_width_m: Some(1.2),
        max_inclination_rad: Some(0.02),
        ..Link::unsearched(id, from, 0.0)
    };
    Btm {
        nodes: vec![
            start,
            Node::new(2, 5.0, 0.0, kind::DIVERGENCE, Some(subtype::T_JUNCTION)),
            Node::new(3, 5.0, 4.0, kind::DIVERGENCE, Some(subtype::DEAD_END)),
            slope,
        ],
        links: vec![
            link(1, 1, 2, 5.0),
            link(2, 2, 3, 4.0),
            link(3, 2, 4, 4.0),
            Link::unsearched(4, 2, -1.57),
        ],
    }
}

fn btm_sqlite_seeds() -> Vec<Vec<u8>> {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("seed.sqlite");
    let mut store = usar_btm::BtmStore::create(&path).expect("a new BTM database");
    store.put_all(&sample_btm()).expect("the sample is valid");
    drop(store);
    vec![std::fs::read(&path).expect("the database was written")]
}

fn load_btm_sqlite(bytes: &[u8]) -> Result<(), String> {
    let path = scratch("sqlite", bytes)?;
    let result = usar_btm::BtmStore::open(&path)
        .and_then(|s| s.load())
        .map_err(|e| e.to_string());
    for suffix in ["", "-journal", "-wal", "-shm"] {
        let _ = std::fs::remove_file(format!("{}{suffix}", path.display()));
    }
    result.map(|_| ())
}

fn btm_json_seeds() -> Vec<Vec<u8>> {
    vec![text(&usar_btm::exchange::to_json(&sample_btm()))]
}

fn load_btm_json(bytes: &[u8]) -> Result<(), String> {
    let btm =
        usar_btm::exchange::from_json(utf8(bytes)?, "fuzz.json").map_err(|e| e.to_string())?;
    // A map that loaded must survive what commands do with it.
    usar_btm::wire::decode(&usar_btm::wire::encode(&btm)).map_err(|e| e.to_string())?;
    Ok(())
}

fn btm_wire_seeds() -> Vec<Vec<u8>> {
    vec![usar_btm::wire::encode(&sample_btm())]
}

fn load_btm_wire(bytes: &[u8]) -> Result<(), String> {
    let btm = usar_btm::wire::decode(bytes).map_err(|e| e.to_string())?;
    usar_btm::exchange::from_json(&usar_btm::exchange::to_json(&btm), "round trip")
        .map_err(|e| e.to_string())?;
    Ok(())
}

//! Autonomous BTM generation on the paper-004 test course (Fig. 15): every junction, dead end
//! and corner found, the hall's free-space pair, slope and stairs measured, nothing left
//! un-searched; five seeds agree; a wheeled robot builds the crawler's map except where it
//! cannot go.

use std::collections::BTreeSet;
use std::sync::{Arc, OnceLock};
use usar_btm::build::{BuildConfig, BuildError, BuildOutcome, IMPASSABLE_FOR, StopReason};
use usar_btm::model::{kind, subtype};
use usar_btm::{Btm, BtmStore, Node, build_btm};
use usar_sim::RobotSpec;
use usar_world::generate::{SceneKind, generate};
use usar_world::{JunctionKind, Point2, Rect, Scene, TerrainFeature};

const SEEDS: [u64; 5] = [1, 2, 3, 4, 5];

fn course() -> Arc<Scene> {
    static SCENE: OnceLock<Arc<Scene>> = OnceLock::new();
    SCENE
        .get_or_init(|| Arc::new(generate(SceneKind::Course, 1)))
        .clone()
}

fn run(robot: RobotSpec, seed: u64) -> BuildOutcome {
    build_btm(course(), robot, &BuildConfig::default(), seed, None).expect("build")
}

/// The crawler with five seeds (built in parallel, once for all tests).
fn crawler_runs() -> &'static Vec<BuildOutcome> {
    static RUNS: OnceLock<Vec<BuildOutcome>> = OnceLock::new();
    RUNS.get_or_init(|| {
        std::thread::scope(|s| {
            let handles: Vec<_> = SEEDS
                .iter()
                .map(|&seed| s.spawn(move || run(RobotSpec::crawler(), seed)))
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("run"))
                .collect()
        })
    })
}

fn wheeled_run() -> &'static BuildOutcome {
    static RUN: OnceLock<BuildOutcome> = OnceLock::new();
    RUN.get_or_init(|| run(RobotSpec::wheeled(), 1))
}

fn at(n: &Node) -> Point2 {
    Point2::new(n.x_m, n.y_m)
}

fn is(n: &Node, k: &str, s: &str) -> bool {
    n.kind == k && n.subtype.as_deref() == Some(s)
}

fn rect_distance(r: &Rect, p: Point2) -> f64 {
    let dx = (r.min.x - p.x).max(p.x - r.max.x).max(0.0);
    let dy = (r.min.y - p.y).max(p.y - r.max.y).max(0.0);
    dx.hypot(dy)
}

fn junction_subtype(k: JunctionKind) -> &'static str {
    match k {
        JunctionKind::DeadEnd => subtype::DEAD_END,
        JunctionKind::Corner => subtype::CORNER,
        JunctionKind::TJunction => subtype::T_JUNCTION,
        JunctionKind::Crossing => subtype::CROSSING,
    }
}

/// Distance from each ground-truth junction to the nearest divergence node of its kind.
fn junction_errors(btm: &Btm) -> Vec<(JunctionKind, Point2, f64)> {
    course()
        .ground_truth
        .junctions
        .iter()
        .map(|j| {
            let d = btm
                .nodes
                .iter()
                .filter(|n| is(n, kind::DIVERGENCE, junction_subtype(j.kind)))
                .map(|n| at(n).distance(j.position))
                .fold(f64::INFINITY, f64::min);
            (j.kind, j.position, d)
        })
        .collect()
}

#[test]
fn the_crawler_finds_every_junction_dead_end_and_corner_within_1_m() {
    let out = &crawler_runs()[0];
    let errors = junction_errors(&out.btm);
    assert_eq!(errors.len(), 9);
    for (k, p, d) in &errors {
        assert!(
            *d < 1.0,
            "{k:?} at ({:.1}, {:.1}): nearest node {d:.2} m away",
            p.x,
            p.y
        );
    }
    // No divergence node where the truth has none.
    let divergences = out
        .btm
        .nodes
        .iter()
        .filter(|n| n.kind == kind::DIVERGENCE)
        .count();
    assert_eq!(divergences, errors.len(), "{:?}", out.nodes_by_type);
}

fn features() -> &'static [TerrainFeature] {
    static F: OnceLock<Vec<TerrainFeature>> = OnceLock::new();
    F.get_or_init(|| course().ground_truth.features.clone())
}

#[test]
fn the_hall_has_its_entrance_and_exit_free_space_nodes() {
    let out = &crawler_runs()[0];
    let hall = features()
        .iter()
        .find_map(|f| match f {
            TerrainFeature::Hall { region } => Some(*region),
            _ => None,
        })
        .expect("the course has a hall");
    for end in [subtype::ENTRANCE, subtype::EXIT] {
        let nodes: Vec<&Node> = out
            .btm
            .nodes
            .iter()
            .filter(|n| is(n, kind::FREE_SPACE, end))
            .collect();
        assert_eq!(nodes.len(), 1, "{end}: {:?}", out.nodes_by_type);
        let d = rect_distance(&hall, at(nodes[0]));
        assert!(d < 1.0, "{end} node {d:.2} m from the hall");
    }
}

#[test]
fn slope_and_stairs_have_obstacle_nodes_of_their_shape_measured_within_20_percent() {
    let out = &crawler_runs()[0];
    let near = |region: &Rect, s: &str| -> Vec<&Node> {
        out.btm
            .nodes
            .iter()
            .filter(|n| is(n, kind::OBSTACLE, s) && rect_distance(region, at(n)) < 1.0)
            .collect()
    };
    let mut checked = 0;
    for f in features() {
        match f {
            TerrainFeature::Slope {
                region,
                inclination_rad,
                ..
            } => {
                let nodes = near(region, subtype::SLOPE);
                assert_eq!(nodes.len(), 1, "slope at {region:?}: {nodes:?}");
                let measured = nodes[0].slope_inclination_rad.expect("inclination");
                let error = (measured - inclination_rad).abs() / inclination_rad;
                assert!(error < 0.2, "slope {measured} vs {inclination_rad}");
                let body = nodes[0].max_robot_inclination_rad.expect("max inclination");
                assert!(
                    body > 0.8 * inclination_rad && body < 1.3 * inclination_rad,
                    "{body}"
                );
                checked += 1;
            }
            TerrainFeature::Stairs {
                region,
                step_height_m,
                ..
            } => {
                let nodes = near(region, subtype::STAIRS);
                assert_eq!(nodes.len(), 1, "stairs at {region:?}: {nodes:?}");
                let measured = nodes[0].step_height_m.expect("step height");
                let error = (measured - step_height_m).abs() / step_height_m;
                assert!(error < 0.2, "step {measured} vs {step_height_m}");
                checked += 1;
            }
            _ => {}
        }
    }
    assert_eq!(checked, 3);
    assert_eq!(out.nodes_by_type.get("obstacle/slope"), Some(&2));
    assert_eq!(out.nodes_by_type.get("obstacle/stairs"), Some(&1));
}

#[test]
fn no_unsearched_link_is_left_and_every_link_was_measured() {
    for out in crawler_runs().iter().chain([wheeled_run()]) {
        assert_eq!(out.stop, StopReason::Explored);
        assert_eq!(out.unsearched_links, 0);
        assert_eq!(out.btm.unsearched().count(), 0);
        assert_eq!(out.nodes_by_type.get("terminal/start"), Some(&1));
        assert_eq!(out.nodes_by_type.get("terminal/end"), Some(&1));
        for l in &out.btm.links {
            let end = l.end.expect("searched links end at a node");
            assert!(out.btm.node(end).is_some() && out.btm.node(l.start).is_some());
            assert!(l.length_m.is_some() && l.min_width_m.is_some());
            assert!(l.max_inclination_rad.is_some());
        }
    }
    // The narrowest passage is 1.6 m ± 10 %; every link between divergence nodes saw it.
    let out = &crawler_runs()[0];
    for l in &out.btm.links {
        let kinds = [l.start, l.end.unwrap()].map(|id| out.btm.node(id).unwrap().kind.clone());
        if kinds.iter().all(|k| k == kind::DIVERGENCE) {
            let w = l.min_width_m.unwrap();
            assert!((1.3..2.0).contains(&w), "link {}: width {w}", l.id);
        }
    }
}

/// A node's place in a reference map: the nearest node of the same kind and subtype.
fn counterpart(reference: &Btm, n: &Node) -> Option<(u32, f64)> {
    reference
        .nodes
        .iter()
        .filter(|r| r.kind == n.kind && r.subtype == n.subtype)
        .map(|r| (r.id, at(r).distance(at(n))))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Links as unordered pairs of reference node ids, for the nodes `keep` accepts.
fn link_pairs(btm: &Btm, reference: &Btm, keep: impl Fn(&Node) -> bool) -> BTreeSet<(u32, u32)> {
    let map = |id: u32| {
        btm.node(id)
            .filter(|n| keep(n))
            .and_then(|n| counterpart(reference, n))
            .map(|c| c.0)
    };
    btm.links
        .iter()
        .filter_map(|l| {
            let (a, b) = (map(l.start)?, map(l.end?)?);
            Some((a.min(b), a.max(b)))
        })
        .collect()
}

#[test]
fn five_seeds_give_the_same_topology_with_nodes_within_half_a_metre() {
    let runs = crawler_runs();
    let reference = &runs[0].btm;
    for (seed, out) in SEEDS.iter().zip(runs).skip(1) {
        assert_eq!(out.nodes_by_type, runs[0].nodes_by_type, "seed {seed}");
        assert_eq!(out.btm.links.len(), reference.links.len(), "seed {seed}");
        let mut matched = BTreeSet::new();
        for n in &out.btm.nodes {
            let (id, d) = counterpart(reference, n).expect("same kinds");
            assert!(
                d < 0.5,
                "seed {seed}: {} {:?} {d:.2} m from seed 1's",
                n.kind,
                n.subtype
            );
            matched.insert(id);
        }
        assert_eq!(
            matched.len(),
            reference.nodes.len(),
            "seed {seed}: one-to-one"
        );
        assert_eq!(
            link_pairs(&out.btm, reference, |_| true),
            link_pairs(reference, reference, |_| true),
            "seed {seed}"
        );
    }
}

/// Whether a node lies where only a robot that climbs the slope or the stairs goes: on them
/// or within a metre, or beyond the stairs (their platform).
fn around_slope_or_stairs(p: Point2) -> bool {
    let width = course().geometry().width as f64 * course().geometry().resolution_m;
    features().iter().any(|f| match f {
        TerrainFeature::Slope { region, .. } => rect_distance(region, p) < 1.0,
        TerrainFeature::Stairs { region, .. } => {
            let beyond = Rect::new(region.min.x, region.min.y, width, region.max.y);
            rect_distance(&beyond, p) < 1.0
        }
        _ => false,
    })
}

#[test]
fn the_wheeled_robot_builds_the_crawlers_btm_except_around_slope_and_stairs() {
    let crawler = &crawler_runs()[0].btm;
    let wheeled = &wheeled_run().btm;
    let common = |n: &Node| {
        n.kind != kind::OBSTACLE
            && !is(n, kind::TERMINAL, subtype::END)
            && !around_slope_or_stairs(at(n))
    };
    let kinds = |b: &Btm| -> Vec<(String, Option<String>)> {
        let mut v: Vec<_> = b
            .nodes
            .iter()
            .filter(|n| common(n))
            .map(|n| (n.kind.clone(), n.subtype.clone()))
            .collect();
        v.sort();
        v
    };
    assert_eq!(kinds(wheeled), kinds(crawler));
    for n in wheeled.nodes.iter().filter(|n| common(n)) {
        let (_, d) = counterpart(crawler, n).expect("a counterpart");
        assert!(
            d < 1.0,
            "{} {:?} {d:.2} m from the crawler's",
            n.kind,
            n.subtype
        );
    }
    assert_eq!(
        link_pairs(wheeled, crawler, common),
        link_pairs(crawler, crawler, common)
    );
    // It met the slope from both sides and the stairs, and could cross none of them.
    let obstacles: Vec<&Node> = wheeled
        .nodes
        .iter()
        .filter(|n| n.kind == kind::OBSTACLE)
        .collect();
    assert_eq!(obstacles.len(), 3, "{obstacles:?}");
    for n in obstacles {
        assert_eq!(n.extra.get(IMPASSABLE_FOR), Some(&"wheeled".into()));
        assert!(around_slope_or_stairs(at(n)));
    }
}

#[test]
fn a_build_is_deterministic_and_its_store_holds_the_final_map() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("course.btm.sqlite");
    let store = BtmStore::create(&path).unwrap();
    let out = build_btm(
        course(),
        RobotSpec::crawler(),
        &BuildConfig::default(),
        1,
        Some(&store),
    )
    .unwrap();
    assert_eq!(out.btm, crawler_runs()[0].btm, "same seed, same map");
    assert_eq!(out.trajectory, crawler_runs()[0].trajectory);
    drop(store);
    let reopened = BtmStore::open(&path).unwrap();
    assert_eq!(reopened.load().unwrap(), out.btm);
}

#[test]
fn a_scene_without_start_pose_or_a_bad_config_is_an_error() {
    let mut scene = (*course()).clone();
    scene.start_poses.clear();
    let err = build_btm(
        Arc::new(scene),
        RobotSpec::crawler(),
        &BuildConfig::default(),
        1,
        None,
    )
    .unwrap_err();
    assert!(matches!(err, BuildError::NoStartPose { .. }), "{err}");
    let config = BuildConfig {
        band_near_m: 5.0,
        ..BuildConfig::default()
    };
    let err = build_btm(course(), RobotSpec::crawler(), &config, 1, None).unwrap_err();
    assert!(err.to_string().contains("band_near_m"), "{err}");
    let mut robot = RobotSpec::crawler();
    robot.width_m = -1.0;
    let err = build_btm(course(), robot, &BuildConfig::default(), 1, None).unwrap_err();
    assert!(matches!(err, BuildError::Placement { .. }), "{err}");
}

/// The builder decides from its robot's readings only: replacing the layers a robot cannot
/// sense — room ids and labels, doors, the victim list, the junctions and terrain features a
/// test checks against — with garbage changes nothing it builds or drives.
#[test]
fn garbage_in_what_the_robot_cannot_sense_changes_nothing_the_builder_does() {
    let clean = &crawler_runs()[0];
    let mut spoiled = (*course()).clone();
    let (w, h) = spoiled.geometry().extent_m();
    for (k, id) in spoiled.room_id.as_mut_slice().iter_mut().enumerate() {
        *id = (k % 7) as u16;
    }
    spoiled.rooms.clear();
    spoiled.doors.clear();
    spoiled.victims = (0..4)
        .map(|id| usar_world::Victim {
            id,
            position: Point2::new(w * 0.2 * f64::from(id + 1), h / 2.0),
            heat_c: 34.0,
            visible_size_m2: 0.4,
            buried_fraction: 0.0,
        })
        .collect();
    spoiled.ground_truth.junctions = (0..5)
        .map(|k| usar_world::Junction {
            kind: JunctionKind::Crossing,
            position: Point2::new(w * 0.15 * f64::from(k), h * 0.3),
        })
        .collect();
    spoiled.ground_truth.features.clear();
    let out = build_btm(
        Arc::new(spoiled),
        RobotSpec::crawler(),
        &BuildConfig::default(),
        SEEDS[0],
        None,
    )
    .expect("build");
    assert_eq!(out.btm, clean.btm);
    assert_eq!(out.trajectory, clean.trajectory);
}

use std::sync::Arc;
use usar_btm::{BuildConfig, build_btm};
use usar_sim::RobotSpec;
use usar_world::generate::{SceneKind, generate};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let robot = if args.get(1).map(String::as_str) == Some("wheeled") {
        RobotSpec::wheeled()
    } else {
        RobotSpec::crawler()
    };
    let seed: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let mut cfg = BuildConfig::default();
    if let Some(t) = args.get(3).and_then(|s| s.parse().ok()) {
        cfg.max_time_s = t;
    }
    if args.get(4).map(String::as_str) == Some("noicp") {
        cfg.scan_matching = false;
    }
    let scene = Arc::new(generate(SceneKind::Course, 1));
    for j in &scene.ground_truth.junctions {
        println!("truth {:?} {:.2} {:.2}", j.kind, j.position.x, j.position.y);
    }
    for f in &scene.ground_truth.features {
        println!("feature {f:?}");
    }
    let t0 = std::time::Instant::now();
    let out = build_btm(scene, robot, &cfg, seed, None).unwrap();
    println!("wall {:?}", t0.elapsed());
    println!("stop {:?} time {:.1} dist {:.1} coll {} icp {} rej {}", out.stop, out.time_s, out.distance_m, out.collisions, out.scan_matches, out.scan_match_rejections);
    for n in &out.btm.nodes {
        println!(
            "node {} {} {:?} ({:.2},{:.2}) incl {:?} step {:?} maxinc {:?} {:?}",
            n.id, n.kind, n.subtype, n.x_m, n.y_m,
            n.slope_inclination_rad.map(f64::to_degrees), n.step_height_m,
            n.max_robot_inclination_rad.map(f64::to_degrees), n.extra
        );
    }
    for l in &out.btm.links {
        println!(
            "link {} {}->{:?} s={} dir={:.0} len={:?} w={:?} inc={:?}",
            l.id, l.start, l.end, l.searched, l.direction_rad.to_degrees(), l.length_m.map(|v| (v*100.0).round()/100.0),
            l.min_width_m.map(|v| (v*100.0).round()/100.0), l.max_inclination_rad.map(|v| v.to_degrees().round())
        );
    }
    let mut err_max: f64 = 0.0;
    let mut last_mode = None;
    for (i, s) in out.trajectory.iter().enumerate() {
        let e = s.estimated.position().distance(s.truth.position());
        err_max = err_max.max(e);
        if last_mode != Some(s.mode) || i % 20 == 0 {
            println!("t {:.1} {:?} est ({:.2},{:.2},{:.0}) true ({:.2},{:.2}) dth {:.2} err {:.2}", s.time_s, s.mode, s.estimated.x, s.estimated.y, s.estimated.theta.to_degrees(), s.truth.x, s.truth.y, usar_world::normalize_angle(s.estimated.theta - s.truth.theta).to_degrees(), e);
            last_mode = Some(s.mode);
        }
    }
    println!("max loc err {err_max:.2}");
}

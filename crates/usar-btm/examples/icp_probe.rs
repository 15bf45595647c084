use std::sync::Arc;
use usar_btm::build::localization::Localizer;
use usar_btm::build::scan::ScanView;
use usar_sim::{RobotSpec, SimConfig, Simulation, Velocity, sensors::LaserScan};
use usar_world::generate::{SceneKind, generate};

fn main() {
    let scene = Arc::new(generate(SceneKind::Course, 1));
    let start = scene.start_poses[0];
    let mut sim = Simulation::new(scene, SimConfig::default(), 3);
    let id = sim.add_robot(RobotSpec::crawler(), start).unwrap();
    let w: f64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let v: f64 = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let mut loc = Localizer::new(start, sim.robot(id).odometry.estimate, true, 1.0, 3.14);
    let mut raw = LaserScan::default();
    for k in 0..400 {
        sim.step(&[Velocity { linear_mps: v, angular_radps: w }]);
        sim.scan_laser(id, &mut raw);
        let view = ScanView::from_scan(&raw);
        loc.predict(sim.robot(id).odometry.estimate);
        loc.correct(&view, false);
        if k % 40 == 0 {
            let t = sim.robot(id).pose;
            let e = loc.pose();
            let o = sim.robot(id).odometry.estimate;
            println!("{k} dth_icp {:.3} dth_odo {:.3} pos_err {:.3}", usar_world::normalize_angle(e.theta - t.theta).to_degrees(), usar_world::normalize_angle(o.theta - t.theta).to_degrees(), e.position().distance(t.position()));
        }
    }
}

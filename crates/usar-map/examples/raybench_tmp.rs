use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use usar_map::{OccupancyGrid, OccupancyParams};
use usar_sim::sensors::{LaserModel, LaserScan, LaserSpec, SensingWorld};
use usar_world::{Cell, Pose2};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(2000, |a| a.parse().unwrap());
    let mode = args.get(2).cloned().unwrap_or_default();
    let scene = usar_world::generate::generate(usar_world::generate::SceneKind::Office, 1);
    let g = *scene.geometry();
    let world = SensingWorld::new(&scene);
    let laser = LaserModel::new(LaserSpec::default());
    let mut rng = Pcg64Mcg::seed_from_u64(3);
    let mut poses = Vec::new();
    // A random walk through free cells (nearby poses, like a robot's).
    let mut c = scene.start_poses[0].position();
    while poses.len() < n {
        let step = usar_world::Point2::new(c.x + rng.random_range(-0.5..0.5), c.y + rng.random_range(-0.5..0.5));
        let cell: Cell = g.world_to_cell(step);
        if g.contains(cell) && !scene.is_obstacle(cell) {
            c = step;
            poses.push(Pose2::new(c.x, c.y, rng.random_range(-3.1..3.1)));
        }
    }
    let mut grid = OccupancyGrid::new(g, OccupancyParams::default());
    let mut scan = LaserScan::default();
    let mut scans = Vec::new();
    for &p in &poses {
        laser.scan_into(&world, p, 0.0, &mut rng, &mut scan);
        scans.push(scan.clone());
    }
    let t = std::time::Instant::now();
    let mut sum = 0.0f64;
    if mode != "integrate" {
        for &p in &poses {
            laser.scan_into(&world, p, 0.0, &mut rng, &mut scan);
            sum += scan.ranges_m.iter().filter(|r| r.is_finite()).map(|&r| r as f64).sum::<f64>();
        }
    }
    let t_cast = t.elapsed();
    let t = std::time::Instant::now();
    if mode != "cast" {
        for s in &scans {
            grid.integrate_scan(s);
        }
    }
    let t_int = t.elapsed();
    let checksum: i64 = grid.logodds().iter().map(|&l| l as i64).sum();
    println!("{sum:.3} {checksum} cast {:?} integrate {:?}", t_cast, t_int);
}

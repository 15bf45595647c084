use proptest::prelude::*;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use usar_map::{CellClass, FrontierTracker, OccupancyGrid, OccupancyParams};
use usar_sim::sensors::{LaserModel, LaserSpec, SensingWorld};
use usar_world::{Cell, GridGeometry, Point2, Pose2, Scene, obstacle};

proptest! {
    /// Frontier clusters only contain free cells next to unknown ones, every frontier cell is in
    /// exactly one cluster, and the incremental frontier equals a full recomputation.
    #[test]
    fn frontier_clusters_only_contain_free_cells_next_to_unknown(
        walls in proptest::collection::vec((0i32..60, 0i32..60), 0..300),
        poses in proptest::collection::vec((0.2f64..5.8, 0.2f64..5.8, -3.2f64..3.2), 1..4),
        seed in 0u64..1000,
    ) {
        let g = GridGeometry::new(60, 60, 0.1, Point2::new(0.0, 0.0));
        let mut scene = Scene::empty("random", g);
        for (c, r) in walls {
            scene.obstacle[Cell::new(c, r)] = obstacle::WALL;
        }
        let world = SensingWorld::new(&scene);
        let laser = LaserModel::new(LaserSpec { max_range_m: 2.0, beams: 90, ..LaserSpec::default() });
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let mut grid = OccupancyGrid::new(g, OccupancyParams::default());
        let mut tracker = FrontierTracker::new(&grid);
        for (x, y, th) in poses {
            if scene.is_obstacle(g.world_to_cell(Point2::new(x, y))) {
                continue;
            }
            grid.integrate_scan(&laser.scan(&world, Pose2::new(x, y, th), 0.0, &mut rng));
            tracker.update(&mut grid);
        }
        prop_assert_eq!(tracker.sorted_indices(), FrontierTracker::new(&grid).sorted_indices());
        let clusters = tracker.clusters(&grid, 1);
        let mut seen = 0;
        for cluster in &clusters {
            for &cell in &cluster.cells {
                prop_assert_eq!(grid.class(cell), CellClass::Free);
                let next_to_unknown = [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|&(dc, dr)| {
                    let n = Cell::new(cell.col + dc, cell.row + dr);
                    g.contains(n) && grid.class(n) == CellClass::Unknown
                });
                prop_assert!(next_to_unknown, "{:?} has no unknown neighbour", cell);
            }
            prop_assert!(cluster.cells.contains(&cluster.candidate));
            seen += cluster.len();
        }
        prop_assert_eq!(seen, tracker.len());
    }
}

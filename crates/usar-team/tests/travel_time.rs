//! Memoised b(p, r) equals the time priced on each path on its own.

use usar_map::planning::{Connectivity, DistanceField, NavGrid};
use usar_team::travel_time::{TravelTimes, grid_travel_time_s};
use usar_world::{Cell, GridGeometry, Point2};

#[test]
fn memoised_travel_times_equal_the_per_path_times_bit_for_bit() {
    let g = GridGeometry::new(60, 45, 0.4, Point2::new(0.0, 0.0));
    // Walls with gaps, so that paths bend.
    let grid = NavGrid::from_fn(g, |c| {
        (c.col % 12 == 6 && c.row % 15 != 3) || (c.row % 11 == 5 && c.col % 17 != 9)
    });
    let spec = usar_sim::RobotSpec::wheeled();
    let mut field = DistanceField::new();
    let mut times = TravelTimes::new();
    for (source, theta) in [(Cell::new(1, 1), 0.3), (Cell::new(40, 30), -2.5)] {
        field.compute(&grid, &[source], Connectivity::Eight);
        times.reset(&field, theta);
        let mut priced = 0;
        // Goals in an order where later descents run into memoised cells.
        for k in 0..g.len() {
            let c = g.cell_of_index((k * 7919) % g.len());
            let expected = field.path_to_source(c).map(|p| {
                let length_m = p.length_cells * g.resolution_m;
                grid_travel_time_s(&p.cells, length_m, theta, &spec)
            });
            let length_m = field.distance_m(c).unwrap_or(0.0);
            let got = times.time_s(&field, c, length_m, &spec);
            assert_eq!(got.map(f64::to_bits), expected.map(f64::to_bits), "{c:?}");
            priced += usize::from(got.is_some());
        }
        assert!(priced > g.len() / 2);
        assert_eq!(times.time_s(&field, source, 0.0, &spec), Some(0.0));
    }
}

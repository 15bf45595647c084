//! Grid planners: golden tests against the MovingAI optimal lengths, property tests of A*,
//! the distance field and inflation on random small grids (checked against independent
//! references), the synthetic building floor, and the scenario checker's error paths.

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use usar_map::planning::bench_grid::{corner_cells, synthetic_building, synthetic_building_walls};
use usar_map::planning::{
    Connectivity, DIAGONAL_COST, DistanceField, GridAStar, GridAlgorithm, GridPath, NavGrid,
    check_scenario_sample, check_scenarios, graph_astar, inflate,
};
use usar_world::{Cell, Grid, GridGeometry, Point2};

fn movingai_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/maps/movingai")
}

fn assert_all_match(file: &str, stride: usize, expected_count: usize) {
    let report = check_scenario_sample(&movingai_dir().join(file), stride).unwrap();
    assert_eq!(report.scenarios, expected_count, "{file}");
    assert_eq!(
        report.matched, report.scenarios,
        "{file}: {:?}",
        report.mismatches
    );
    assert!(report.mismatches.is_empty());
    assert!(report.total_expanded > 0);
}

// ---------------------------------------------------------------------------------------------
// Golden tests: every scenario of the small files and of the room maps, and every 20th of the
// 9730 long maze512 scenarios (the whole file takes minutes at opt-level 1).

#[test]
fn astar_matches_movingai_optima_on_maze_32() {
    let report = check_scenarios(&movingai_dir().join("maze-32-32-2-random-1.scen")).unwrap();
    assert_eq!(
        (report.scenarios, report.matched),
        (333, 333),
        "{:?}",
        report.mismatches
    );
    // These files print 8 decimals: A* agrees to rounding.
    assert!(report.max_abs_error < 1e-6, "{}", report.max_abs_error);
}

#[test]
fn astar_matches_movingai_optima_on_room_32() {
    let report = check_scenarios(&movingai_dir().join("room-32-32-4-random-1.scen")).unwrap();
    assert_eq!(
        (report.scenarios, report.matched),
        (341, 341),
        "{:?}",
        report.mismatches
    );
    assert!(report.max_abs_error < 1e-6, "{}", report.max_abs_error);
}

#[test]
fn astar_matches_movingai_optima_on_16room() {
    assert_all_match("16room_000.map.scen", 1, 1860);
}

#[test]
fn astar_matches_movingai_optima_on_8room() {
    assert_all_match("8room_000.map.scen", 1, 1940);
}

#[test]
fn astar_matches_movingai_optima_on_every_20th_maze512_scenario() {
    // Indices 0, 20, …, 9720: all buckets, from short to the longest paths.
    assert_all_match("maze512-4-0.map.scen", 20, 487);
}

#[test]
fn open_list_never_falls_back_on_the_room_and_maze_maps() {
    // Every step of f on these maps is one of the reduced-cost classes of the open list.
    use usar_world::io::movingai::{read_movingai_map, read_scenarios};
    for (map, scen) in [
        ("8room_000.map", "8room_000.map.scen"),
        ("maze512-4-0.map", "maze512-4-0.map.scen"),
    ] {
        let map = read_movingai_map(movingai_dir().join(map)).unwrap();
        let grid = NavGrid::from_passable(&map.passable);
        let mut astar = GridAStar::new();
        for s in read_scenarios(movingai_dir().join(scen))
            .unwrap()
            .iter()
            .step_by(97)
        {
            for connectivity in BOTH {
                let start = map.cell_of(s.start.0, s.start.1);
                let goal = map.cell_of(s.goal.0, s.goal.1);
                let plain = astar.plan_with(&grid, start, goal, connectivity, GridAlgorithm::AStar);
                assert!(plain.is_some());
                assert_eq!(astar.fallback_pushes(), 0);
            }
        }
    }
}

#[test]
fn scenario_report_serializes_to_json() {
    let report =
        check_scenario_sample(&movingai_dir().join("maze-32-32-2-random-1.scen"), 50).unwrap();
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["scenarios"], 7);
    assert_eq!(json["matched"], 7);
    assert!(json["mismatches"].as_array().unwrap().is_empty());
    assert!(json["max_abs_error"].as_f64().unwrap() < 1e-6);
}

#[test]
fn wrong_optimal_lengths_are_reported_as_mismatches() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("tiny.map"),
        "type octile\nheight 2\nwidth 3\nmap\n...\n.@.\n",
    )
    .unwrap();
    // MovingAI (0,1) → (2,1) round the pillar at (1,1), over the top row without cutting its
    // corners: (0,1)→(0,0)→(1,0)→(2,0)→(2,1) = 4.
    std::fs::write(
        dir.join("tiny.scen"),
        "version 1\n0\ttiny.map\t3\t2\t0\t1\t2\t1\t4\n0\ttiny.map\t3\t2\t0\t1\t2\t1\t3.5\n\
         0\ttiny.map\t3\t2\t0\t1\t1\t1\t1\n",
    )
    .unwrap();
    let report = check_scenarios(&dir.join("tiny.scen")).unwrap();
    assert_eq!((report.scenarios, report.matched), (3, 1));
    assert_eq!(report.mismatches.len(), 2);
    assert_eq!(report.mismatches[0].index, 1);
    assert_eq!(report.mismatches[0].found, Some(4.0));
    assert_eq!(report.mismatches[0].expected, 3.5);
    // The goal of the third is the pillar: no path.
    assert_eq!(report.mismatches[1].index, 2);
    assert_eq!(report.mismatches[1].found, None);
    // 3.5 printed with one decimal stands for [3.45, 3.55): 4 lies 0.45 beyond it.
    assert!((report.max_abs_error - 0.45).abs() < 1e-12);
    assert_eq!(report.max_raw_error, 0.5);
}

#[test]
fn lengths_are_compared_at_the_printed_precision() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("line.map"),
        "type octile\nheight 1\nwidth 5\nmap\n.....\n",
    )
    .unwrap();
    // The path is exactly 4. "4.004" (three decimals) stands for [4.0035, 4.0045): 3.5e-3 off,
    // a mismatch; "4.00" and "4" are exact, and "3.9996" is within the 1e-3 tolerance.
    std::fs::write(
        dir.join("line.scen"),
        "version 1\n0\tline.map\t5\t1\t0\t0\t4\t0\t4.004\n0\tline.map\t5\t1\t0\t0\t4\t0\t4.00\n\
         0\tline.map\t5\t1\t0\t0\t4\t0\t4\n0\tline.map\t5\t1\t0\t0\t4\t0\t3.9996\n",
    )
    .unwrap();
    let report = check_scenarios(&dir.join("line.scen")).unwrap();
    assert_eq!((report.scenarios, report.matched), (4, 3));
    assert_eq!(report.mismatches[0].index, 0);
    assert!((report.max_abs_error - 3.5e-3).abs() < 1e-9);
}

#[test]
fn missing_map_referenced_by_a_scenario_is_an_error_naming_it_and_the_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("a.scen"),
        "version 1\n0\tmaps/nothere.map\t3\t2\t0\t1\t2\t1\t4\n",
    )
    .unwrap();
    let err = check_scenarios(&dir.join("a.scen"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("nothere.map") && err.contains("line 2"),
        "{err}"
    );
    assert!(err.contains("a.scen"), "{err}");
}

#[test]
fn scenario_map_found_by_scen_file_stem() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("real.map"),
        "type octile\nheight 1\nwidth 3\nmap\n...\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("real.map.scen"),
        "version 1\n0\tother/name.map\t3\t1\t0\t0\t2\t0\t2\n",
    )
    .unwrap();
    let report = check_scenarios(&dir.join("real.map.scen")).unwrap();
    assert_eq!((report.scenarios, report.matched), (1, 1));
}

#[test]
fn scenario_for_a_map_of_another_size_is_rejected() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("m.map"),
        "type octile\nheight 1\nwidth 3\nmap\n...\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.scen"),
        "version 1\n0\tm.map\t4\t1\t0\t0\t2\t0\t2\n",
    )
    .unwrap();
    let err = check_scenarios(&dir.join("m.scen"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("line 2") && err.contains("4x1") && err.contains("3x1"),
        "{err}"
    );
}

// ---------------------------------------------------------------------------------------------
// Path checks shared by the property tests.

fn step_cost(a: Cell, b: Cell) -> f64 {
    if a.col != b.col && a.row != b.row {
        DIAGONAL_COST
    } else {
        1.0
    }
}

/// Contiguous, inside free cells, no corner cutting, length = sum of its steps.
fn assert_valid_path(grid: &NavGrid, path: &GridPath, connectivity: Connectivity) {
    assert!(!path.cells.is_empty());
    let mut length = 0.0;
    for c in &path.cells {
        assert!(grid.is_passable(*c), "path enters blocked {c:?}");
    }
    for w in path.cells.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dc, dr) = (b.col - a.col, b.row - a.row);
        match connectivity {
            Connectivity::Four => assert_eq!(dc.abs() + dr.abs(), 1, "{a:?} → {b:?}"),
            Connectivity::Eight => {
                assert_eq!(a.chebyshev(b), 1, "{a:?} → {b:?}");
                if dc != 0 && dr != 0 {
                    assert!(
                        grid.is_passable(Cell::new(a.col + dc, a.row)),
                        "cuts a corner"
                    );
                    assert!(
                        grid.is_passable(Cell::new(a.col, a.row + dr)),
                        "cuts a corner"
                    );
                }
            }
        }
        length += step_cost(a, b);
    }
    assert!(
        (length - path.length_cells).abs() < 1e-9,
        "{length} vs {}",
        path.length_cells
    );
}

/// Reference: the `pathfinding` crate's Dijkstra on the same moves (independent code).
fn reference_distance(
    grid: &NavGrid,
    from: Cell,
    to: Cell,
    connectivity: Connectivity,
) -> Option<f64> {
    if !grid.is_passable(from) || !grid.is_passable(to) {
        return None;
    }
    let successors = |c: &Cell| -> Vec<(Cell, f64)> {
        let mut out = Vec::new();
        for (dc, dr) in usar_world::NEIGHBORS8 {
            let n = Cell::new(c.col + dc, c.row + dr);
            let diagonal = dc != 0 && dr != 0;
            if diagonal && connectivity == Connectivity::Four {
                continue;
            }
            if !grid.is_passable(n) {
                continue;
            }
            if diagonal
                && !(grid.is_passable(Cell::new(c.col + dc, c.row))
                    && grid.is_passable(Cell::new(c.col, c.row + dr)))
            {
                continue;
            }
            out.push((n, if diagonal { DIAGONAL_COST } else { 1.0 }));
        }
        out
    };
    graph_astar(&from, successors, |_| 0.0, |c| *c == to).map(|(_, cost)| cost)
}

/// Reference: a textbook Dijkstra with a binary heap over every cell, 8-connected, no corner
/// cutting, from several sources (independent of the planners' bucket queues). Distances by
/// [`GridGeometry::index`], `INFINITY` where unreachable.
fn reference_field(grid: &NavGrid, sources: &[Cell]) -> Vec<f64> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let g = *grid.geometry();
    let mut dist = vec![f64::INFINITY; g.len()];
    // Keys as the exact bit patterns of non-negative f64 (ordered like the values).
    let mut heap = BinaryHeap::new();
    for &s in sources {
        if grid.is_passable(s) {
            dist[g.index(s)] = 0.0;
            heap.push(Reverse((0u64, s.col, s.row)));
        }
    }
    while let Some(Reverse((bits, col, row))) = heap.pop() {
        let d = f64::from_bits(bits);
        let c = Cell::new(col, row);
        if d > dist[g.index(c)] {
            continue;
        }
        for (dc, dr) in usar_world::NEIGHBORS8 {
            let n = Cell::new(col + dc, row + dr);
            let diagonal = dc != 0 && dr != 0;
            if !grid.is_passable(n)
                || (diagonal
                    && !(grid.is_passable(Cell::new(col + dc, row))
                        && grid.is_passable(Cell::new(col, row + dr))))
            {
                continue;
            }
            let nd = d + if diagonal { DIAGONAL_COST } else { 1.0 };
            let slot = &mut dist[g.index(n)];
            if nd < *slot {
                *slot = nd;
                heap.push(Reverse((nd.to_bits(), n.col, n.row)));
            }
        }
    }
    dist
}

fn grid_strategy() -> impl Strategy<Value = (NavGrid, Cell, Cell)> {
    (1u32..14, 1u32..14, 0.0f64..0.45).prop_flat_map(|(w, h, density)| {
        let cells = (w * h) as usize;
        (
            proptest::collection::vec(proptest::bool::weighted(density), cells),
            0..w as i32,
            0..h as i32,
            0..w as i32,
            0..h as i32,
        )
            .prop_map(move |(blocked, c0, r0, c1, r1)| {
                let g = GridGeometry::new(w, h, 0.1, Point2::new(0.0, 0.0));
                let grid = NavGrid::from_blocked(&Grid::from_vec(g, blocked).unwrap());
                (grid, Cell::new(c0, r0), Cell::new(c1, r1))
            })
    })
}

const BOTH: [Connectivity; 2] = [Connectivity::Four, Connectivity::Eight];

/// Larger random grids for jump point search: rooms-like blocks and scattered cells, with a
/// density from open floor to nearly closed, and start and goal anywhere.
fn jump_grid_strategy() -> impl Strategy<Value = (NavGrid, Cell, Cell)> {
    (1u32..100, 1u32..70, 0.0f64..0.5, 0usize..6).prop_flat_map(|(w, h, density, walls)| {
        let cells = (w * h) as usize;
        (
            proptest::collection::vec(proptest::bool::weighted(density), cells),
            proptest::collection::vec((0..w as i32, 0..h as i32, any::<bool>(), 1i32..80), walls),
            0..w as i32,
            0..h as i32,
            0..w as i32,
            0..h as i32,
        )
            .prop_map(move |(blocked, walls, c0, r0, c1, r1)| {
                let g = GridGeometry::new(w, h, 0.1, Point2::new(0.0, 0.0));
                let mut grid = NavGrid::from_blocked(&Grid::from_vec(g, blocked).unwrap());
                // Straight walls make corridors and rooms, where jumps are long.
                for (c, r, horizontal, len) in walls {
                    for k in 0..len {
                        let cell = if horizontal {
                            Cell::new(c + k, r)
                        } else {
                            Cell::new(c, r + k)
                        };
                        grid.set_passable(cell, false);
                    }
                }
                (grid, Cell::new(c0, r0), Cell::new(c1, r1))
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn astar_paths_are_valid_and_optimal((grid, start, goal) in grid_strategy()) {
        let mut astar = GridAStar::new();
        for connectivity in BOTH {
            let planned =
                astar.plan_with(&grid, start, goal, connectivity, GridAlgorithm::AStar);
            let reference = reference_distance(&grid, start, goal, connectivity);
            prop_assert_eq!(planned.is_some(), reference.is_some());
            if let (Some(path), Some(best)) = (planned, reference) {
                assert_valid_path(&grid, &path, connectivity);
                prop_assert_eq!(path.cells.first(), Some(&start));
                prop_assert_eq!(path.cells.last(), Some(&goal));
                prop_assert!((path.length_cells - best).abs() < 1e-9, "{} vs {}", path.length_cells, best);
                prop_assert!(astar.expanded() >= path.cells.len());
            }
            // The open list's step classes cover every move (no fallback to the heap).
            prop_assert_eq!(astar.fallback_pushes(), 0);
        }
    }

    #[test]
    fn jump_point_search_lengths_equal_plain_astar_and_paths_are_valid(
        (grid, start, goal) in jump_grid_strategy(),
    ) {
        let mut jps = GridAStar::new();
        let mut plain = GridAStar::new();
        let expected =
            plain.plan_with(&grid, start, goal, Connectivity::Eight, GridAlgorithm::AStar);
        let planned =
            jps.plan_with(&grid, start, goal, Connectivity::Eight, GridAlgorithm::JumpPoint);
        prop_assert_eq!(planned.is_some(), expected.is_some());
        if let (Some(path), Some(best)) = (planned, expected) {
            // Every cell listed, none blocked, no corner cut, length the sum of its steps.
            assert_valid_path(&grid, &path, Connectivity::Eight);
            prop_assert_eq!(path.cells.first(), Some(&start));
            prop_assert_eq!(path.cells.last(), Some(&goal));
            prop_assert!(
                (path.length_cells - best.length_cells).abs() < 1e-9,
                "JPS {} vs A* {}", path.length_cells, best.length_cells
            );
            let independent = reference_field(&grid, &[start])[grid.geometry().index(goal)];
            prop_assert!((path.length_cells - independent).abs() < 1e-9);
            // `plan` runs jump point search for 8-connected planning.
            prop_assert_eq!(jps.plan(&grid, start, goal, Connectivity::Eight), Some(path));
        }
    }

    #[test]
    fn eight_connected_field_equals_an_independent_dijkstra_on_larger_grids(
        (grid, a, b) in jump_grid_strategy(),
    ) {
        let g = *grid.geometry();
        let sources = [a, b];
        let reference = reference_field(&grid, &sources);
        let mut field = DistanceField::new();
        field.compute(&grid, &sources, Connectivity::Eight);
        let mut reachable = 0;
        for row in 0..g.height as i32 {
            for col in 0..g.width as i32 {
                let cell = Cell::new(col, row);
                let expected = reference[g.index(cell)];
                let d = field.distance_cells(cell);
                prop_assert_eq!(d.is_some(), expected.is_finite(), "{:?}", cell);
                if let Some(d) = d {
                    reachable += 1;
                    prop_assert!((d - expected).abs() < 1e-9, "{:?}: {} vs {}", cell, d, expected);
                }
            }
        }
        prop_assert_eq!(field.reached_count(), reachable);
        // The descent from the farthest cell reaches a source along a valid shortest path.
        let far = field
            .to_grid()
            .iter_cells()
            .filter(|(_, d)| d.is_finite())
            .max_by(|x, y| x.1.total_cmp(y.1))
            .map(|(c, _)| c);
        if let Some(far) = far {
            let path = field.path_to_source(far).unwrap();
            assert_valid_path(&grid, &path, Connectivity::Eight);
            prop_assert!(sources.contains(path.cells.last().unwrap()));
        }
    }

    /// Stopping once the targets are settled changes neither their distances nor the paths
    /// back from them, and the search does stop early when the targets are near.
    #[test]
    fn a_field_stopped_once_its_targets_are_settled_agrees_on_them(
        (grid, a, b) in jump_grid_strategy(),
        picks in proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0), 0..6),
    ) {
        let g = *grid.geometry();
        let targets: Vec<Cell> = picks
            .iter()
            .map(|&(x, y)| Cell::new((x * g.width as f64) as i32, (y * g.height as f64) as i32))
            .collect();
        let mut full = DistanceField::new();
        full.compute(&grid, &[a], Connectivity::Eight);
        let mut early = DistanceField::new();
        early.compute_until_settled(&grid, &[a], Connectivity::Eight, &targets);
        for &t in targets.iter().chain([&b]) {
            let settled = targets.contains(&t)
                || full.distance_cells(t).is_some_and(|d| {
                    targets
                        .iter()
                        .any(|&x| full.distance_cells(x).is_some_and(|dx| d < dx.floor()))
                });
            if settled {
                prop_assert_eq!(early.distance_cells(t), full.distance_cells(t), "{:?}", t);
                prop_assert_eq!(early.path_to_source(t), full.path_to_source(t));
            }
        }
        if !targets.is_empty() && targets.iter().all(|&t| full.distance_cells(t).is_some()) {
            prop_assert!(early.reached_count() <= full.reached_count());
        }
        if targets.is_empty() {
            prop_assert_eq!(early.reached_count(), full.reached_count());
        }
    }

    #[test]
    fn astar_agrees_with_the_distance_field((grid, start, goal) in grid_strategy()) {
        let mut astar = GridAStar::new();
        let mut field = DistanceField::new();
        for connectivity in BOTH {
            field.compute(&grid, &[goal], connectivity);
            let planned = astar.plan(&grid, start, goal, connectivity);
            // A* finds no path exactly when the field says unreachable.
            prop_assert_eq!(planned.is_some(), field.distance_cells(start).is_some());
            if let Some(path) = planned {
                let d = field.distance_cells(start).unwrap();
                match connectivity {
                    Connectivity::Four => prop_assert_eq!(d, path.length_cells),
                    // Exact up to the order in which the same steps are summed.
                    Connectivity::Eight => prop_assert!((d - path.length_cells).abs() < 1e-9),
                }
            }
        }
    }

    #[test]
    fn distance_field_is_exact_and_its_paths_are_valid((grid, start, _goal) in grid_strategy()) {
        let mut field = DistanceField::new();
        let g = *grid.geometry();
        for connectivity in BOTH {
            field.compute(&grid, &[start], connectivity);
            for row in 0..g.height as i32 {
                for col in 0..g.width as i32 {
                    let cell = Cell::new(col, row);
                    let reference = reference_distance(&grid, cell, start, connectivity);
                    let d = field.distance_cells(cell);
                    prop_assert_eq!(d.is_some(), reference.is_some(), "{:?}", cell);
                    if let (Some(d), Some(r)) = (d, reference) {
                        prop_assert!((d - r).abs() < 1e-9, "{:?}: {} vs {}", cell, d, r);
                        let path = field.path_to_source(cell).unwrap();
                        assert_valid_path(&grid, &path, connectivity);
                        prop_assert_eq!(path.cells.first(), Some(&cell));
                        prop_assert_eq!(path.cells.last(), Some(&start));
                        prop_assert_eq!(path.length_cells, d);
                        prop_assert_eq!(field.nearest_source(cell), Some(start));
                    } else {
                        prop_assert!(field.path_to_source(cell).is_none());
                        prop_assert!(field.to_grid()[cell].is_infinite());
                    }
                }
            }
        }
    }

    #[test]
    fn multi_source_field_is_the_minimum_of_single_source_fields(
        (grid, a, b) in grid_strategy(),
    ) {
        let g = *grid.geometry();
        let c = Cell::new(g.width as i32 / 2, g.height as i32 / 2);
        let sources = [a, b, c];
        let mut field = DistanceField::new();
        let mut single = DistanceField::new();
        for connectivity in BOTH {
            field.compute(&grid, &sources, connectivity);
            let mut expected: Vec<Cell> = Vec::new();
            for s in sources {
                if grid.is_passable(s) && !expected.contains(&s) {
                    expected.push(s);
                }
            }
            prop_assert_eq!(field.sources(), &expected[..]);
            let singles: Vec<(Cell, Grid<f64>)> = expected
                .iter()
                .map(|&s| {
                    single.compute(&grid, &[s], connectivity);
                    (s, single.to_grid())
                })
                .collect();
            for (cell, &d) in field.to_grid().iter_cells() {
                let best = singles.iter().map(|(_, f)| f[cell]).fold(f64::INFINITY, f64::min);
                prop_assert_eq!(d.is_finite(), best.is_finite());
                prop_assert_eq!(field.distance_cells(cell).is_some(), d.is_finite());
                if d.is_finite() {
                    prop_assert!((d - best).abs() < 1e-9);
                    let nearest = field.nearest_source(cell).unwrap();
                    let from_nearest = &singles.iter().find(|(s, _)| *s == nearest).unwrap().1;
                    prop_assert!((from_nearest[cell] - d).abs() < 1e-9);
                    let path = field.path_to_source(cell).unwrap();
                    prop_assert_eq!(path.cells.last(), Some(&nearest));
                }
            }
        }
    }

    #[test]
    fn inflation_blocks_exactly_the_cells_within_the_radius(
        w in 1u32..16,
        h in 1u32..16,
        blocked in proptest::collection::vec(proptest::bool::weighted(0.12), 225),
        radius_cells in 0.0f64..4.5,
    ) {
        let resolution = 0.1;
        let g = GridGeometry::new(w, h, resolution, Point2::new(0.0, 0.0));
        let original = Grid::from_vec(g, blocked[..(w * h) as usize].to_vec()).unwrap();
        let radius_m = radius_cells * resolution;
        let inflated = inflate(&original, radius_m);
        let obstacles: Vec<Cell> =
            original.iter_cells().filter(|(_, b)| **b).map(|(c, _)| c).collect();
        for (cell, &b) in inflated.iter_cells() {
            // Brute force over every original obstacle, in metres between centres.
            let near = obstacles.iter().any(|o| {
                g.cell_center(*o).distance(g.cell_center(cell)) <= radius_m + 1e-9
            });
            prop_assert_eq!(b, near || original[cell], "{:?}", cell);
            if original[cell] {
                prop_assert!(b);
            }
        }
    }
}

#[test]
fn a_field_with_near_targets_stops_early_and_one_with_an_unreachable_target_does_not() {
    let g = GridGeometry::new(60, 60, 0.1, Point2::new(0.0, 0.0));
    // A wall closes off the column 50 and beyond.
    let grid = NavGrid::from_fn(g, |c| c.col == 50);
    let mut field = DistanceField::new();
    field.compute_until_settled(
        &grid,
        &[Cell::new(5, 5)],
        Connectivity::Eight,
        &[Cell::new(8, 9)],
    );
    let d = field.distance_cells(Cell::new(8, 9)).unwrap();
    assert!((d - (1.0 + 3.0 * DIAGONAL_COST)).abs() < 1e-12, "{d}");
    assert!(field.reached_count() < 200, "{}", field.reached_count());
    field.compute_until_settled(
        &grid,
        &[Cell::new(5, 5)],
        Connectivity::Eight,
        &[Cell::new(8, 9), Cell::new(55, 5)],
    );
    assert_eq!(field.reached_count(), 50 * 60);
    assert_eq!(field.distance_cells(Cell::new(55, 5)), None);
}

#[test]
fn inflation_radius_on_the_grid_spacing_includes_cells_at_exactly_that_distance() {
    let g = GridGeometry::new(9, 9, 0.1, Point2::new(0.0, 0.0));
    let mut blocked = Grid::filled(g, false);
    blocked[Cell::new(4, 4)] = true;
    let out = inflate(&blocked, 0.3);
    assert!(out[Cell::new(7, 4)] && out[Cell::new(4, 1)]);
    assert!(!out[Cell::new(8, 4)]);
    // 0.2·√2 ≈ 0.283 ≤ 0.3 < √(0.3² + 0.1²)
    assert!(out[Cell::new(6, 6)] && !out[Cell::new(7, 5)]);
}

#[test]
fn planner_reuse_over_many_searches_and_sizes_gives_fresh_results() {
    // More searches than the 16-bit search stamp can number (it wraps at 32 766).
    let small = NavGrid::from_fn(GridGeometry::new(4, 3, 1.0, Point2::new(0.0, 0.0)), |c| {
        c == Cell::new(1, 1) || c == Cell::new(2, 1)
    });
    let large = NavGrid::from_fn(GridGeometry::new(40, 30, 1.0, Point2::new(0.0, 0.0)), |c| {
        c.col == 20 && c.row < 25
    });
    let mut reused = GridAStar::new();
    let expected_small = GridAStar::new().plan(
        &small,
        Cell::new(0, 1),
        Cell::new(3, 1),
        Connectivity::Eight,
    );
    let expected_large = GridAStar::new().plan(
        &large,
        Cell::new(0, 0),
        Cell::new(39, 0),
        Connectivity::Four,
    );
    // Round the two-cell wall; every diagonal would cut one of its corners.
    assert_eq!(expected_small.as_ref().map(|p| p.length_cells), Some(5.0));
    assert_eq!(
        expected_large.as_ref().map(|p| p.length_cells),
        Some(39.0 + 50.0)
    );
    for i in 0..70_000 {
        if i % 1000 == 0 {
            let p = reused.plan(
                &large,
                Cell::new(0, 0),
                Cell::new(39, 0),
                Connectivity::Four,
            );
            assert_eq!(p, expected_large, "search {i}");
        }
        let p = reused.plan(
            &small,
            Cell::new(0, 1),
            Cell::new(3, 1),
            Connectivity::Eight,
        );
        assert_eq!(p, expected_small, "search {i}");
    }
}

#[test]
fn blocked_or_outside_endpoints_give_no_path() {
    let grid = NavGrid::from_fn(GridGeometry::new(5, 5, 1.0, Point2::new(0.0, 0.0)), |c| {
        c == Cell::new(2, 2)
    });
    let mut astar = GridAStar::new();
    for connectivity in BOTH {
        assert!(
            astar
                .plan(&grid, Cell::new(2, 2), Cell::new(0, 0), connectivity)
                .is_none()
        );
        assert!(
            astar
                .plan(&grid, Cell::new(0, 0), Cell::new(2, 2), connectivity)
                .is_none()
        );
        assert!(
            astar
                .plan(&grid, Cell::new(-1, 0), Cell::new(0, 0), connectivity)
                .is_none()
        );
        assert!(
            astar
                .plan(&grid, Cell::new(0, 0), Cell::new(0, 5), connectivity)
                .is_none()
        );
        assert_eq!(astar.expanded(), 0);
    }
    let mut field = DistanceField::new();
    field.compute(
        &grid,
        &[Cell::new(2, 2), Cell::new(9, 9)],
        Connectivity::Eight,
    );
    assert!(field.sources().is_empty());
    assert_eq!(field.reached_count(), 0);
    assert_eq!(field.distance_cells(Cell::new(0, 0)), None);
}

/// A goal in a walled pocket is found unreachable without a search, whichever end is in the
/// pocket, also when the pocket's wall is open at a corner (no corner cutting); two parts both
/// larger than the floods' bound are still found unreachable, by the search.
#[test]
fn unreachable_goals_are_answered_without_searching_the_start_s_whole_part() {
    let g = GridGeometry::new(120, 120, 1.0, Point2::new(0.0, 0.0));
    let ring = |c: Cell, lo: i32, hi: i32| {
        (lo..=hi).contains(&c.col)
            && (lo..=hi).contains(&c.row)
            && (c.col == lo || c.col == hi || c.row == lo || c.row == hi)
    };
    // A closed pocket inside (9..=13)², and one inside (20..=24)² whose corner (24, 24) is open.
    let grid = NavGrid::from_fn(g, |c| {
        ring(c, 9, 13) || (ring(c, 20, 24) && c != Cell::new(24, 24))
    });
    let mut astar = GridAStar::new();
    for connectivity in BOTH {
        for (a, b) in [
            (Cell::new(100, 100), Cell::new(11, 11)),
            (Cell::new(11, 11), Cell::new(100, 100)),
            (Cell::new(100, 100), Cell::new(22, 22)),
        ] {
            assert_eq!(astar.plan(&grid, a, b, connectivity), None);
            assert_eq!(astar.expanded(), 0, "{a:?} → {b:?}");
        }
        let path = astar
            .plan(&grid, Cell::new(100, 100), Cell::new(24, 24), connectivity)
            .expect("the open corner is outside the pocket");
        assert_valid_path(&grid, &path, connectivity);
    }
    // Two halves of 60 × 120 cells, split by a wall with diagonal gaps only.
    let halves = NavGrid::from_fn(g, |c| {
        (c.col == 60 && c.row % 2 == 0) || (c.col == 61 && c.row % 2 == 1)
    });
    for connectivity in BOTH {
        assert_eq!(
            astar.plan(&halves, Cell::new(0, 0), Cell::new(119, 119), connectivity),
            None
        );
        assert!(astar.expanded() > 0, "the search ran");
    }
}

#[test]
fn tie_breaking_toward_larger_g_walks_straight_to_the_goal_on_an_open_floor() {
    let grid = NavGrid::from_fn(
        GridGeometry::new(200, 200, 0.1, Point2::new(0.0, 0.0)),
        |_| false,
    );
    let mut astar = GridAStar::new();
    let (a, b) = (Cell::new(0, 0), Cell::new(199, 150));
    let four = astar.plan(&grid, a, b, Connectivity::Four).unwrap();
    assert_eq!(four.length_cells, 349.0);
    // Every cell with f = 349 ties; preferring larger g expands only the path.
    assert_eq!(astar.expanded(), four.cells.len());
    let eight = astar
        .plan_with(&grid, a, b, Connectivity::Eight, GridAlgorithm::AStar)
        .unwrap();
    assert!((eight.length_cells - (49.0 + 150.0 * DIAGONAL_COST)).abs() < 1e-9);
    assert_eq!(astar.expanded(), eight.cells.len());
    assert!((four.length_m(0.1) - 34.9).abs() < 1e-9);
    // Jump point search: the start, the goal (found by the first diagonal scan's straight
    // jumps), nothing else.
    let jps = astar.plan(&grid, a, b, Connectivity::Eight).unwrap();
    assert!((jps.length_cells - eight.length_cells).abs() < 1e-9);
    assert_eq!(jps.cells.len(), eight.cells.len());
    assert_eq!(astar.expanded(), 2);
    assert!(astar.scanned() > 0);
}

#[test]
fn jump_point_search_sees_cells_changed_after_an_earlier_search() {
    // The packed bits of a grid are rebuilt after `set_passable`: a wall put across the first
    // path is walked around, and taking it away again restores the straight path.
    let g = GridGeometry::new(130, 40, 0.1, Point2::new(0.0, 0.0));
    let mut grid = NavGrid::from_fn(g, |_| false);
    let mut astar = GridAStar::new();
    let (a, b) = (Cell::new(2, 20), Cell::new(127, 20));
    let straight = astar.plan(&grid, a, b, Connectivity::Eight).unwrap();
    assert_eq!(straight.length_cells, 125.0);
    for row in 0..35 {
        grid.set_passable(Cell::new(70, row), false);
    }
    let around = astar.plan(&grid, a, b, Connectivity::Eight).unwrap();
    assert_valid_path(&grid, &around, Connectivity::Eight);
    let expected = astar
        .plan_with(&grid, a, b, Connectivity::Eight, GridAlgorithm::AStar)
        .unwrap();
    assert!((around.length_cells - expected.length_cells).abs() < 1e-9);
    assert!(around.length_cells > 135.0);
    for row in 0..35 {
        grid.set_passable(Cell::new(70, row), true);
    }
    assert_eq!(astar.plan(&grid, a, b, Connectivity::Eight), Some(straight));
}

#[test]
fn jump_point_search_and_plain_astar_agree_on_the_synthetic_building() {
    // Long corridors, doors and furniture over 64-cell words of the packed rows and columns.
    let blocked = synthetic_building(300, 260, 3);
    let grid = NavGrid::from_blocked(&blocked);
    let (start, goal) = corner_cells(&blocked).unwrap();
    let mut jps = GridAStar::new();
    let mut plain = GridAStar::new();
    let mut field = DistanceField::new();
    field.compute(&grid, &[start], Connectivity::Eight);
    let g = *grid.geometry();
    for k in 0..40 {
        // Goals spread over the floor (every passable cell is reachable from the start).
        let goal = if k == 0 {
            goal
        } else {
            Cell::new((k * 7919) % g.width as i32, (k * 104_729) % g.height as i32)
        };
        let expected = plain.plan_with(
            &grid,
            start,
            goal,
            Connectivity::Eight,
            GridAlgorithm::AStar,
        );
        let found = jps.plan(&grid, start, goal, Connectivity::Eight);
        assert_eq!(found.is_some(), expected.is_some(), "{goal:?}");
        if let (Some(p), Some(e)) = (found, expected) {
            assert_valid_path(&grid, &p, Connectivity::Eight);
            assert!((p.length_cells - e.length_cells).abs() < 1e-9, "{goal:?}");
            assert!((field.distance_cells(goal).unwrap() - p.length_cells).abs() < 1e-9);
            assert!(jps.expanded() < plain.expanded(), "{goal:?}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Synthetic building floor.

#[test]
fn synthetic_building_is_deterministic_connected_and_building_like() {
    let a = synthetic_building(600, 450, 7);
    assert_eq!(a, synthetic_building(600, 450, 7));
    assert_ne!(a, synthetic_building(600, 450, 8));
    assert_eq!(a, inflate(&synthetic_building_walls(600, 450, 7), 0.3));
    let blocked_share =
        a.as_slice().iter().filter(|&&b| b).count() as f64 / a.as_slice().len() as f64;
    assert!((0.1..0.45).contains(&blocked_share), "{blocked_share}");

    // One connected floor: every free cell is reachable from the lower-left corner.
    let grid = NavGrid::from_blocked(&a);
    let (start, goal) = corner_cells(&a).unwrap();
    assert!(
        start.col + start.row < 20 && goal.col + goal.row > 600 + 450 - 20,
        "{start:?} {goal:?}"
    );
    let mut field = DistanceField::new();
    field.compute(&grid, &[start], Connectivity::Four);
    assert_eq!(field.reached_count(), grid.passable_count());
    assert!(field.distance_cells(goal).is_some());
    // Walls and doors force detours: some cells are much farther than their Manhattan distance.
    let detours = field
        .to_grid()
        .iter_cells()
        .filter(|(c, d)| {
            d.is_finite() && **d > 1.5 * Connectivity::Four.heuristic(start, *c) + 10.0
        })
        .count();
    assert!(detours > 1000, "{detours}");
}

#[test]
fn synthetic_building_of_tiny_or_empty_size_does_not_panic() {
    for (w, h) in [(0, 0), (1, 1), (3, 50), (30, 30), (60, 2000)] {
        let grid = synthetic_building(w, h, 1);
        assert_eq!((grid.width(), grid.height()), (w, h));
    }
}

#[test]
fn no_path_says_whether_start_goal_or_the_passage_is_closed() {
    use usar_map::planning::{NavGrid, NoPath};
    // Three columns: free, wall, free.
    let mut blocked = Grid::filled(GridGeometry::new(3, 3, 1.0, Point2::new(0.0, 0.0)), false);
    for row in 0..3 {
        *blocked.get_mut(Cell::new(1, row)).expect("in grid") = true;
    }
    let grid = NavGrid::from_blocked(&blocked);
    let (a, wall, b) = (Cell::new(0, 0), Cell::new(1, 1), Cell::new(2, 2));
    assert_eq!(NoPath::explain(&grid, wall, b), NoPath::StartBlocked);
    assert_eq!(NoPath::explain(&grid, a, wall), NoPath::GoalBlocked);
    assert_eq!(NoPath::explain(&grid, a, b), NoPath::NotConnected);
}

//! The exploration guidance: local exploration (the eight cells around the robot, then cells
//! within d₁ moves) before D_E's target, and the first step of a shortest path that needs no
//! turn.

use usar_rescue::cell_map::{CellMap, MapCell};
use usar_rescue::exploration::{Direction, ExplorationWeights, Explorer};

/// A `size × size` map the robot has visited entirely except for `cells`.
fn map_with(size: i32, cells: &[((i32, i32), MapCell)]) -> CellMap {
    let mut map = CellMap::new(size, size);
    map.cells.fill(MapCell::OpenVisited);
    for &((c, r), cell) in cells {
        let i = map.index(c, r).expect("inside");
        map.cells[i] = cell;
    }
    map
}

fn heading(map: &CellMap, robot: (i32, i32), facing: Direction) -> Option<Direction> {
    let weights = ExplorationWeights::named("equal").expect("Table II case");
    let mut explorer = Explorer::new(weights, map);
    explorer.guide(map, robot.0, robot.1, facing, None).heading
}

#[test]
fn a_neighbour_of_interest_comes_before_the_exploration_target() {
    // Far open unvisited cells east pull D_E east; the unknown cell north of the robot is
    // faced first, by the one turn to the left.
    let far: Vec<_> = (0..7).map(|r| ((6, r), MapCell::OpenUnvisited)).collect();
    let mut cells = far.clone();
    cells.push(((3, 4), MapCell::Unknown));
    let map = map_with(7, &cells);
    assert_eq!(
        heading(&map, (3, 3), Direction::East),
        Some(Direction::North)
    );
    // Without it the heading goes toward the far cells.
    let map = map_with(7, &far);
    assert_eq!(
        heading(&map, (3, 3), Direction::North),
        Some(Direction::East)
    );
}

#[test]
fn a_cell_of_interest_within_d1_moves_comes_before_the_exploration_target() {
    // Open unvisited cells along the east edge pull D_E east (5 moves away). An unknown cell
    // faced from a cell 3 moves west (d₁ = 3 in simulation) is explored first; one faced from
    // 4 moves away is not.
    let far: Vec<_> = (0..11).map(|r| ((10, r), MapCell::OpenUnvisited)).collect();
    for (unknown, step) in [((1, 5), Direction::West), ((0, 5), Direction::East)] {
        let mut cells = far.clone();
        cells.push((unknown, MapCell::Unknown));
        let map = map_with(11, &cells);
        assert_eq!(
            heading(&map, (5, 5), Direction::East),
            Some(step),
            "unknown cell at {unknown:?}"
        );
    }
}

#[test]
fn a_diagonal_cell_of_interest_is_reached_through_a_free_neighbour() {
    // The unknown cell north-east of the robot is faced from the east or the north neighbour:
    // the one ahead when the robot faces east, the one on the right when it faces west.
    let mut cells: Vec<_> = (0..7).map(|c| ((c, 0), MapCell::OpenUnvisited)).collect();
    cells.push(((4, 4), MapCell::Unknown));
    let map = map_with(7, &cells);
    assert_eq!(
        heading(&map, (3, 3), Direction::East),
        Some(Direction::East)
    );
    assert_eq!(
        heading(&map, (3, 3), Direction::West),
        Some(Direction::North)
    );
}

#[test]
fn the_first_step_of_a_shortest_path_needs_no_turn() {
    // From (0, 0) to (4, 4) east and north both start a shortest path: the robot keeps its
    // axis, driving ahead or reversing.
    let map = map_with(5, &[((4, 4), MapCell::OpenUnvisited)]);
    for (facing, step) in [
        (Direction::North, Direction::North),
        (Direction::East, Direction::East),
        (Direction::West, Direction::East),
        (Direction::South, Direction::North),
    ] {
        assert_eq!(
            heading(&map, (0, 0), facing),
            Some(step),
            "facing {facing:?}"
        );
    }
}

//! Grid and graph planners: the [`NavGrid`] the planners read, [`inflate`] for the robot's
//! radius, [`GridAStar`] (4- or 8-connected, octile costs, no corner cutting; jump point search
//! for 8-connected plans), a generic [`graph_astar`] for graphs such as the BTM, the
//! multi-source [`DistanceField`], a checker of MovingAI scenarios, and a synthetic building
//! floor for speed measurements.
//!
//! Everything works on flat buffers with a one-cell blocked border and keeps its scratch memory
//! between calls, so that repeated searches on a grid of one size do not allocate.
//!
//! ```
//! use usar_map::planning::{Connectivity, DistanceField, GridAStar, NavGrid, inflate};
//! use usar_world::{Cell, Grid, GridGeometry, Point2};
//!
//! // A 4 m × 2 m room at 0.1 m with a pillar in the middle, inflated by a 0.2 m robot radius.
//! let geometry = GridGeometry::new(40, 20, 0.1, Point2::new(0.0, 0.0));
//! let mut blocked = Grid::filled(geometry, false);
//! blocked[Cell::new(20, 10)] = true;
//! let grid = NavGrid::from_blocked(&inflate(&blocked, 0.2));
//!
//! let mut astar = GridAStar::new();
//! let path = astar.plan(&grid, Cell::new(2, 10), Cell::new(37, 10), Connectivity::Eight).unwrap();
//! assert!(path.length_m(0.1) > 3.5);
//!
//! let mut field = DistanceField::new();
//! field.compute(&grid, &[Cell::new(37, 10)], Connectivity::Eight);
//! let d = field.distance_cells(Cell::new(2, 10)).unwrap();
//! assert!((d - path.length_cells).abs() < 1e-9);
//! ```

pub mod bench_grid;
mod bit_lines;
mod distance_field;
mod graph_astar;
mod grid_astar;
mod inflate;
mod jump_point;
mod nav_grid;
mod open_list;
pub mod scenarios;
mod separation;

pub use self::distance_field::DistanceField;
pub use self::graph_astar::{TotalCost, astar, astar_bag, graph_astar};
pub use self::grid_astar::{Connectivity, DIAGONAL_COST, GridAStar, GridAlgorithm, GridPath};
pub use self::inflate::inflate;
pub use self::nav_grid::{NavGrid, NoPath};
pub use self::scenarios::{Mismatch, ScenarioReport, check_scenario_sample, check_scenarios};

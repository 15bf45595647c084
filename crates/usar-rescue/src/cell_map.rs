//! The robot's own cell map (paper 000 §V, categories i–v): what the robot knows of every
//! coarse cell, built only from its sensors.

use serde::Serialize;

/// A cell of the robot's map (paper 000 §V).
///
/// Explored cells: [`MapCell::OpenVisited`], [`MapCell::NonClimbable`],
/// [`MapCell::ClimbableVisited`], [`MapCell::Victim`]. Unexplored cells — the *cells of
/// interest* of the exploration — are [`MapCell::Unknown`], [`MapCell::UnknownObstacle`],
/// [`MapCell::OpenUnvisited`] and [`MapCell::ClimbableUnvisited`]. Drops are non-climbable.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum MapCell {
    /// (v) no sensory information.
    #[default]
    Unknown,
    /// (i) an obstacle the infrared sensors detected but could not classify.
    UnknownObstacle,
    /// (iii) obstacle-free, not visited yet.
    OpenUnvisited,
    /// (ii) obstacle-free and visited.
    OpenVisited,
    /// (i) climbable rubble, not visited yet.
    ClimbableUnvisited,
    /// (i) climbable rubble the robot has crossed.
    ClimbableVisited,
    /// (i) non-climbable rubble or a drop.
    NonClimbable,
    /// (iv) a (possible) victim lies here: the robot never enters.
    Victim,
}

impl MapCell {
    /// Whether exploring this cell can add to the robot's knowledge (§V).
    pub fn is_of_interest(self) -> bool {
        matches!(
            self,
            MapCell::Unknown
                | MapCell::UnknownObstacle
                | MapCell::OpenUnvisited
                | MapCell::ClimbableUnvisited
        )
    }

    /// Whether the robot knows it may drive here.
    pub fn is_known_passable(self) -> bool {
        matches!(
            self,
            MapCell::OpenUnvisited
                | MapCell::OpenVisited
                | MapCell::ClimbableUnvisited
                | MapCell::ClimbableVisited
        )
    }

    pub fn is_visited(self) -> bool {
        matches!(self, MapCell::OpenVisited | MapCell::ClimbableVisited)
    }

    /// Whether the depth sensor has not classified the cell yet.
    pub fn is_unclassified(self) -> bool {
        matches!(self, MapCell::Unknown | MapCell::UnknownObstacle)
    }

    /// The cell once the robot has driven onto it.
    pub fn visited(self) -> MapCell {
        match self {
            MapCell::ClimbableUnvisited | MapCell::ClimbableVisited => MapCell::ClimbableVisited,
            _ => MapCell::OpenVisited,
        }
    }
}

/// The robot's map: `cols × rows` cells, row-major, row 0 south (the cell view's frame).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CellMap {
    pub cols: i32,
    pub rows: i32,
    pub cells: Vec<MapCell>,
}

impl CellMap {
    pub fn new(cols: i32, rows: i32) -> Self {
        Self {
            cols,
            rows,
            cells: vec![MapCell::Unknown; (cols * rows) as usize],
        }
    }

    #[inline]
    pub fn index(&self, col: i32, row: i32) -> Option<usize> {
        (col >= 0 && row >= 0 && col < self.cols && row < self.rows)
            .then(|| (row * self.cols + col) as usize)
    }

    /// (col, row) of cell index `i` (the inverse of [`CellMap::index`]).
    #[inline]
    pub fn col_row(&self, i: usize) -> (i32, i32) {
        (i as i32 % self.cols, i as i32 / self.cols)
    }

    /// The category of a cell; outside the arena everything is non-climbable (the boundary).
    #[inline]
    pub fn get(&self, col: i32, row: i32) -> MapCell {
        self.index(col, row)
            .map_or(MapCell::NonClimbable, |i| self.cells[i])
    }

    pub fn count(&self, category: MapCell) -> usize {
        self.cells.iter().filter(|&&c| c == category).count()
    }
}

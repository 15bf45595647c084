//! MovingAI grid benchmarks: `.map` grids and `.scen` scenario lists
//! (Sturtevant 2012, "Benchmarks for Grid-Based Pathfinding", <https://movingai.com/benchmarks/>).
//!
//! A `.map` file is a header — `type octile`, `height H`, `width W`, `map` — followed by `H` rows
//! of `W` characters. MovingAI's (0, 0) is the *upper-left* cell and `x` is the column; our grids
//! have row 0 at the bottom, so rows are flipped here, at the boundary, and nowhere else:
//! [`MovingAiMap::cell_of`] converts a MovingAI coordinate to our [`Cell`].
//!
//! Terrain characters: `.` and `G` are passable; `@`, `O` (out of bounds), `T` (trees), `S`
//! (swamp) and `W` (water) are treated as blocked — swamp and water are passable only for some
//! agents in the benchmark's definition, and the published optimal lengths treat them as blocked.
//!
//! A `.scen` file starts with `version 1` (or `version 1.0`) and lists one scenario per line,
//! tab-separated: bucket, map, map width, map height, start x, start y, goal x, goal y, optimal
//! length (straight moves cost 1, diagonal moves √2, no corner cutting).
//!
//! ```
//! use usar_world::io::movingai::parse_movingai_map;
//!
//! let map = parse_movingai_map("type octile\nheight 2\nwidth 3\nmap\n.@.\n...\n", "m.map".as_ref())
//!     .unwrap();
//! // MovingAI (1, 0) is the `@` on the top row, which is our row 1.
//! assert_eq!(map.cell_of(1, 0), usar_world::Cell::new(1, 1));
//! assert!(!map.passable[map.cell_of(1, 0)]);
//! ```

use crate::error::{Result, WorldError};
use crate::geometry::{Point2, Pose2};
use crate::grid::{Cell, Grid, GridGeometry, NEIGHBORS8};
use crate::scene::{Provenance, Scene, obstacle};
use std::path::Path;

/// Largest map side accepted, cells (published MovingAI maps are at most a few thousand).
pub const MAX_GRID_SIDE: u32 = 500_000;

/// A MovingAI map in our convention: row 0 is the bottom row of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingAiMap {
    /// Number of columns (`width` in the header).
    pub width: u32,
    /// Number of rows (`height` in the header).
    pub height: u32,
    /// True where an agent may stand. Its geometry has 1-unit cells with the origin at (0, 0):
    /// MovingAI maps have no physical scale (see [`MovingAiMap::to_scene`]).
    pub passable: Grid<bool>,
}

impl MovingAiMap {
    /// Our cell for the MovingAI coordinate (`x` column, `y` row counted from the top).
    ///
    /// The result lies outside the grid when `x >= width` or `y >= height`.
    pub fn cell_of(&self, x: u32, y: u32) -> Cell {
        Cell::new(x as i32, self.height as i32 - 1 - y as i32)
    }

    /// True if the MovingAI coordinate is inside the map and passable.
    pub fn is_passable_at(&self, x: u32, y: u32) -> bool {
        self.passable
            .get(self.cell_of(x, y))
            .copied()
            .unwrap_or(false)
    }

    /// The blocked mask (`true` = blocked), the form the planners take.
    pub fn blocked(&self) -> Grid<bool> {
        self.passable.map(|&p| !p)
    }

    /// A scene of the map with cells of `resolution_m` metres: blocked cells become
    /// [`obstacle::WALL`], the floor is flat, and there are no rooms or victims.
    ///
    /// One start pose (heading 0, east) is placed at the centre of the first cell, in our row-major
    /// order (bottom row first, then by column), of the largest 4-connected passable component;
    /// when two components are equally large the one whose first cell comes first wins. A map
    /// with no passable cell gets no start pose.
    ///
    /// Fails when `resolution_m` is not a positive finite number or `passable` does not have the
    /// map's size.
    pub fn to_scene(&self, name: impl Into<String>, resolution_m: f64) -> Result<Scene> {
        if !(resolution_m.is_finite() && resolution_m > 0.0) {
            return Err(WorldError::invalid(
                Path::new("<MovingAI map>"),
                "resolution_m",
                resolution_m,
                "a positive number of metres",
            ));
        }
        if self.passable.width() != self.width || self.passable.height() != self.height {
            return Err(WorldError::invalid(
                Path::new("<MovingAI map>"),
                "passable",
                format!("{}x{} cells", self.passable.width(), self.passable.height()),
                format!("{}x{} cells (width x height)", self.width, self.height),
            ));
        }
        let geometry =
            GridGeometry::new(self.width, self.height, resolution_m, Point2::new(0.0, 0.0));
        let name = name.into();
        let mut scene = Scene::empty(name.clone(), geometry);
        scene.provenance = Provenance {
            source: "import".into(),
            seed: None,
            detail: format!("MovingAI map {name} ({}x{})", self.width, self.height),
        };
        for (o, &p) in scene
            .obstacle
            .as_mut_slice()
            .iter_mut()
            .zip(self.passable.as_slice())
        {
            *o = if p { obstacle::NONE } else { obstacle::WALL };
        }
        if let Some(start) = first_cell_of_largest_component(&self.passable) {
            let c = geometry.cell_center(start);
            scene.start_poses.push(Pose2::new(c.x, c.y, 0.0));
        }
        Ok(scene)
    }
}

/// The first cell (row-major) of the largest 4-connected component of `true` cells.
fn first_cell_of_largest_component(passable: &Grid<bool>) -> Option<Cell> {
    let g = *passable.geometry();
    let mut seen = vec![false; g.len()];
    let mut stack = Vec::new();
    let mut best: Option<(usize, Cell)> = None;
    for (i, &p) in passable.as_slice().iter().enumerate() {
        if !p || seen[i] {
            continue;
        }
        let first = g.cell_of_index(i);
        seen[i] = true;
        stack.push(first);
        let mut size = 0usize;
        while let Some(c) = stack.pop() {
            size += 1;
            for &(dc, dr) in &NEIGHBORS8[..4] {
                let n = Cell::new(c.col + dc, c.row + dr);
                if let Some(j) = g.checked_index(n)
                    && passable.as_slice()[j]
                    && !seen[j]
                {
                    seen[j] = true;
                    stack.push(n);
                }
            }
        }
        if best.is_none_or(|(s, _)| size > s) {
            best = Some((size, first));
        }
    }
    best.map(|(_, c)| c)
}

/// One MovingAI scenario: a start, a goal and the published optimal path length.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Difficulty bucket (column 1).
    pub bucket: u32,
    /// Map file as written in the scenario (often with a directory: match it by basename).
    pub map: String,
    /// Map width the scenario was made for.
    pub width: u32,
    /// Map height the scenario was made for.
    pub height: u32,
    /// Start, MovingAI coordinates (x column, y row from the top).
    pub start: (u32, u32),
    /// Goal, MovingAI coordinates.
    pub goal: (u32, u32),
    /// Optimal octile length without corner cutting, in cells (printed to ~6 significant digits).
    pub optimal_length: f64,
    /// Digits printed after the decimal point of `optimal_length` (`3894.56` → 2): the
    /// precision a planned length can be compared at.
    pub optimal_length_decimals: u32,
    /// Line of the file the scenario was read from (1-based), for error messages.
    pub line: usize,
}

/// Reads a MovingAI `.map` file.
pub fn read_movingai_map(path: impl AsRef<Path>) -> Result<MovingAiMap> {
    let path = path.as_ref();
    let text = crate::limits::read_text(path)?;
    parse_movingai_map(&text, path)
}

/// Parses the text of a MovingAI `.map` file; `path` only names the file in errors.
pub fn parse_movingai_map(text: &str, path: &Path) -> Result<MovingAiMap> {
    let mut lines = text
        .lines()
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
        .enumerate();
    let mut next_line = |what: &str| -> Result<(usize, &str)> {
        for (i, line) in lines.by_ref() {
            if !line.trim().is_empty() {
                return Ok((i + 1, line.trim()));
            }
        }
        Err(WorldError::syntax(
            path,
            "end of file",
            format!("missing {what}"),
        ))
    };

    let (n, type_line) = next_line("the header line `type octile`")?;
    if type_line.split_whitespace().collect::<Vec<_>>() != ["type", "octile"] {
        return Err(WorldError::syntax(
            path,
            format!("line {n}"),
            format!("found `{type_line}`, expected `type octile`"),
        ));
    }
    let mut height = None;
    let mut width = None;
    loop {
        let (n, line) = next_line("the header line `map`")?;
        if line == "map" {
            break;
        }
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or_default();
        let slot = match key {
            "height" => &mut height,
            "width" => &mut width,
            _ => {
                return Err(WorldError::syntax(
                    path,
                    format!("line {n}"),
                    format!("found `{line}`, expected `height H`, `width W` or `map`"),
                ));
            }
        };
        let value = words
            .next()
            .and_then(|v| v.parse::<u32>().ok())
            .filter(|&v| v > 0);
        match (value, words.next()) {
            (Some(v), None) if v <= MAX_GRID_SIDE => *slot = Some(v),
            _ => {
                return Err(WorldError::syntax(
                    path,
                    format!("line {n}"),
                    format!(
                        "found `{line}`, expected `{key}` and an integer in 1..={MAX_GRID_SIDE}"
                    ),
                ));
            }
        }
    }
    let (Some(height), Some(width)) = (height, width) else {
        let missing = if height.is_none() { "height" } else { "width" };
        return Err(WorldError::syntax(
            path,
            "header",
            format!("`{missing}` is missing before `map`"),
        ));
    };
    crate::limits::check_cells(path, "height × width", width.into(), height.into())?;

    let geometry = GridGeometry::new(width, height, 1.0, Point2::new(0.0, 0.0));
    let mut passable = Grid::filled(geometry, false);
    for file_row in 0..height {
        let (n, line) = lines.next().ok_or_else(|| {
            WorldError::syntax(
                path,
                "end of file",
                format!("found {file_row} map rows, expected {height} (the header's height)"),
            )
        })?;
        let n = n + 1;
        let row = height - 1 - file_row;
        if line.chars().count() != width as usize {
            return Err(WorldError::syntax(
                path,
                format!("line {n}"),
                format!(
                    "map row {file_row} has {} characters, expected {width} (the header's width)",
                    line.chars().count()
                ),
            ));
        }
        let start = row as usize * width as usize;
        let out = &mut passable.as_mut_slice()[start..start + width as usize];
        for (col, (ch, cell)) in line.chars().zip(out.iter_mut()).enumerate() {
            *cell = match ch {
                '.' | 'G' => true,
                '@' | 'O' | 'T' | 'S' | 'W' => false,
                found => {
                    return Err(WorldError::syntax(
                        path,
                        format!("line {n}, column {}", col + 1),
                        format!(
                            "unknown terrain character {found:?}, expected one of . G @ O T S W"
                        ),
                    ));
                }
            };
        }
    }
    for (i, line) in lines {
        if !line.trim().is_empty() {
            return Err(WorldError::syntax(
                path,
                format!("line {}", i + 1),
                format!("found more than {height} map rows (the header's height)"),
            ));
        }
    }
    Ok(MovingAiMap {
        width,
        height,
        passable,
    })
}

/// Reads a MovingAI `.scen` file.
pub fn read_scenarios(path: impl AsRef<Path>) -> Result<Vec<Scenario>> {
    let path = path.as_ref();
    let text = crate::limits::read_text(path)?;
    parse_scenarios(&text, path)
}

/// Column names of a `.scen` row, for error messages.
const SCEN_COLUMNS: [&str; 9] = [
    "bucket",
    "map",
    "map width",
    "map height",
    "start x",
    "start y",
    "goal x",
    "goal y",
    "optimal length",
];

/// Parses the text of a MovingAI `.scen` file; `path` only names the file in errors.
///
/// Rows are tab-separated; a row without tabs is split at whitespace instead. Blank lines are
/// skipped. Start and goal must lie inside the stated map size.
pub fn parse_scenarios(text: &str, path: &Path) -> Result<Vec<Scenario>> {
    let mut lines = text
        .lines()
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
        .enumerate();
    let version = lines.by_ref().find(|(_, l)| !l.trim().is_empty());
    match version.map(|(i, l)| (i, l.split_whitespace().collect::<Vec<_>>())) {
        Some((_, words)) if words.len() == 2 && words[0] == "version" => {
            if words[1] != "1" && words[1] != "1.0" {
                return Err(WorldError::UnsupportedVersion {
                    path: path.display().to_string(),
                    format: "MovingAI scenario".into(),
                    found: words[1].to_string(),
                    expected: "1 or 1.0".into(),
                });
            }
        }
        Some((i, _)) => {
            return Err(WorldError::syntax(
                path,
                format!("line {}", i + 1),
                "expected `version 1` as the first line",
            ));
        }
        None => {
            return Err(WorldError::syntax(
                path,
                "end of file",
                "missing `version 1`",
            ));
        }
    }

    let mut scenarios = Vec::new();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let n = i + 1;
        let fields: Vec<&str> = if line.contains('\t') {
            line.split('\t').map(str::trim).collect()
        } else {
            line.split_whitespace().collect()
        };
        if fields.len() != SCEN_COLUMNS.len() {
            return Err(WorldError::syntax(
                path,
                format!("line {n}"),
                format!(
                    "found {} tab-separated columns, expected 9: {}",
                    fields.len(),
                    SCEN_COLUMNS.join(", ")
                ),
            ));
        }
        let bad = |col: usize, expected: &str| {
            WorldError::syntax(
                path,
                format!("line {n}, column {} ({})", col + 1, SCEN_COLUMNS[col]),
                format!("found `{}`, expected {expected}", fields[col]),
            )
        };
        let int = |col: usize| {
            fields[col]
                .parse::<u32>()
                .map_err(|_| bad(col, "a non-negative integer"))
        };
        let bucket = int(0)?;
        if fields[1].is_empty() {
            return Err(bad(1, "a map file name"));
        }
        let width = int(2)?;
        let height = int(3)?;
        let coordinate = |col: usize, limit: u32, dim: &str| -> Result<u32> {
            let v = int(col)?;
            if v >= limit {
                return Err(bad(
                    col,
                    &format!("a coordinate below the map {dim} {limit}"),
                ));
            }
            Ok(v)
        };
        let start = (
            coordinate(4, width, "width")?,
            coordinate(5, height, "height")?,
        );
        let goal = (
            coordinate(6, width, "width")?,
            coordinate(7, height, "height")?,
        );
        let optimal_length = fields[8]
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v >= 0.0)
            .ok_or_else(|| bad(8, "a non-negative number"))?;
        scenarios.push(Scenario {
            bucket,
            map: fields[1].to_string(),
            width,
            height,
            start,
            goal,
            optimal_length,
            optimal_length_decimals: fields[8]
                .split_once('.')
                .map_or(0, |(_, fraction)| fraction.len() as u32),
            line: n,
        });
    }
    Ok(scenarios)
}

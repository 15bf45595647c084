//! Checks [`GridAStar`] against the published optimal lengths of a MovingAI `.scen` file.
//!
//! Every scenario is planned with [`GridAStar::plan`] (8-connected, no corner cutting: jump
//! point search) and its length compared with the file's optimal length at the precision the
//! file prints, within [`LENGTH_TOLERANCE`].

use super::grid_astar::{Connectivity, GridAStar};
use super::nav_grid::NavGrid;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use usar_world::io::movingai::{MovingAiMap, Scenario, read_movingai_map, read_scenarios};
use usar_world::{Result, WorldError};

/// The accepted error beyond the file's own rounding, cells (see [`printed_error`]).
pub const LENGTH_TOLERANCE: f64 = 1e-3;

/// How far a planned length lies outside the interval the printed optimum stands for:
/// max(0, |found − expected| − ½·10⁻ᵈ), where `d` is the number of decimals the file printed.
///
/// The files print about six significant digits (`3166.91` for a path of 3166.915005…), so the
/// raw difference reaches half a unit of the last digit (5·10⁻³ on maze512-4-0) even for a
/// planner that is exactly right; what is left after that rounding is the planner's error.
pub fn printed_error(found: f64, scenario: &Scenario) -> f64 {
    let half_unit = 0.5 * 10f64.powi(-(scenario.optimal_length_decimals.min(15) as i32));
    ((found - scenario.optimal_length).abs() - half_unit).max(0.0)
}

/// How many mismatches a report lists in full.
pub const MISMATCHES_LISTED: usize = 10;

/// One scenario whose planned length differs from the published one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Mismatch {
    /// Index of the scenario in the file (0 = first row after `version`).
    pub index: usize,
    /// Start, MovingAI coordinates (x column, y row from the top).
    pub start: (u32, u32),
    /// Goal, MovingAI coordinates.
    pub goal: (u32, u32),
    /// Published optimal length, cells.
    pub expected: f64,
    /// Planned length, cells; `None` when the planner found no path.
    pub found: Option<f64>,
}

/// The outcome of checking a `.scen` file.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScenarioReport {
    /// Number of scenarios planned.
    pub scenarios: usize,
    /// Number whose planned length matched within [`LENGTH_TOLERANCE`] at the printed
    /// precision.
    pub matched: usize,
    /// Largest [`printed_error`] over scenarios where a path was found, cells.
    pub max_abs_error: f64,
    /// Largest unrounded |found − expected|, cells (bounded by half a unit of the last
    /// printed digit when the planner is right).
    pub max_raw_error: f64,
    /// Cells expanded by the planner (jump points), summed over all scenarios.
    pub total_expanded: u64,
    /// The first [`MISMATCHES_LISTED`] mismatches.
    pub mismatches: Vec<Mismatch>,
}

/// Plans every scenario of `scen_path` and compares lengths with the published optima.
///
/// The map of a row is looked up by the basename of its `map` column in the `.scen` file's
/// folder; if that file does not exist, `<scen file name without .scen>` is tried (for
/// `16room_000.map.scen`, `16room_000.map`). A missing map is an error naming it.
pub fn check_scenarios(scen_path: &Path) -> Result<ScenarioReport> {
    check_scenario_sample(scen_path, 1)
}

/// Like [`check_scenarios`], but plans only every `stride`-th scenario (indices 0, stride,
/// 2·stride, …): a deterministic spread for large files. A stride of 0 is taken as 1.
pub fn check_scenario_sample(scen_path: &Path, stride: usize) -> Result<ScenarioReport> {
    let stride = stride.max(1);
    let scenarios = read_scenarios(scen_path)?;
    let folder = scen_path.parent().unwrap_or(Path::new("."));
    // Maps by the name written in the scenario rows (usually one map per file).
    let mut maps: BTreeMap<String, (MovingAiMap, NavGrid)> = BTreeMap::new();
    let mut astar = GridAStar::new();
    let mut report = ScenarioReport {
        scenarios: 0,
        matched: 0,
        max_abs_error: 0.0,
        max_raw_error: 0.0,
        total_expanded: 0,
        mismatches: Vec::new(),
    };
    for (index, scenario) in scenarios.iter().enumerate().step_by(stride) {
        if !maps.contains_key(&scenario.map) {
            let map = load_map(scen_path, folder, scenario)?;
            let nav = NavGrid::from_passable(&map.passable);
            maps.insert(scenario.map.clone(), (map, nav));
        }
        let (map, nav) = &maps[&scenario.map];
        if (map.width, map.height) != (scenario.width, scenario.height) {
            return Err(WorldError::invalid(
                scen_path,
                format!("line {} columns 3-4 (map width, map height)", scenario.line),
                format!("{}x{}", scenario.width, scenario.height),
                format!(
                    "{}x{}, the size of map {}",
                    map.width, map.height, scenario.map
                ),
            ));
        }
        let start = map.cell_of(scenario.start.0, scenario.start.1);
        let goal = map.cell_of(scenario.goal.0, scenario.goal.1);
        let found = astar
            .plan(nav, start, goal, Connectivity::Eight)
            .map(|p| p.length_cells);
        report.scenarios += 1;
        report.total_expanded += astar.expanded() as u64;
        let error = found.map(|f| printed_error(f, scenario));
        if let (Some(f), Some(e)) = (found, error) {
            report.max_abs_error = report.max_abs_error.max(e);
            report.max_raw_error = report
                .max_raw_error
                .max((f - scenario.optimal_length).abs());
        }
        if error.is_some_and(|e| e <= LENGTH_TOLERANCE) {
            report.matched += 1;
        } else if report.mismatches.len() < MISMATCHES_LISTED {
            report.mismatches.push(Mismatch {
                index,
                start: scenario.start,
                goal: scenario.goal,
                expected: scenario.optimal_length,
                found,
            });
        }
    }
    Ok(report)
}

/// Finds and reads the map a scenario row names.
fn load_map(scen_path: &Path, folder: &Path, scenario: &Scenario) -> Result<MovingAiMap> {
    let basename = scenario
        .map
        .rsplit(['/', '\\'])
        .next()
        .unwrap_or(&scenario.map);
    let mut candidates: Vec<PathBuf> = vec![folder.join(basename)];
    if let Some(stem) = scen_path
        .file_name()
        .and_then(|n| n.to_str()?.strip_suffix(".scen"))
    {
        let by_stem = folder.join(stem);
        if !candidates.contains(&by_stem) {
            candidates.push(by_stem);
        }
    }
    for candidate in &candidates {
        if candidate.is_file() {
            return read_movingai_map(candidate);
        }
    }
    let tried: Vec<String> = candidates.iter().map(|c| c.display().to_string()).collect();
    Err(WorldError::MissingReference {
        path: scen_path.display().to_string(),
        field: format!("line {} column 2 (map)", scenario.line),
        target: format!("`{}` (looked for {})", scenario.map, tried.join(" and ")),
        io: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
    })
}

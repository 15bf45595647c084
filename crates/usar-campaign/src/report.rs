//! Tables in the papers' style — `mean (sd)` per configuration, rows and columns chosen by the
//! campaign file — the comparisons it asks for, and plots: each series over time with a mean ±
//! sd band per row level, and a bar chart with sd error bars per metric.

use crate::design::{CampaignFile, Comparison, Level, TestKind};
use crate::error::{CampaignError, Result};
use crate::lock::FolderLock;
use crate::stats::{self, Summary, Tails};
use crate::store::StoredRun;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use usar_plot::{Bar, BarChart, LineChart, Series};

/// One table: a metric's `mean (sd)` per (row level, column level).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table {
    pub metric: String,
    pub rows_factor: Option<String>,
    pub columns_factor: Option<String>,
    pub rows: Vec<String>,
    pub columns: Vec<String>,
    /// `cells[row][column]`; `None` where no run has that combination.
    pub cells: Vec<Vec<Option<Summary>>>,
}

/// One comparison's outcome.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TestRow {
    pub metric: String,
    pub factor: String,
    /// The runs compared, when restricted (`robots = 6, hypothesis = big`); empty: all.
    pub within: String,
    /// The campaign's note on the comparison (e.g. the paper's result).
    pub note: String,
    /// The levels compared, in order (a t-test's first group is the one `greater` refers to).
    pub groups: Vec<String>,
    pub test: TestKind,
    pub tails: Tails,
    /// Runs per group (pairs for a paired test).
    pub n: Vec<usize>,
    pub statistic: Option<f64>,
    pub df: Vec<f64>,
    pub p: Option<f64>,
    /// Why the test could not be computed, if it could not.
    pub error: Option<String>,
}

/// Everything `usar campaign report` shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    pub campaign: String,
    pub description: String,
    pub runs: usize,
    pub tables: Vec<Table>,
    pub tests: Vec<TestRow>,
}

/// Joins the levels of a composite axis (`robots+coordination`).
const LEVEL_JOIN: &str = " · ";

/// A run's level of `factor`; for a composite `a+b`, its levels of a and b joined.
fn level_of(run: &StoredRun, factor: &str) -> String {
    factor
        .split('+')
        .map(|f| run.config.get(f).map(Level::to_string).unwrap_or_default())
        .collect::<Vec<_>>()
        .join(LEVEL_JOIN)
}

/// Levels of `factor` in the order the campaign lists them; for a composite `a+b`, every
/// combination, b varying fastest.
fn levels(campaign: &CampaignFile, factor: &str) -> Vec<String> {
    factor.split('+').fold(vec![String::new()], |acc, f| {
        let ls: Vec<String> = campaign
            .factors
            .get(f)
            .map(|ls| ls.iter().map(Level::to_string).collect())
            .unwrap_or_default();
        acc.iter()
            .flat_map(|a| {
                ls.iter().map(move |l| {
                    if a.is_empty() {
                        l.clone()
                    } else {
                        format!("{a}{LEVEL_JOIN}{l}")
                    }
                })
            })
            .collect()
    })
}

/// Builds the report of `runs` (all of one campaign) as its campaign file asks.
pub fn build(campaign: &CampaignFile, runs: &[StoredRun], all_metrics: &[String]) -> Report {
    let spec = &campaign.report;
    let rows_factor = spec
        .rows
        .clone()
        .or_else(|| campaign.factors.keys().next().cloned());
    let columns_factor = spec
        .columns
        .clone()
        .filter(|c| Some(c) != rows_factor.as_ref());
    let metrics: Vec<String> = if spec.metrics.is_empty() {
        all_metrics.to_vec()
    } else {
        spec.metrics.clone()
    };
    let axis = |f: &Option<String>| match f {
        Some(f) => levels(campaign, f),
        None => vec!["all".to_string()],
    };
    let (rows, columns) = (axis(&rows_factor), axis(&columns_factor));
    let key = |run: &StoredRun, f: &Option<String>| match f {
        Some(f) => level_of(run, f),
        None => "all".to_string(),
    };
    let tables = metrics
        .iter()
        .map(|metric| {
            let cells = rows
                .iter()
                .map(|r| {
                    columns
                        .iter()
                        .map(|c| {
                            let values: Vec<f64> = runs
                                .iter()
                                .filter(|run| {
                                    &key(run, &rows_factor) == r && &key(run, &columns_factor) == c
                                })
                                .filter_map(|run| run.output.metrics.get(metric).copied())
                                .collect();
                            stats::summarize(&values)
                        })
                        .collect()
                })
                .collect();
            Table {
                metric: metric.clone(),
                rows_factor: rows_factor.clone(),
                columns_factor: columns_factor.clone(),
                rows: rows.clone(),
                columns: columns.clone(),
                cells,
            }
        })
        .collect();
    let tests = spec
        .compare
        .iter()
        .map(|c| compare(campaign, c, runs))
        .collect();
    Report {
        campaign: campaign.name.clone(),
        description: campaign.description.clone(),
        runs: runs.len(),
        tables,
        tests,
    }
}

/// Runs one comparison.
fn compare(campaign: &CampaignFile, c: &Comparison, runs: &[StoredRun]) -> TestRow {
    let groups: Vec<String> = if c.groups.is_empty() {
        levels(campaign, &c.factor)
    } else {
        c.groups.iter().map(Level::to_string).collect()
    };
    let within = |r: &StoredRun| {
        c.within.iter().all(|(f, l)| {
            r.config
                .get(f)
                .is_some_and(|v| v.to_string() == l.to_string())
        })
    };
    let values = |g: &str| -> Vec<(String, f64)> {
        runs.iter()
            .filter(|r| within(r) && level_of(r, &c.factor) == g)
            .filter_map(|r| {
                let v = *r.output.metrics.get(&c.metric)?;
                // The pairing key: every other factor's value and the seed.
                let mut rest = r.config.clone();
                for f in c.factor.split('+') {
                    rest.0.remove(f);
                }
                Some((format!("{}|{}", rest.describe(&[]), r.seed), v))
            })
            .collect()
    };
    let samples: Vec<Vec<(String, f64)>> = groups.iter().map(|g| values(g)).collect();
    let plain: Vec<Vec<f64>> = samples
        .iter()
        .map(|s| s.iter().map(|(_, v)| *v).collect())
        .collect();
    let (result, n) = match c.test {
        TestKind::Anova => {
            let refs: Vec<&[f64]> = plain.iter().map(Vec::as_slice).collect();
            (
                stats::one_way_anova(&refs),
                plain.iter().map(Vec::len).collect(),
            )
        }
        TestKind::Welch => (
            stats::welch_t_test(&plain[0], &plain[1], c.tails),
            plain.iter().map(Vec::len).collect(),
        ),
        TestKind::Paired => {
            let second: BTreeMap<&str, f64> =
                samples[1].iter().map(|(k, v)| (k.as_str(), *v)).collect();
            let (a, b): (Vec<f64>, Vec<f64>) = samples[0]
                .iter()
                .filter_map(|(k, v)| Some((*v, *second.get(k.as_str())?)))
                .unzip();
            let n = a.len();
            (stats::paired_t_test(&a, &b, c.tails), vec![n, n])
        }
    };
    let (statistic, df, p, error) = match result {
        Ok(r) => (Some(r.statistic), r.df, Some(r.p), None),
        Err(e) => (None, Vec::new(), None, Some(e.to_string())),
    };
    TestRow {
        metric: c.metric.clone(),
        factor: c.factor.clone(),
        within: c
            .within
            .iter()
            .map(|(f, l)| format!("{f} = {l}"))
            .collect::<Vec<_>>()
            .join(", "),
        note: c.note.clone(),
        groups,
        test: c.test,
        tails: c.tails,
        n,
        statistic,
        df,
        p,
        error,
    }
}

fn cell_text(s: &Option<Summary>) -> String {
    match s {
        Some(Summary {
            mean, sd: Some(sd), ..
        }) => format!("{mean:.4} ({sd:.4})"),
        Some(Summary { mean, sd: None, .. }) => format!("{mean:.4}"),
        None => "–".into(),
    }
}

/// The compared factor, with the runs it is restricted to.
fn factor_text(t: &TestRow) -> String {
    if t.within.is_empty() {
        t.factor.clone()
    } else {
        format!("{} ({})", t.factor, t.within)
    }
}

fn test_name(t: &TestRow) -> String {
    let kind = match t.test {
        TestKind::Anova => "one-way ANOVA",
        TestKind::Welch => "Welch t-test",
        TestKind::Paired => "paired t-test",
    };
    match (t.test, t.tails) {
        (TestKind::Anova, _) => kind.to_string(),
        (_, Tails::TwoSided) => format!("{kind}, two-sided"),
        (_, Tails::Greater) => format!("{kind}, one-sided ({} > {})", t.groups[0], t.groups[1]),
        (_, Tails::Less) => format!("{kind}, one-sided ({} < {})", t.groups[0], t.groups[1]),
    }
}

fn stat_text(t: &TestRow) -> (String, String, String) {
    let letter = if t.test == TestKind::Anova { "F" } else { "t" };
    match (t.statistic, t.p) {
        (Some(s), Some(p)) => (
            format!("{letter} = {s:.4}"),
            t.df.iter()
                .map(|d| format!("{d:.2}"))
                .collect::<Vec<_>>()
                .join(", "),
            format!("{p:.4e}"),
        ),
        _ => (
            t.error.clone().unwrap_or_default(),
            String::new(),
            String::new(),
        ),
    }
}

impl Report {
    /// The report as Markdown.
    pub fn to_markdown(&self, plots: &[PathBuf]) -> String {
        let mut out = format!("# Campaign `{}`\n\n", self.campaign);
        if !self.description.is_empty() {
            out += &format!("{}\n\n", self.description);
        }
        out += &format!("{} runs. Cells: mean (sd) over runs.\n\n", self.runs);
        for t in &self.tables {
            out += &format!("## {}\n\n", t.metric);
            let corner = match (&t.rows_factor, &t.columns_factor) {
                (Some(r), Some(c)) => format!("{r} \\ {c}"),
                (Some(r), None) => r.clone(),
                _ => String::new(),
            };
            out += &format!("| {corner} | {} |\n", t.columns.join(" | "));
            out += &format!("|---|{}\n", "---|".repeat(t.columns.len()));
            for (r, row) in t.rows.iter().zip(&t.cells) {
                let cells: Vec<String> = row.iter().map(cell_text).collect();
                out += &format!("| {r} | {} |\n", cells.join(" | "));
            }
            out += "\n";
        }
        if !self.tests.is_empty() {
            out += "## Comparisons\n\n| metric | factor | groups | test | n | statistic | df | p | note |\n|---|---|---|---|---|---|---|---|---|\n";
            for t in &self.tests {
                let (s, df, p) = stat_text(t);
                let n: Vec<String> = t.n.iter().map(usize::to_string).collect();
                out += &format!(
                    "| {} | {} | {} | {} | {} | {s} | {df} | {p} | {} |\n",
                    t.metric,
                    factor_text(t),
                    t.groups.join(", "),
                    test_name(t),
                    n.join(", "),
                    t.note
                );
            }
            out += "\n";
        }
        for p in plots
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "png"))
        {
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy())
                .unwrap_or_default();
            out += &format!("![{name}]({name})\n\n");
        }
        out
    }

    /// The report as a standalone HTML page.
    pub fn to_html(&self, plots: &[PathBuf]) -> String {
        let esc = |s: &str| {
            s.replace('&', "&amp;")
                .replace('<', "&lt;")
                .replace('>', "&gt;")
        };
        let mut out = format!(
            "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>Campaign {0}</title>\
             <style>body{{font-family:sans-serif;margin:2em}}table{{border-collapse:collapse;margin-bottom:1.5em}}\
             td,th{{border:1px solid #bbb;padding:4px 8px;text-align:right}}th{{background:#eee}}</style>\
             </head><body>\n<h1>Campaign {0}</h1>\n<p>{1}</p>\n<p>{2} runs. Cells: mean (sd) over runs.</p>\n",
            esc(&self.campaign),
            esc(&self.description),
            self.runs
        );
        for t in &self.tables {
            out += &format!(
                "<h2>{}</h2>\n<table><tr><th>{}</th>",
                esc(&t.metric),
                esc(t.rows_factor.as_deref().unwrap_or(""))
            );
            for c in &t.columns {
                out += &format!("<th>{}</th>", esc(c));
            }
            out += "</tr>\n";
            for (r, row) in t.rows.iter().zip(&t.cells) {
                out += &format!("<tr><th>{}</th>", esc(r));
                for c in row {
                    out += &format!("<td>{}</td>", esc(&cell_text(c)));
                }
                out += "</tr>\n";
            }
            out += "</table>\n";
        }
        if !self.tests.is_empty() {
            out += "<h2>Comparisons</h2>\n<table><tr><th>metric</th><th>factor</th><th>groups</th><th>test</th><th>n</th><th>statistic</th><th>df</th><th>p</th><th>note</th></tr>\n";
            for t in &self.tests {
                let (s, df, p) = stat_text(t);
                let n: Vec<String> = t.n.iter().map(usize::to_string).collect();
                out += &format!(
                    "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                    esc(&t.metric),
                    esc(&factor_text(t)),
                    esc(&t.groups.join(", ")),
                    esc(&test_name(t)),
                    n.join(", "),
                    esc(&s),
                    df,
                    p,
                    esc(&t.note)
                );
            }
            out += "</table>\n";
        }
        for p in plots
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        {
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy())
                .unwrap_or_default();
            out += &format!("<p><img src=\"{}\" alt=\"{0}\"></p>\n", esc(&name));
        }
        out + "</body></html>\n"
    }
}

/// A report folder opened for writing: created, locked (one report writes it at a time) and
/// cleared of the temporary files a killed report left.
#[derive(Debug)]
pub struct ReportFolder {
    pub dir: PathBuf,
    /// Stale temporary files removed on opening.
    pub removed: Vec<PathBuf>,
    _lock: FolderLock,
}

impl ReportFolder {
    /// Creates `dir` if needed, takes its lock (another report writing it is refused at once)
    /// and removes the temporary files of earlier reports that were killed while writing
    /// (see [`is_report_temporary`]).
    pub fn open(dir: &Path) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(|e| {
            CampaignError::Input(format!("{}: cannot create the folder: {e}", dir.display()))
        })?;
        let lock = FolderLock::exclusive(dir, "campaign report")?;
        let entries = std::fs::read_dir(dir).map_err(|e| {
            CampaignError::Input(format!("{}: cannot list the folder: {e}", dir.display()))
        })?;
        let mut removed = Vec::new();
        for entry in entries.flatten() {
            let name = entry.file_name();
            let is_file = entry.file_type().is_ok_and(|t| t.is_file());
            if is_file && name.to_str().is_some_and(is_report_temporary) {
                let path = entry.path();
                std::fs::remove_file(&path).map_err(|e| {
                    CampaignError::Input(format!("{}: cannot remove: {e}", path.display()))
                })?;
                removed.push(path);
            }
        }
        removed.sort();
        Ok(Self {
            dir: dir.to_path_buf(),
            removed,
            _lock: lock,
        })
    }
}

/// Whether `name` is a temporary file of a report's atomic write ([`usar_world::write_atomic`]:
/// `.TARGET.tmp-PID`) whose target is a file a report writes: `report.md`, `report.html`,
/// `series_*` and `bars_*` plots (`.png`, `.svg`).
pub fn is_report_temporary(name: &str) -> bool {
    let Some((target, pid)) = name
        .strip_prefix('.')
        .and_then(|rest| rest.rsplit_once(".tmp-"))
    else {
        return false;
    };
    let plot = |prefix: &str| {
        target.strip_prefix(prefix).is_some_and(|rest| {
            !rest.is_empty() && (rest.ends_with(".png") || rest.ends_with(".svg"))
        })
    };
    !pid.is_empty()
        && pid.bytes().all(|b| b.is_ascii_digit())
        && (target == "report.md" || target == "report.html" || plot("series_") || plot("bars_"))
}

/// Draws the plots into `dir` (PNG and SVG each): every `series` metric over x with a mean ± sd
/// band per row level, and a bar chart of every tabulated metric per row level. Returns the
/// files written.
pub fn write_plots(
    report: &Report,
    campaign: &CampaignFile,
    runs: &[StoredRun],
    series_x: &str,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let rows_factor = report.tables.first().and_then(|t| t.rows_factor.clone());
    let row_levels = match &rows_factor {
        Some(f) => levels(campaign, f),
        None => vec!["all".to_string()],
    };
    let in_row = |run: &StoredRun, level: &str| match &rows_factor {
        Some(f) => level_of(run, f) == level,
        None => true,
    };
    for metric in &campaign.report.series {
        let series = row_levels
            .iter()
            .map(|level| {
                // Mean and sd over runs at every x (runs sample at the same x values).
                let mut at: BTreeMap<u64, (f64, Vec<f64>)> = BTreeMap::new();
                for run in runs.iter().filter(|r| in_row(r, level)) {
                    for p in &run.output.series {
                        if let Some(v) = p.values.get(metric) {
                            at.entry(p.x.to_bits())
                                .or_insert((p.x, Vec::new()))
                                .1
                                .push(*v);
                        }
                    }
                }
                let mut points: Vec<(f64, Vec<f64>)> = at.into_values().collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                let means = points.iter().map(|(x, v)| (*x, stats::mean(v))).collect();
                let sds = points
                    .iter()
                    .map(|(_, v)| stats::variance(v).map_or(0.0, f64::sqrt))
                    .collect();
                let label = match &rows_factor {
                    Some(f) => format!("{f} = {level}"),
                    None => level.clone(),
                };
                Series::with_band(label, means, sds)
            })
            .collect();
        let chart = LineChart {
            title: format!("{metric} (mean ± sd)"),
            x_label: series_x.to_string(),
            y_label: metric.clone(),
            series,
            y_range: None,
        };
        for ext in ["png", "svg"] {
            let path = dir.join(format!("series_{metric}.{ext}"));
            chart.save(&path)?;
            files.push(path);
        }
    }
    for table in &report.tables {
        let bars = table
            .rows
            .iter()
            .map(|level| {
                let values: Vec<f64> = runs
                    .iter()
                    .filter(|r| in_row(r, level))
                    .filter_map(|r| r.output.metrics.get(&table.metric).copied())
                    .collect();
                let s = stats::summarize(&values);
                Bar {
                    label: level.clone(),
                    value: s.as_ref().map_or(0.0, |s| s.mean),
                    error: s.and_then(|s| s.sd).unwrap_or(0.0),
                }
            })
            .collect();
        let chart = BarChart {
            title: format!(
                "{} by {} (mean ± sd)",
                table.metric,
                table.rows_factor.as_deref().unwrap_or("campaign")
            ),
            y_label: table.metric.clone(),
            bars,
        };
        for ext in ["png", "svg"] {
            let path = dir.join(format!("bars_{}.{ext}", table.metric));
            chart.save(&path)?;
            files.push(path);
        }
    }
    Ok(files)
}

/// The format of a report's text file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `report.md`.
    Markdown,
    /// `report.html`.
    Html,
}

impl Format {
    /// The file the report is written to in its folder.
    pub fn file_name(self) -> &'static str {
        match self {
            Format::Markdown => "report.md",
            Format::Html => "report.html",
        }
    }
}

/// What [`write_folder`] wrote.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WrittenReport {
    /// The report's text file (`report.md` or `report.html`).
    pub file: PathBuf,
    /// The plots, PNG and SVG each.
    pub plots: Vec<PathBuf>,
    /// The report itself.
    pub report: Report,
}

/// Writes a campaign's report folder `dir`: builds the report of `runs` (the tables of every
/// metric of `runner` unless the campaign names some), opens the folder ([`ReportFolder`]: one
/// report at a time; stale temporary files go first), draws the plots ([`write_plots`]) and
/// writes the report's text in `format`, atomically and last.
pub fn write_folder(
    dir: &Path,
    campaign: &CampaignFile,
    runs: &[StoredRun],
    runner: &dyn crate::Runner,
    format: Format,
) -> Result<WrittenReport> {
    let metrics: Vec<String> = runner.metrics().into_iter().map(|m| m.name).collect();
    let report = build(campaign, runs, &metrics);
    let folder = ReportFolder::open(dir)?;
    let plots = write_plots(&report, campaign, runs, runner.series_x(), &folder.dir)?;
    let text = match format {
        Format::Markdown => report.to_markdown(&plots),
        Format::Html => report.to_html(&plots),
    };
    let file = folder.dir.join(format.file_name());
    usar_world::write_atomic(&file, text.as_bytes())?;
    Ok(WrittenReport {
        file,
        plots,
        report,
    })
}

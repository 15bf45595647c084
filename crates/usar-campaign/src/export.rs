//! `usar campaign export --csv`: one row per run for analysis elsewhere.
//!
//! Columns, in order: `run_id`, `config_index`, `repetition`, `seed`; then one column per factor
//! of the runner (alphabetical; varied and fixed alike, the value the run used); then one
//! column per final metric (alphabetical). Numbers are written with Rust's shortest exact
//! representation, so a value read back is the stored f64. See `docs/campaign-format.md`.

use crate::error::{CampaignError, Result};
use crate::store::StoredRun;
use std::collections::BTreeSet;
use std::path::Path;

/// Writes `runs` as CSV to `path` (atomically). Returns the header.
pub fn write_csv(runs: &[StoredRun], path: &Path) -> Result<Vec<String>> {
    let factors: BTreeSet<&String> = runs.iter().flat_map(|r| r.config.0.keys()).collect();
    let metrics: BTreeSet<&String> = runs.iter().flat_map(|r| r.output.metrics.keys()).collect();
    let mut header: Vec<String> = ["run_id", "config_index", "repetition", "seed"]
        .map(String::from)
        .to_vec();
    header.extend(factors.iter().map(|f| f.to_string()));
    header.extend(metrics.iter().map(|m| m.to_string()));
    let mut w = csv::Writer::from_writer(Vec::new());
    let csv_err = |e: csv::Error| CampaignError::Input(format!("{}: {e}", path.display()));
    w.write_record(&header).map_err(csv_err)?;
    for r in runs {
        let mut row = vec![
            r.id.to_string(),
            r.config_index.to_string(),
            r.repetition.to_string(),
            r.seed.to_string(),
        ];
        row.extend(
            factors
                .iter()
                .map(|f| r.config.get(f).map(|l| l.to_string()).unwrap_or_default()),
        );
        row.extend(metrics.iter().map(|m| {
            r.output
                .metrics
                .get(*m)
                .map(|v| v.to_string())
                .unwrap_or_default()
        }));
        w.write_record(&row).map_err(csv_err)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| CampaignError::Input(format!("{}: {e}", path.display())))?;
    usar_world::write_atomic(path, &bytes)?;
    Ok(header)
}

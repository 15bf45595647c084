//! Running a design: the runs not yet in the database (of this shard) run in parallel on a
//! rayon pool; one writer — the calling thread — commits them as they arrive, several per
//! transaction when they arrive together.

use crate::design::{Design, RunSpec};
use crate::error::{CampaignError, Result};
use crate::runner::Runner;
use crate::store::{Finished, Store};
use std::sync::mpsc;
use std::time::Instant;

/// A deterministic slice of a design: shard `index` (1-based) of `count` holds the runs whose
/// id ≡ index − 1 (mod count).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl Shard {
    /// The whole design.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Parses `K/N` with 1 ≤ K ≤ N.
    pub fn parse(s: &str) -> std::result::Result<Self, String> {
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| format!("--shard {s:?}, expected K/N such as 1/4"))?;
        let (k, n) = (k.trim().parse::<u64>(), n.trim().parse::<u64>());
        match (k, n) {
            (Ok(index), Ok(count)) if count >= 1 && (1..=count).contains(&index) => {
                Ok(Shard { index, count })
            }
            _ => Err(format!("--shard {s:?}, expected K/N with 1 ≤ K ≤ N")),
        }
    }

    pub fn contains(&self, id: u64) -> bool {
        id % self.count == self.index - 1
    }
}

/// How a campaign run went.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunReport {
    /// Runs of the design (all shards).
    pub design_runs: u64,
    /// Runs of this shard.
    pub shard_runs: u64,
    /// Runs found already finished and not redone.
    pub skipped: u64,
    /// Runs done now.
    pub done: u64,
    /// Runs in the database now (all shards it holds).
    pub stored: u64,
}

/// Runs the runs of `shard` that `store` lacks, on `jobs` threads (0: one per core).
/// `on_progress(done, todo)` is called from the calling thread after each commit.
pub fn run_design(
    design: &Design,
    runner: &dyn Runner,
    store: &mut Store,
    shard: Shard,
    jobs: usize,
    mut on_progress: impl FnMut(u64, u64),
) -> Result<RunReport> {
    let finished = store.finished_ids()?;
    let shard_runs: Vec<RunSpec> = design.runs().filter(|r| shard.contains(r.id)).collect();
    let todo: Vec<RunSpec> = shard_runs
        .iter()
        .filter(|r| finished.binary_search(&r.id).is_err())
        .copied()
        .collect();
    let skipped = (shard_runs.len() - todo.len()) as u64;
    let total = todo.len() as u64;
    on_progress(0, total);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| CampaignError::Input(format!("--jobs {jobs}: cannot start threads: {e}")))?;
    let (tx, rx) = mpsc::channel::<Result<Finished>>();
    let mut done = 0u64;
    let mut failure: Option<CampaignError> = None;
    std::thread::scope(|scope| {
        scope.spawn(|| {
            pool.install(|| {
                use rayon::prelude::*;
                todo.par_iter().for_each_with(tx, |tx, spec| {
                    let config = &design.configs[spec.config_index];
                    let started = Instant::now();
                    let result = runner
                        .run(config, spec.seed)
                        .map(|output| Finished {
                            id: spec.id,
                            config_index: spec.config_index,
                            repetition: spec.repetition,
                            seed: spec.seed,
                            config: config.clone(),
                            output,
                            wall_time_s: started.elapsed().as_secs_f64(),
                        })
                        .map_err(|error| CampaignError::Run {
                            run: spec.id,
                            config: config.describe(
                                &design.campaign.factors.keys().cloned().collect::<Vec<_>>(),
                            ),
                            error,
                        });
                    // The writer stops listening after a failure; later results are dropped.
                    let _ = tx.send(result);
                });
            });
        });
        // The writer: block for one result, then take whatever else is ready (group commit).
        while let Ok(first) = rx.recv() {
            let mut batch = Vec::new();
            for result in std::iter::once(first).chain(rx.try_iter()) {
                match result {
                    Ok(f) => batch.push(f),
                    Err(e) => {
                        failure.get_or_insert(e);
                    }
                }
            }
            if !batch.is_empty() {
                if let Err(e) = store.insert(&batch) {
                    failure.get_or_insert(e);
                }
                done += batch.len() as u64;
                on_progress(done, total);
            }
            if failure.is_some() {
                break;
            }
        }
        drop(rx);
    });
    if let Some(e) = failure {
        return Err(e);
    }
    Ok(RunReport {
        design_runs: design.len(),
        shard_runs: shard_runs.len() as u64,
        skipped,
        done,
        stored: store.finished_ids()?.len() as u64,
    })
}

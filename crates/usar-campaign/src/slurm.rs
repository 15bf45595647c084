//! Campaigns on a SLURM cluster: a job array whose task K runs shard K of N
//! (`usar campaign run --shard K/N`) into a result folder of its own — SQLite is not safe on
//! the network file systems clusters share, one writer per database is — and a job that
//! depends on the array, merges the shards and writes the report.
//!
//! ```text
//! DIR/slurm/campaign.toml   the campaign, as submitted (tasks read this copy)
//! DIR/slurm/job.json        tasks, design hash and size: what `status` compares against
//! DIR/slurm/array.sbatch    #SBATCH --array=1-N; task K: campaign run --shard K/N --out DIR/shards/K
//! DIR/slurm/merge.sbatch    campaign merge DIR/shards/* --out DIR/merged; campaign report
//! DIR/slurm/submit.sh       sbatch the array, then the merge with --dependency=afterok
//! DIR/slurm/logs/           one log per task and the merge's
//! ```
//!
//! Submitting again resumes: a task skips the runs its folder already holds, so only what a
//! cancelled or failed task left undone is run. The same index sharding serves any scheduler
//! with indexed jobs: a Kubernetes indexed Job (`JOB_COMPLETION_INDEX` + 1 as K), an HTCondor
//! `queue N` (`$(Process)` + 1 as K).

use crate::design::Design;
use crate::error::{CampaignError, Result};
use crate::lock::FolderLock;
use crate::store::Store;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The most array tasks (SLURM's default `MaxArraySize` is 1001).
pub const MAX_TASKS: u64 = 1000;

/// What a SLURM submission asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct SlurmJob {
    /// The campaign's text (written to `DIR/slurm/campaign.toml`).
    pub campaign_text: String,
    /// The result folder (absolute: the tasks run wherever the scheduler starts them).
    pub out: PathBuf,
    pub tasks: u64,
    /// `#SBATCH --partition`, `--time` (e.g. `02:00:00`), `--cpus-per-task`.
    pub partition: Option<String>,
    pub time: Option<String>,
    pub cpus_per_task: u32,
    /// The `usar` binary the tasks run (absolute).
    pub usar: PathBuf,
}

/// What `DIR/slurm/job.json` records.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobRecord {
    pub campaign: String,
    pub design_hash: String,
    pub design_runs: u64,
    pub tasks: u64,
}

/// The files written.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SlurmScripts {
    pub array: PathBuf,
    pub merge: PathBuf,
    pub submit: PathBuf,
}

fn bad(message: String) -> CampaignError {
    CampaignError::Input(message)
}

/// A value for an `#SBATCH` line: `allowed` characters only (no space, quote or line break
/// that could end the directive or start a command).
fn directive(
    name: &str,
    value: &str,
    allowed: impl Fn(char) -> bool,
    expected: &str,
) -> Result<()> {
    if value.is_empty() || value.len() > 64 || !value.chars().all(allowed) {
        return Err(bad(format!("--{name} {value:?}: expected {expected}")));
    }
    Ok(())
}

/// `path` quoted for a POSIX shell.
fn quoted(path: &Path) -> String {
    format!("'{}'", path.display().to_string().replace('\'', r"'\''"))
}

impl SlurmJob {
    /// Checks the values that go into the scripts.
    pub fn check(&self) -> Result<()> {
        if !(1..=MAX_TASKS).contains(&self.tasks) {
            return Err(bad(format!(
                "--tasks {}: expected 1 to {MAX_TASKS}",
                self.tasks
            )));
        }
        if !(1..=1024).contains(&self.cpus_per_task) {
            return Err(bad(format!(
                "--cpus-per-task {}: expected 1 to 1024",
                self.cpus_per_task
            )));
        }
        if let Some(p) = &self.partition {
            let ok = |c: char| c.is_ascii_alphanumeric() || "_-.,".contains(c);
            directive(
                "partition",
                p,
                ok,
                "a partition name (letters, digits, _ - . ,)",
            )?;
        }
        if let Some(t) = &self.time {
            let ok = |c: char| c.is_ascii_digit() || c == ':' || c == '-';
            directive(
                "time",
                t,
                ok,
                "a SLURM time limit such as 02:00:00 or 1-12:00:00",
            )?;
        }
        for (name, p) in [("--out", &self.out), ("the usar binary", &self.usar)] {
            if !p.is_absolute() || p.to_str().is_none_or(|s| s.contains('\n')) {
                return Err(bad(format!(
                    "{name} {}: expected an absolute path without line breaks",
                    p.display()
                )));
            }
        }
        Ok(())
    }

    /// Writes the scripts for `design` (the design `campaign_text` parses to) into
    /// `DIR/slurm/`, replacing those of an earlier submission of the same design; a folder
    /// holding another design is refused.
    pub fn write(&self, design: &Design) -> Result<SlurmScripts> {
        self.check()?;
        let dir = self.out.join("slurm");
        let record = JobRecord {
            campaign: design.campaign.name.clone(),
            design_hash: design.hash.clone(),
            design_runs: design.len(),
            tasks: self.tasks,
        };
        if let Ok(old) = read_record(&self.out)
            && (old.design_hash != record.design_hash || old.tasks != record.tasks)
        {
            return Err(bad(format!(
                "{}: holds design {} in {} tasks, not design {} in {}; expected a new --out folder",
                self.out.display(),
                old.design_hash,
                old.tasks,
                record.design_hash,
                record.tasks
            )));
        }
        let io = |p: &Path, e: std::io::Error| bad(format!("{}: cannot write: {e}", p.display()));
        std::fs::create_dir_all(dir.join("logs")).map_err(|e| io(&dir, e))?;
        let campaign = dir.join("campaign.toml");
        usar_world::write_atomic(&campaign, self.campaign_text.as_bytes())?;
        let json =
            serde_json::to_vec_pretty(&record).map_err(|e| bad(format!("job record: {e}")))?;
        usar_world::write_atomic(&dir.join("job.json"), &json)?;

        let (usar, out, n) = (quoted(&self.usar), quoted(&self.out), self.tasks);
        let logs = self.out.join("slurm/logs");
        let mut header = format!(
            "#!/bin/bash\n#SBATCH --job-name=usar-{name}\n#SBATCH --array=1-{n}\n\
             #SBATCH --cpus-per-task={cpus}\n#SBATCH --output={log}/task-%a.out\n",
            name = record.campaign,
            cpus = self.cpus_per_task,
            log = logs.display(),
        );
        if let Some(p) = &self.partition {
            header.push_str(&format!("#SBATCH --partition={p}\n"));
        }
        if let Some(t) = &self.time {
            header.push_str(&format!("#SBATCH --time={t}\n"));
        }
        let array = format!(
            "{header}# Task K runs shard K of {n} into a result folder of its own; run again, it\n\
             # skips the runs its folder holds.\nset -euo pipefail\n\
             exec {usar} campaign run {campaign} --shard \"${{SLURM_ARRAY_TASK_ID}}/{n}\" \\\n  \
             --out {out}/shards/\"${{SLURM_ARRAY_TASK_ID}}\" --jobs \"${{SLURM_CPUS_PER_TASK:-1}}\" --json\n",
            campaign = quoted(&campaign),
        );
        let shards: Vec<String> = (1..=n).map(|k| format!("{out}/shards/{k}")).collect();
        let merge = format!(
            "#!/bin/bash\n#SBATCH --job-name=usar-{name}-merge\n#SBATCH --output={log}/merge.out\n{part}{time}\
             # Runs after every array task succeeded: the shards merged into DIR/merged (replaced\n\
             # whole, never left half written), then its report.\nset -euo pipefail\n\
             rm -rf {out}/merged.partial\n\
             {usar} campaign merge {shards} --out {out}/merged.partial --json\n\
             rm -rf {out}/merged\nmv {out}/merged.partial {out}/merged\n\
             {usar} campaign report {out}/merged --json > {out}/slurm/logs/report.json\n",
            name = record.campaign,
            log = logs.display(),
            part = self
                .partition
                .as_ref()
                .map_or(String::new(), |p| format!("#SBATCH --partition={p}\n")),
            time = self
                .time
                .as_ref()
                .map_or(String::new(), |t| format!("#SBATCH --time={t}\n")),
            shards = shards.join(" "),
        );
        let submit = format!(
            "#!/bin/sh\n# Submits the array and the merge that waits for it; prints both job ids.\n\
             # Run it again to resume: finished runs are skipped.\nset -eu\n\
             array=$(sbatch --parsable {dir}/array.sbatch)\narray=${{array%%;*}}\n\
             merge=$(sbatch --parsable --dependency=afterok:\"$array\" {dir}/merge.sbatch)\n\
             echo \"array ${{array}} merge ${{merge%%;*}}\"\n",
            dir = quoted(&dir),
        );
        let scripts = SlurmScripts {
            array: dir.join("array.sbatch"),
            merge: dir.join("merge.sbatch"),
            submit: dir.join("submit.sh"),
        };
        for (path, text) in [
            (&scripts.array, array),
            (&scripts.merge, merge),
            (&scripts.submit, submit),
        ] {
            usar_world::write_atomic(path, text.as_bytes())?;
            make_executable(path)?;
        }
        Ok(scripts)
    }
}

#[cfg(unix)]
fn make_executable(path: &Path) -> Result<()> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
        .map_err(|e| bad(format!("{}: cannot make executable: {e}", path.display())))
}

#[cfg(not(unix))]
fn make_executable(_: &Path) -> Result<()> {
    Ok(())
}

/// The job record of the submission in `out`.
pub fn read_record(out: &Path) -> Result<JobRecord> {
    let path = out.join("slurm/job.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        bad(format!(
            "{}: {e}; expected a folder written by `usar campaign slurm`",
            path.display()
        ))
    })?;
    serde_json::from_str(&text).map_err(|e| bad(format!("{}: {e}", path.display())))
}

/// Where a shard stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "state", rename_all = "snake_case")]
pub enum ShardState {
    /// Every run of the shard is in its database.
    Done,
    /// A task holds its folder now (`finished` of `runs` so far).
    Running { finished: u64, runs: u64 },
    /// Not running, some runs missing (a cancelled or failed task).
    Partial { finished: u64, runs: u64 },
    /// Not started.
    Missing,
}

/// A submission's state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Status {
    pub job: JobRecord,
    /// Per shard 1…N.
    pub shards: Vec<ShardState>,
    /// Whether `DIR/merged` holds every run of the design.
    pub merged: bool,
}

/// The runs of shard `k` of `n` in a design of `runs` runs (ids ≡ k − 1 mod n).
fn shard_runs(runs: u64, k: u64, n: u64) -> u64 {
    if k > runs { 0 } else { (runs - k) / n + 1 }
}

/// Reads the state of the submission in `out`: each shard's folder (locked by a running task,
/// or how many of its runs are stored) and the merged folder.
pub fn status(out: &Path) -> Result<Status> {
    let job = read_record(out)?;
    let finished = |dir: &Path| -> Result<u64> {
        let db = Store::path_in(dir);
        if !db.exists() {
            return Ok(0);
        }
        let store = Store::open(&db)?;
        if store.meta("design_hash")? != job.design_hash {
            return Err(bad(format!(
                "{}: holds another design than {}",
                dir.display(),
                job.design_hash
            )));
        }
        Ok(store.finished_ids()?.len() as u64)
    };
    let mut shards = Vec::new();
    for k in 1..=job.tasks {
        let dir = out.join("shards").join(k.to_string());
        let runs = shard_runs(job.design_runs, k, job.tasks);
        if !dir.is_dir() {
            shards.push(ShardState::Missing);
            continue;
        }
        // A running task holds the folder's lock exclusively.
        let running = FolderLock::shared(&dir).is_err();
        let done = finished(&dir)?;
        shards.push(match (running, done) {
            (true, _) => ShardState::Running {
                finished: done,
                runs,
            },
            (false, d) if d >= runs => ShardState::Done,
            (false, 0) if !Store::path_in(&dir).exists() => ShardState::Missing,
            (false, d) => ShardState::Partial { finished: d, runs },
        });
    }
    let merged_dir = out.join("merged");
    let merged = merged_dir.is_dir() && finished(&merged_dir)? >= job.design_runs;
    Ok(Status {
        job,
        shards,
        merged,
    })
}

#[cfg(test)]
mod tests {
    use super::shard_runs;

    #[test]
    fn the_shards_split_the_design_exactly() {
        for runs in 0..40 {
            for n in 1..9 {
                let total: u64 = (1..=n).map(|k| shard_runs(runs, k, n)).sum();
                assert_eq!(total, runs, "{runs} runs in {n} shards");
                for k in 1..=n {
                    let ids = (0..runs).filter(|id| id % n == k - 1).count() as u64;
                    assert_eq!(shard_runs(runs, k, n), ids);
                }
            }
        }
    }
}

//! The result database: one SQLite file per campaign output folder (`results.sqlite`).
//!
//! ```sql
//! meta(key TEXT PRIMARY KEY, value TEXT)   -- format=usar-campaign, version=1, design_hash,
//!                                          -- campaign (the campaign file as JSON)
//! runs(id INTEGER PRIMARY KEY, config_index, repetition, seed, config TEXT)  -- config as JSON
//! metrics(run_id, name, value, PRIMARY KEY (run_id, name))
//! series(run_id, name, x, value, PRIMARY KEY (run_id, name, x))
//! timings(run_id INTEGER PRIMARY KEY, wall_time_s)  -- not part of the results
//! ```
//!
//! A run is written in one transaction with its metrics and series, so after a crash (Ctrl-C,
//! `kill -9`, power loss: the rollback journal with `synchronous = FULL`) a run is either wholly
//! there or not at all, and resuming redoes exactly the missing runs. Runs that finish together
//! share a transaction (group commit), which keeps the cost of the fsync per run small.
//!
//! A database is opened only after checking that it is one of ours and holds the same design;
//! nothing is written to a file that fails the check.
//!
//! [`Store::open_or_create`] holds the folder's lock ([`crate::lock`]) for as long as the store
//! is open: a second `usar campaign run` on the folder is refused at once, and the database is
//! created (beside its final name, then renamed) by one process only. A `results.sqlite` that an
//! interrupted creation of an older version left behind — an empty file, or a database with
//! some of the tables but no design and no runs — holds nothing and is created anew.

use crate::design::{Config, Design};
use crate::error::{CampaignError, Result};
use crate::lock::FolderLock;
use crate::runner::RunOutput;
use rusqlite::{Connection, OpenFlags, params};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The database's file name inside a campaign output folder.
pub const DB_FILE: &str = "results.sqlite";
const FORMAT: &str = "usar-campaign";
const VERSION: &str = "1";

const SCHEMA: &str = "
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE runs (
    id INTEGER PRIMARY KEY,
    config_index INTEGER NOT NULL,
    repetition INTEGER NOT NULL,
    seed INTEGER NOT NULL,
    config TEXT NOT NULL
);
CREATE TABLE metrics (
    run_id INTEGER NOT NULL REFERENCES runs(id),
    name TEXT NOT NULL,
    value REAL NOT NULL,
    PRIMARY KEY (run_id, name)
);
CREATE TABLE series (
    run_id INTEGER NOT NULL REFERENCES runs(id),
    name TEXT NOT NULL,
    x REAL NOT NULL,
    value REAL NOT NULL,
    PRIMARY KEY (run_id, name, x)
);
CREATE TABLE timings (run_id INTEGER PRIMARY KEY, wall_time_s REAL NOT NULL);
";

/// A finished run as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct StoredRun {
    pub id: u64,
    pub config_index: usize,
    pub repetition: u32,
    pub seed: u64,
    pub config: Config,
    pub output: RunOutput,
}

/// An open result database.
pub struct Store {
    conn: Connection,
    path: PathBuf,
    /// The folder's lock, held while a run writes (dropped after the connection).
    _lock: Option<FolderLock>,
}

/// The tables of [`SCHEMA`].
const TABLES: [&str; 5] = ["meta", "runs", "metrics", "series", "timings"];
/// The `meta` keys a complete database has.
const META_KEYS: [&str; 4] = ["format", "version", "design_hash", "campaign"];

/// One finished run on its way to the database.
pub struct Finished {
    pub id: u64,
    pub config_index: usize,
    pub repetition: u32,
    pub seed: u64,
    pub config: Config,
    pub output: RunOutput,
    pub wall_time_s: f64,
}

impl Store {
    /// The database of campaign output folder `dir`.
    pub fn path_in(dir: &Path) -> PathBuf {
        dir.join(DB_FILE)
    }

    /// Opens the database in `dir` for `design`, creating it (and `dir`) if there is none. An
    /// existing file must be a usar campaign database of the same design. The store holds the
    /// folder's lock exclusively until it is dropped; a folder another process holds is
    /// refused at once (an input error naming that process).
    pub fn open_or_create(dir: &Path, design: &Design) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(|e| {
            CampaignError::Input(format!("{}: cannot create the folder: {e}", dir.display()))
        })?;
        let lock = FolderLock::exclusive(dir, "campaign run")?;
        let path = Self::path_in(dir);
        if path.exists() && left_by_interrupted_creation(&path) {
            remove_database(&path)?;
        }
        if path.exists() {
            let mut store = Self::open(&path)?;
            store._lock = Some(lock);
            let found = store.meta("design_hash")?;
            if found != design.hash {
                let name = store.campaign_name().unwrap_or_else(|_| "?".into());
                return Err(CampaignError::Input(format!(
                    "{}: holds results of another design (campaign `{name}`, design {found}), expected design {} of campaign `{}`; use another --out folder",
                    path.display(),
                    design.hash,
                    design.campaign.name
                )));
            }
            return Ok(store);
        }
        let mut store = Self::create(&path, design)?;
        store._lock = Some(lock);
        Ok(store)
    }

    /// Creates a new database at `path` for `design`.
    pub fn create(path: &Path, design: &Design) -> Result<Self> {
        let campaign = serde_json::to_string(&design.campaign).expect("campaign serializes");
        Self::create_with(path, &design.hash, &campaign)
    }

    /// Creates a database at `path` holding no runs yet: written beside it and renamed into
    /// place, so a crash never leaves a database without its design.
    fn create_with(path: &Path, design_hash: &str, campaign_json: &str) -> Result<Self> {
        let tmp = path.with_extension("sqlite.partial");
        // Left by a killed creation (the caller holds the folder's lock: nobody is writing it).
        remove_database(&tmp)?;
        {
            let conn = Connection::open(&tmp).map_err(|e| CampaignError::db(&tmp, e))?;
            let db = |e| CampaignError::db(&tmp, e);
            conn.execute_batch(&format!("PRAGMA journal_mode = DELETE; BEGIN; {SCHEMA}"))
                .map_err(db)?;
            conn.execute(
                "INSERT INTO meta VALUES ('format', ?1), ('version', ?2), ('design_hash', ?3), \
                 ('campaign', ?4)",
                params![FORMAT, VERSION, design_hash, campaign_json],
            )
            .map_err(db)?;
            conn.execute_batch("COMMIT").map_err(db)?;
        }
        std::fs::rename(&tmp, path).map_err(|e| {
            CampaignError::Input(format!("{}: cannot move into place: {e}", path.display()))
        })?;
        Self::open(path)
    }

    /// Opens an existing database after checking it is ours. Opening rolls back a transaction
    /// a killed process left half-written (SQLite's hot journal), so a crashed campaign can be
    /// reported, merged or resumed at once; nothing else is written.
    pub fn open(path: &Path) -> Result<Self> {
        if !path.is_file() {
            return Err(CampaignError::Input(format!(
                "{}: no such result database, expected the output folder of `usar campaign run`",
                path.display()
            )));
        }
        if std::fs::metadata(path).is_ok_and(|m| m.len() == 0) {
            return Err(CampaignError::Input(format!(
                "{}: an empty file (left by an interrupted `usar campaign run`), expected a result database; run the campaign again to create it",
                path.display()
            )));
        }
        let flags = OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let conn =
            Connection::open_with_flags(path, flags).map_err(|e| foreign(path, &e.to_string()))?;
        let store = Store {
            conn,
            path: path.to_path_buf(),
            _lock: None,
        };
        let format: std::result::Result<String, _> =
            store
                .conn
                .query_row("SELECT value FROM meta WHERE key = 'format'", [], |r| {
                    r.get(0)
                });
        match format {
            Ok(f) if f == FORMAT => {}
            Ok(f) => return Err(foreign(path, &format!("format `{f}`"))),
            Err(e) => return Err(foreign(path, &e.to_string())),
        }
        let version = store.meta("version")?;
        if version != VERSION {
            return Err(CampaignError::Input(format!(
                "{}: result database version {version}, expected version {VERSION}",
                path.display()
            )));
        }
        let check: String = store
            .conn
            .query_row("PRAGMA quick_check", [], |r| r.get(0))
            .map_err(|e| foreign(path, &e.to_string()))?;
        if check != "ok" {
            return Err(foreign(path, &format!("integrity check: {check}")));
        }
        store.pragmas()?;
        Ok(store)
    }

    fn pragmas(&self) -> Result<()> {
        self.conn
            .execute_batch("PRAGMA journal_mode = DELETE; PRAGMA synchronous = FULL;")
            .map_err(|e| CampaignError::db(&self.path, e))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A `meta` value.
    pub fn meta(&self, key: &str) -> Result<String> {
        self.conn
            .query_row("SELECT value FROM meta WHERE key = ?1", [key], |r| r.get(0))
            .map_err(|e| {
                CampaignError::Input(format!(
                    "{}: meta `{key}` unreadable ({e}), expected a usar campaign database",
                    self.path.display()
                ))
            })
    }

    /// The campaign file stored with the results.
    pub fn campaign(&self) -> Result<crate::design::CampaignFile> {
        let text = self.meta("campaign")?;
        serde_json::from_str(&text).map_err(|e| {
            CampaignError::Input(format!(
                "{}: stored campaign unreadable ({e})",
                self.path.display()
            ))
        })
    }

    fn campaign_name(&self) -> Result<String> {
        Ok(self.campaign()?.name)
    }

    /// Ids of the runs already stored.
    pub fn finished_ids(&self) -> Result<Vec<u64>> {
        let mut stmt = self
            .conn
            .prepare("SELECT id FROM runs ORDER BY id")
            .map_err(|e| CampaignError::db(&self.path, e))?;
        stmt.query_map([], |r| r.get::<_, i64>(0))
            .and_then(|rows| rows.map(|r| r.map(|v| v as u64)).collect())
            .map_err(|e| CampaignError::db(&self.path, e))
    }

    /// Writes finished runs in one transaction: all of them, or (on error) none.
    pub fn insert(&mut self, runs: &[Finished]) -> Result<()> {
        let path = self.path.clone();
        let db = |e| CampaignError::db(&path, e);
        let tx = self.conn.transaction().map_err(db)?;
        {
            let mut run_stmt = tx
                .prepare_cached("INSERT INTO runs VALUES (?1, ?2, ?3, ?4, ?5)")
                .map_err(db)?;
            let mut metric_stmt = tx
                .prepare_cached("INSERT INTO metrics VALUES (?1, ?2, ?3)")
                .map_err(db)?;
            let mut series_stmt = tx
                .prepare_cached("INSERT INTO series VALUES (?1, ?2, ?3, ?4)")
                .map_err(db)?;
            let mut timing_stmt = tx
                .prepare_cached("INSERT INTO timings VALUES (?1, ?2)")
                .map_err(db)?;
            for r in runs {
                let config = serde_json::to_string(&r.config).expect("config serializes");
                run_stmt
                    .execute(params![
                        r.id as i64,
                        r.config_index as i64,
                        r.repetition,
                        r.seed as i64,
                        config
                    ])
                    .map_err(db)?;
                for (name, value) in &r.output.metrics {
                    metric_stmt
                        .execute(params![r.id as i64, name, value])
                        .map_err(db)?;
                }
                for point in &r.output.series {
                    for (name, value) in &point.values {
                        series_stmt
                            .execute(params![r.id as i64, name, point.x, value])
                            .map_err(db)?;
                    }
                }
                timing_stmt
                    .execute(params![r.id as i64, r.wall_time_s])
                    .map_err(db)?;
            }
        }
        tx.commit().map_err(db)
    }

    /// Every stored run with its metrics and series, in id order.
    pub fn runs(&self) -> Result<Vec<StoredRun>> {
        let db = |e| CampaignError::db(&self.path, e);
        let mut runs: BTreeMap<u64, StoredRun> = BTreeMap::new();
        let mut stmt = self
            .conn
            .prepare("SELECT id, config_index, repetition, seed, config FROM runs ORDER BY id")
            .map_err(db)?;
        let rows = stmt
            .query_map([], |r| {
                Ok((
                    r.get::<_, i64>(0)? as u64,
                    r.get::<_, i64>(1)? as usize,
                    r.get::<_, u32>(2)?,
                    r.get::<_, i64>(3)? as u64,
                    r.get::<_, String>(4)?,
                ))
            })
            .map_err(db)?;
        for row in rows {
            let (id, config_index, repetition, seed, config) = row.map_err(db)?;
            let config: Config = serde_json::from_str(&config).map_err(|e| {
                CampaignError::Input(format!(
                    "{}: run {id}: config unreadable ({e})",
                    self.path.display()
                ))
            })?;
            runs.insert(
                id,
                StoredRun {
                    id,
                    config_index,
                    repetition,
                    seed,
                    config,
                    output: RunOutput::default(),
                },
            );
        }
        let mut stmt = self
            .conn
            .prepare("SELECT run_id, name, value FROM metrics ORDER BY run_id, name")
            .map_err(db)?;
        let rows = stmt
            .query_map([], |r| {
                Ok((
                    r.get::<_, i64>(0)? as u64,
                    r.get::<_, String>(1)?,
                    r.get::<_, f64>(2)?,
                ))
            })
            .map_err(db)?;
        for row in rows {
            let (id, name, value) = row.map_err(db)?;
            if let Some(run) = runs.get_mut(&id) {
                run.output.metrics.insert(name, value);
            }
        }
        let mut stmt = self
            .conn
            .prepare("SELECT run_id, name, x, value FROM series ORDER BY run_id, x, name")
            .map_err(db)?;
        let rows = stmt
            .query_map([], |r| {
                Ok((
                    r.get::<_, i64>(0)? as u64,
                    r.get::<_, String>(1)?,
                    r.get::<_, f64>(2)?,
                    r.get::<_, f64>(3)?,
                ))
            })
            .map_err(db)?;
        for row in rows {
            let (id, name, x, value) = row.map_err(db)?;
            if let Some(run) = runs.get_mut(&id) {
                let series = &mut run.output.series;
                if series.last().is_none_or(|p| p.x != x) {
                    series.push(crate::runner::SeriesPoint {
                        x,
                        values: BTreeMap::new(),
                    });
                }
                series
                    .last_mut()
                    .expect("pushed")
                    .values
                    .insert(name, value);
            }
        }
        Ok(runs.into_values().collect())
    }

    /// A digest of the results (meta, runs, metrics, series; not the timings): two databases
    /// with equal digests hold the same results.
    pub fn results_digest(&self) -> Result<String> {
        let runs = self.runs()?;
        let text = format!(
            "{}|{}|{:?}",
            self.meta("design_hash")?,
            self.meta("campaign")?,
            runs
        );
        Ok(format!(
            "{:016x}",
            text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
                (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
            })
        ))
    }
}

/// Whether `path` is what an interrupted creation left: an empty file, or a SQLite database
/// holding none but (some of) our tables, no results in them, and not every `meta` key of a complete
/// database. Anything else — a complete database, a foreign one, garbage — is not.
fn left_by_interrupted_creation(path: &Path) -> bool {
    match std::fs::metadata(path) {
        Ok(m) if m.len() == 0 => return true,
        Ok(_) => {}
        Err(_) => return false,
    }
    let flags = OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let Ok(conn) = Connection::open_with_flags(path, flags) else {
        return false;
    };
    let tables: rusqlite::Result<Vec<String>> = conn
        .prepare("SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%'")
        .and_then(|mut s| s.query_map([], |r| r.get(0))?.collect());
    let Ok(tables) = tables else {
        return false;
    };
    if !tables.iter().all(|t| TABLES.contains(&t.as_str())) {
        return false;
    }
    // No results in any table (the names are ours, checked above).
    for t in tables.iter().filter(|t| *t != "meta") {
        let rows: rusqlite::Result<i64> =
            conn.query_row(&format!("SELECT count(*) FROM {t}"), [], |r| r.get(0));
        if rows != Ok(0) {
            return false;
        }
    }
    if !tables.iter().any(|t| t == "meta") {
        return true;
    }
    let keys: rusqlite::Result<i64> = conn.query_row(
        &format!(
            "SELECT count(DISTINCT key) FROM meta WHERE key IN ({})",
            META_KEYS.map(|k| format!("'{k}'")).join(", ")
        ),
        [],
        |r| r.get(0),
    );
    keys.is_ok_and(|n| n < META_KEYS.len() as i64)
}

/// Removes a database file and its rollback journal (neither need exist).
fn remove_database(path: &Path) -> Result<()> {
    let mut journal = path.as_os_str().to_owned();
    journal.push("-journal");
    for p in [path.to_path_buf(), PathBuf::from(journal)] {
        match std::fs::remove_file(&p) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => {
                return Err(CampaignError::Input(format!(
                    "{}: cannot remove: {e}",
                    p.display()
                )));
            }
        }
    }
    Ok(())
}

fn foreign(path: &Path, why: &str) -> CampaignError {
    CampaignError::Input(format!(
        "{}: not a usar campaign result database ({why}); expected a `results.sqlite` written by `usar campaign run`",
        path.display()
    ))
}

/// Merges the result databases of `inputs` (shards of one design) into a new database at
/// `out_dir`. Refuses mismatched designs and runs that differ between inputs, and inputs or an
/// output folder another process is using ([`crate::lock`]); writes to a temporary file
/// renamed into place, so a failed merge leaves no database behind.
pub fn merge(inputs: &[PathBuf], out_dir: &Path) -> Result<(usize, u64)> {
    let Some(first) = inputs.first() else {
        return Err(CampaignError::Input(
            "campaign merge: no input folders, expected at least one".into(),
        ));
    };
    let out = Store::path_in(out_dir);
    if out.exists() {
        return Err(CampaignError::Input(format!(
            "{}: already exists; merge writes a new result database, expected an empty --out folder",
            out.display()
        )));
    }
    // Each input is read under its folder's shared lock: a shard still being run is refused.
    let stores: Vec<Store> = inputs
        .iter()
        .map(|d| {
            let lock = if d.is_dir() {
                FolderLock::shared(d)?
            } else {
                None
            };
            let mut store = Store::open(&Store::path_in(d))?;
            store._lock = lock;
            Ok(store)
        })
        .collect::<Result<_>>()?;
    let hash = stores[0].meta("design_hash")?;
    let campaign = stores[0].meta("campaign")?;
    for (s, dir) in stores.iter().zip(inputs).skip(1) {
        let h = s.meta("design_hash")?;
        if h != hash {
            return Err(CampaignError::Input(format!(
                "{}: design {h}, expected design {hash} of {}: results of different campaigns cannot be merged",
                dir.display(),
                first.display()
            )));
        }
    }
    let mut merged: BTreeMap<u64, (StoredRun, f64)> = BTreeMap::new();
    for (s, dir) in stores.iter().zip(inputs) {
        let timings: BTreeMap<u64, f64> = {
            let mut stmt = s
                .conn
                .prepare("SELECT run_id, wall_time_s FROM timings")
                .map_err(|e| CampaignError::db(s.path(), e))?;
            stmt.query_map([], |r| {
                Ok((r.get::<_, i64>(0)? as u64, r.get::<_, f64>(1)?))
            })
            .and_then(|rows| rows.collect::<std::result::Result<_, _>>())
            .map_err(|e| CampaignError::db(s.path(), e))?
        };
        for run in s.runs()? {
            if let Some((existing, _)) = merged.get(&run.id) {
                if existing != &run {
                    return Err(CampaignError::Input(format!(
                        "{}: run {} differs from the same run in another input; refusing to merge",
                        dir.display(),
                        run.id
                    )));
                }
                continue;
            }
            let t = timings.get(&run.id).copied().unwrap_or(0.0);
            merged.insert(run.id, (run, t));
        }
    }
    std::fs::create_dir_all(out_dir).map_err(|e| {
        CampaignError::Input(format!(
            "{}: cannot create the folder: {e}",
            out_dir.display()
        ))
    })?;
    // The new folder is ours alone while the database is written; checked again under the lock.
    let _lock = FolderLock::exclusive(out_dir, "campaign merge")?;
    if out.exists() {
        return Err(CampaignError::Input(format!(
            "{}: already exists; merge writes a new result database, expected an empty --out folder",
            out.display()
        )));
    }
    // Built beside the final name and renamed: a failed merge leaves no database behind.
    let tmp = out_dir.join(format!("{DB_FILE}.merging"));
    let _ = std::fs::remove_file(&tmp);
    let mut store = Store::create_with(&tmp, &hash, &campaign)?;
    let finished: Vec<Finished> = merged
        .into_values()
        .map(|(r, wall_time_s)| Finished {
            id: r.id,
            config_index: r.config_index,
            repetition: r.repetition,
            seed: r.seed,
            config: r.config,
            output: r.output,
            wall_time_s,
        })
        .collect();
    store.insert(&finished)?;
    drop(store);
    std::fs::rename(&tmp, &out).map_err(|e| {
        CampaignError::Input(format!("{}: cannot move into place: {e}", out.display()))
    })?;
    Ok((inputs.len(), finished.len() as u64))
}

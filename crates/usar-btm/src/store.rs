//! A BTM in SQLite (paper 004 §II: the map database), written while the robot drives.
//!
//! ```sql
//! meta(key PRIMARY KEY, value)     -- format = usar-btm, schema_version = 1
//! nodes(id PRIMARY KEY, x_m, y_m, kind, subtype, slope_inclination_rad, step_height_m,
//!       max_robot_inclination_rad, operator_note, extra)         -- extra: JSON object
//! links(id PRIMARY KEY, start, end, searched, direction_rad, length_m, min_width_m,
//!       max_inclination_rad, max_step_m, extra)
//! ```
//!
//! Every [`BtmStore::put_node`] / [`BtmStore::put_link`] is its own transaction (rollback
//! journal, `synchronous = FULL`): a crash loses at most the update in flight. A newer schema
//! version is refused with a clear error; columns added by later versions are ignored by
//! this reader, and their attributes travel in `extra`.

use crate::model::{Btm, Extra, Link, Node};
use rusqlite::{Connection, OptionalExtension, params};
use std::path::{Path, PathBuf};

pub const FORMAT: &str = "usar-btm";
pub const SCHEMA_VERSION: i64 = 1;

const SCHEMA: &str = "
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE nodes (
    id INTEGER PRIMARY KEY,
    x_m REAL NOT NULL,
    y_m REAL NOT NULL,
    kind TEXT NOT NULL,
    subtype TEXT,
    slope_inclination_rad REAL,
    step_height_m REAL,
    max_robot_inclination_rad REAL,
    operator_note TEXT,
    extra TEXT NOT NULL DEFAULT '{}'
);
CREATE TABLE links (
    id INTEGER PRIMARY KEY,
    start INTEGER NOT NULL REFERENCES nodes(id),
    end INTEGER REFERENCES nodes(id),
    searched INTEGER NOT NULL,
    direction_rad REAL NOT NULL,
    length_m REAL,
    min_width_m REAL,
    max_inclination_rad REAL,
    max_step_m REAL,
    extra TEXT NOT NULL DEFAULT '{}'
);
";

/// Why a BTM database could not be used.
#[derive(Debug, thiserror::Error)]
pub enum BtmError {
    #[error("{path}: not a BTM database ({why}); expected a file written by `usar btm build`")]
    Foreign { path: String, why: String },
    #[error("{path}: BTM schema version {found}, expected {expected} or older")]
    Version {
        path: String,
        found: i64,
        expected: i64,
    },
    #[error("{path}: {message}")]
    Database { path: String, message: String },
    #[error("{path}: {what}: {message}")]
    Invalid {
        path: String,
        what: String,
        message: String,
    },
}

/// An open BTM database.
pub struct BtmStore {
    conn: Connection,
    path: PathBuf,
}

fn extra_json(extra: &Extra) -> String {
    serde_json::to_string(extra).expect("JSON values serialize")
}

fn insert_node(conn: &Connection, n: &Node) -> rusqlite::Result<()> {
    conn.execute(
        "INSERT OR REPLACE INTO nodes VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)",
        params![
            n.id,
            n.x_m,
            n.y_m,
            n.kind,
            n.subtype,
            n.slope_inclination_rad,
            n.step_height_m,
            n.max_robot_inclination_rad,
            n.operator_note,
            extra_json(&n.extra)
        ],
    )
    .map(|_| ())
}

fn insert_link(conn: &Connection, l: &Link) -> rusqlite::Result<()> {
    conn.execute(
        "INSERT OR REPLACE INTO links VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)",
        params![
            l.id,
            l.start,
            l.end,
            l.searched,
            l.direction_rad,
            l.length_m,
            l.min_width_m,
            l.max_inclination_rad,
            l.max_step_m,
            extra_json(&l.extra)
        ],
    )
    .map(|_| ())
}

impl BtmStore {
    fn db(&self, e: rusqlite::Error) -> BtmError {
        BtmError::Database {
            path: self.path.display().to_string(),
            message: e.to_string(),
        }
    }

    /// Creates an empty BTM database at `path`, replacing nothing: the file must not exist.
    pub fn create(path: &Path) -> Result<Self, BtmError> {
        let fail = |message: String| BtmError::Database {
            path: path.display().to_string(),
            message,
        };
        if path.exists() {
            return Err(fail("already exists; expected a new file".into()));
        }
        let conn = Connection::open(path).map_err(|e| fail(e.to_string()))?;
        conn.execute_batch(&format!(
            "PRAGMA journal_mode = DELETE; PRAGMA synchronous = FULL; BEGIN; {SCHEMA}
             INSERT INTO meta VALUES ('format', '{FORMAT}'), ('schema_version', '{SCHEMA_VERSION}');
             COMMIT;"
        ))
        .map_err(|e| fail(e.to_string()))?;
        Ok(Self {
            conn,
            path: path.to_path_buf(),
        })
    }

    /// Opens an existing BTM database after checking its format and schema version.
    pub fn open(path: &Path) -> Result<Self, BtmError> {
        let foreign = |why: String| BtmError::Foreign {
            path: path.display().to_string(),
            why,
        };
        if !path.is_file() {
            return Err(foreign("no such file".into()));
        }
        let conn = Connection::open(path).map_err(|e| foreign(e.to_string()))?;
        let meta = |key: &str| -> Result<Option<String>, BtmError> {
            conn.query_row("SELECT value FROM meta WHERE key = ?1", [key], |r| r.get(0))
                .optional()
                .map_err(|e| foreign(e.to_string()))
        };
        match meta("format")? {
            Some(f) if f == FORMAT => {}
            other => return Err(foreign(format!("format {other:?}"))),
        }
        let version: i64 = meta("schema_version")?
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| foreign("no schema_version".into()))?;
        if version > SCHEMA_VERSION {
            return Err(BtmError::Version {
                path: path.display().to_string(),
                found: version,
                expected: SCHEMA_VERSION,
            });
        }
        conn.execute_batch("PRAGMA synchronous = FULL;")
            .map_err(|e| foreign(e.to_string()))?;
        Ok(Self {
            conn,
            path: path.to_path_buf(),
        })
    }

    /// Inserts or replaces a node (one transaction).
    pub fn put_node(&self, n: &Node) -> Result<(), BtmError> {
        insert_node(&self.conn, n).map_err(|e| self.db(e))
    }

    /// Inserts or replaces a link (one transaction).
    pub fn put_link(&self, l: &Link) -> Result<(), BtmError> {
        insert_link(&self.conn, l).map_err(|e| self.db(e))
    }

    /// Deletes a link (one transaction): an un-searched link found to be the far end of a
    /// link just driven when a loop closes. Deleting a missing id is not an error.
    pub fn delete_link(&self, id: u32) -> Result<(), BtmError> {
        self.conn
            .execute("DELETE FROM links WHERE id = ?1", [id])
            .map(|_| ())
            .map_err(|e| self.db(e))
    }

    /// Writes a whole map in one transaction (import, merge).
    pub fn put_all(&mut self, btm: &Btm) -> Result<(), BtmError> {
        let path = self.path.display().to_string();
        let db = |e: rusqlite::Error| BtmError::Database {
            path: path.clone(),
            message: e.to_string(),
        };
        let tx = self.conn.transaction().map_err(db)?;
        for n in &btm.nodes {
            insert_node(&tx, n).map_err(db)?;
        }
        for l in &btm.links {
            insert_link(&tx, l).map_err(db)?;
        }
        tx.commit().map_err(db)
    }

    /// Reads the whole map, nodes and links by id.
    pub fn load(&self) -> Result<Btm, BtmError> {
        let extra = |id: u32, what: &str, text: String| -> Result<Extra, BtmError> {
            serde_json::from_str(&text).map_err(|e| BtmError::Invalid {
                path: self.path.display().to_string(),
                what: format!("{what} {id} column extra"),
                message: format!("found {text:?}, expected a JSON object ({e})"),
            })
        };
        let mut stmt = self
            .conn
            .prepare(
                "SELECT id, x_m, y_m, kind, subtype, slope_inclination_rad, step_height_m, \
                 max_robot_inclination_rad, operator_note, extra FROM nodes ORDER BY id",
            )
            .map_err(|e| self.db(e))?;
        let rows: Vec<(Node, String)> = stmt
            .query_map([], |r| {
                Ok((
                    Node {
                        id: r.get(0)?,
                        x_m: r.get(1)?,
                        y_m: r.get(2)?,
                        kind: r.get(3)?,
                        subtype: r.get(4)?,
                        slope_inclination_rad: r.get(5)?,
                        step_height_m: r.get(6)?,
                        max_robot_inclination_rad: r.get(7)?,
                        operator_note: r.get(8)?,
                        extra: Extra::new(),
                    },
                    r.get(9)?,
                ))
            })
            .and_then(|rows| rows.collect())
            .map_err(|e| self.db(e))?;
        let mut btm = Btm::default();
        for (mut n, e) in rows {
            n.extra = extra(n.id, "node", e)?;
            btm.nodes.push(n);
        }
        let mut stmt = self
            .conn
            .prepare(
                "SELECT id, start, end, searched, direction_rad, length_m, min_width_m, \
                 max_inclination_rad, max_step_m, extra FROM links ORDER BY id",
            )
            .map_err(|e| self.db(e))?;
        let rows: Vec<(Link, String)> = stmt
            .query_map([], |r| {
                Ok((
                    Link {
                        id: r.get(0)?,
                        start: r.get(1)?,
                        end: r.get(2)?,
                        searched: r.get(3)?,
                        direction_rad: r.get(4)?,
                        length_m: r.get(5)?,
                        min_width_m: r.get(6)?,
                        max_inclination_rad: r.get(7)?,
                        max_step_m: r.get(8)?,
                        extra: Extra::new(),
                    },
                    r.get(9)?,
                ))
            })
            .and_then(|rows| rows.collect())
            .map_err(|e| self.db(e))?;
        for (mut l, e) in rows {
            l.extra = extra(l.id, "link", e)?;
            btm.links.push(l);
        }
        Ok(btm)
    }
}

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
use crate::validate::Invalid;
use rusqlite::types::Value;
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
    /// A map that reads but fails its checks ([`crate::validate`]).
    #[error("{path}: {problem}")]
    Check {
        path: String,
        problem: crate::validate::Invalid,
    },
    /// A `.btmb` file that is not a binary BTM.
    #[error("{path}: {problem}")]
    Wire {
        path: String,
        problem: crate::wire::DecodeError,
    },
    /// A file name whose extension names no BTM format (or one that is written only).
    #[error("{path}: {message}")]
    Format { path: String, message: String },
    /// A file could not be read or written (size limits included).
    #[error(transparent)]
    File(#[from] usar_world::WorldError),
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

    /// Reads the whole map, nodes and links by id, and checks it ([`crate::validate`]): a
    /// value of the wrong type, a non-finite or out-of-range measure, a malformed kind, a link
    /// to a missing node is an [`BtmError::Invalid`] naming the node or link and the field.
    pub fn load(&self) -> Result<Btm, BtmError> {
        let mut btm = Btm::default();
        let nodes = self.count("nodes", crate::validate::MAX_NODES)?;
        btm.nodes.reserve(nodes);
        self.rows(
            "SELECT id, x_m, y_m, kind, subtype, slope_inclination_rad, step_height_m, \
             max_robot_inclination_rad, operator_note, extra FROM nodes ORDER BY id",
            "node",
            |v| {
                let id = v.id(0, "id")?;
                v.named(format!("node {id}"));
                btm.nodes.push(Node {
                    id,
                    x_m: v.real(1, "x_m")?,
                    y_m: v.real(2, "y_m")?,
                    kind: v.text(3, "kind")?,
                    subtype: v.opt_text(4, "subtype")?,
                    slope_inclination_rad: v.opt_real(5, "slope_inclination_rad")?,
                    step_height_m: v.opt_real(6, "step_height_m")?,
                    max_robot_inclination_rad: v.opt_real(7, "max_robot_inclination_rad")?,
                    operator_note: v.opt_text(8, "operator_note")?,
                    extra: v.extra(9)?,
                });
                Ok(())
            },
        )?;
        let links = self.count("links", crate::validate::MAX_LINKS)?;
        btm.links.reserve(links);
        self.rows(
            "SELECT id, start, end, searched, direction_rad, length_m, min_width_m, \
             max_inclination_rad, max_step_m, extra FROM links ORDER BY id",
            "link",
            |v| {
                let id = v.id(0, "id")?;
                v.named(format!("link {id}"));
                btm.links.push(Link {
                    id,
                    start: v.id(1, "start")?,
                    end: match v.is_null(2) {
                        true => None,
                        false => Some(v.id(2, "end")?),
                    },
                    searched: v.flag(3, "searched")?,
                    direction_rad: v.real(4, "direction_rad")?,
                    length_m: v.opt_real(5, "length_m")?,
                    min_width_m: v.opt_real(6, "min_width_m")?,
                    max_inclination_rad: v.opt_real(7, "max_inclination_rad")?,
                    max_step_m: v.opt_real(8, "max_step_m")?,
                    extra: v.extra(9)?,
                });
                Ok(())
            },
        )?;
        crate::validate::check(&btm).map_err(|e| self.invalid(e))?;
        Ok(btm)
    }

    fn invalid(&self, e: Invalid) -> BtmError {
        BtmError::Invalid {
            path: self.path.display().to_string(),
            what: format!("{} field `{}`", e.what, e.field),
            message: format!("found {}, expected {}", e.found, e.expected),
        }
    }

    /// The rows of `table`, refused above `limit` before any is read.
    fn count(&self, table: &str, limit: usize) -> Result<usize, BtmError> {
        let n: i64 = self
            .conn
            .query_row(&format!("SELECT count(*) FROM {table}"), [], |r| r.get(0))
            .map_err(|e| self.db(e))?;
        if n as u64 > limit as u64 {
            return Err(self.invalid(
                Invalid::new(format!("table {table}"), "rows", n.to_string())
                    .expected(format!("at most {limit}")),
            ));
        }
        Ok(n as usize)
    }

    /// Runs `sql` and hands each row's values to `each`.
    fn rows(
        &self,
        sql: &str,
        what: &str,
        mut each: impl FnMut(&mut Values) -> Result<(), Invalid>,
    ) -> Result<(), BtmError> {
        let mut stmt = self.conn.prepare(sql).map_err(|e| self.db(e))?;
        let columns = stmt.column_count();
        let mut rows = stmt.query([]).map_err(|e| self.db(e))?;
        let mut index = 0usize;
        while let Some(row) = rows.next().map_err(|e| self.db(e))? {
            index += 1;
            let values = (0..columns)
                .map(|i| row.get::<_, Value>(i))
                .collect::<rusqlite::Result<Vec<_>>>()
                .map_err(|e| self.db(e))?;
            let mut v = Values {
                what: format!("{what} in row {index}"),
                values,
            };
            each(&mut v).map_err(|e| self.invalid(e))?;
        }
        Ok(())
    }
}

/// One row's values, converted with errors naming the node or link and the column.
struct Values {
    what: String,
    values: Vec<Value>,
}

fn found(v: &Value) -> String {
    match v {
        Value::Null => "NULL".into(),
        Value::Integer(i) => i.to_string(),
        Value::Real(f) => f.to_string(),
        Value::Text(t) => format!("text {}", crate::validate::quoted(t)),
        Value::Blob(b) => format!("a blob of {} bytes", b.len()),
    }
}

impl Values {
    fn named(&mut self, what: String) {
        self.what = what;
    }

    fn bad(&self, i: usize, field: &'static str, expected: &str) -> Invalid {
        Invalid::new(self.what.clone(), field, found(&self.values[i])).expected(expected)
    }

    fn is_null(&self, i: usize) -> bool {
        matches!(self.values[i], Value::Null)
    }

    fn id(&self, i: usize, field: &'static str) -> Result<u32, Invalid> {
        match self.values[i] {
            Value::Integer(v) => u32::try_from(v).ok(),
            _ => None,
        }
        .ok_or_else(|| self.bad(i, field, "an id from 0 to 4294967295"))
    }

    fn opt_real(&self, i: usize, field: &'static str) -> Result<Option<f64>, Invalid> {
        match self.values[i] {
            Value::Null => Ok(None),
            Value::Real(v) => Ok(Some(v)),
            Value::Integer(v) => Ok(Some(v as f64)),
            _ => Err(self.bad(i, field, "a number or NULL")),
        }
    }

    fn real(&self, i: usize, field: &'static str) -> Result<f64, Invalid> {
        match self.values[i] {
            Value::Real(v) => Ok(v),
            Value::Integer(v) => Ok(v as f64),
            _ => Err(self.bad(i, field, "a number")),
        }
    }

    fn opt_text(&self, i: usize, field: &'static str) -> Result<Option<String>, Invalid> {
        match &self.values[i] {
            Value::Null => Ok(None),
            Value::Text(t) => Ok(Some(t.clone())),
            _ => Err(self.bad(i, field, "text or NULL")),
        }
    }

    fn text(&self, i: usize, field: &'static str) -> Result<String, Invalid> {
        match &self.values[i] {
            Value::Text(t) => Ok(t.clone()),
            _ => Err(self.bad(i, field, "text")),
        }
    }

    fn flag(&self, i: usize, field: &'static str) -> Result<bool, Invalid> {
        match self.values[i] {
            Value::Integer(0) => Ok(false),
            Value::Integer(1) => Ok(true),
            _ => Err(self.bad(i, field, "0 or 1")),
        }
    }

    fn extra(&self, i: usize) -> Result<Extra, Invalid> {
        match &self.values[i] {
            Value::Text(t) => serde_json::from_str(t).ok(),
            _ => None,
        }
        .ok_or_else(|| self.bad(i, "extra", "a JSON object"))
    }
}

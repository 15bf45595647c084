//! The policy file: a trained USAR hierarchy, versioned JSON, written atomically.
//!
//! ```text
//! { "format": "usar-maxq-policy", "version": 1,
//!   "training": { "seed": 1, "trials": 1800 },
//!   "learner": { nodes, params, v, c, c_tilde, steps } }
//! ```
//!
//! Loading checks the format, the version and that the task graph and every table have the
//! sizes of [`RescueHierarchy`]; floats round-trip exactly, so a reloaded policy acts exactly
//! as the one saved.

use crate::hierarchy::RescueHierarchy;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use usar_maxq::{Hierarchy, MaxqQ, NodeKind};

pub const FORMAT: &str = "usar-maxq-policy";
pub const VERSION: u32 = 1;

/// Why a policy file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum PolicyError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file could not be read, or is past the input limits ([`usar_world::limits`]).
    #[error(transparent)]
    File(#[from] usar_world::WorldError),
    /// The file is not valid policy JSON.
    #[error("{path}: not a policy file: {message}")]
    Parse { path: PathBuf, message: String },
    /// A field holds something other than what this program writes.
    #[error("{path}: {field} is {found}, expected {expected}")]
    Mismatch {
        path: PathBuf,
        field: String,
        found: String,
        expected: String,
    },
}

/// Where the policy came from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainingInfo {
    pub seed: u64,
    pub trials: u32,
}

/// The file's content.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PolicyFile {
    pub format: String,
    pub version: u32,
    pub training: TrainingInfo,
    pub learner: MaxqQ,
}

impl PolicyFile {
    pub fn new(learner: MaxqQ, training: TrainingInfo) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            training,
            learner,
        }
    }

    /// Writes atomically (temporary file and rename).
    pub fn save(&self, path: &Path) -> Result<(), PolicyError> {
        let text = serde_json::to_string(self).map_err(|e| PolicyError::Parse {
            path: path.into(),
            message: e.to_string(),
        })?;
        usar_world::write_atomic(path, text.as_bytes()).map_err(|e| PolicyError::Io {
            path: path.into(),
            source: std::io::Error::other(e.to_string()),
        })
    }

    /// Reads and checks a policy file.
    pub fn load(path: &Path) -> Result<Self, PolicyError> {
        let text = usar_world::limits::read_text(path)?;
        let file: PolicyFile = serde_json::from_str(&text).map_err(|e| PolicyError::Parse {
            path: path.into(),
            message: e.to_string(),
        })?;
        file.check(path)?;
        Ok(file)
    }

    fn check(&self, path: &Path) -> Result<(), PolicyError> {
        let mismatch = |field: &str, found: String, expected: String| PolicyError::Mismatch {
            path: path.into(),
            field: field.into(),
            found,
            expected,
        };
        if self.format != FORMAT {
            return Err(mismatch(
                "format",
                format!("{:?}", self.format),
                format!("{FORMAT:?}"),
            ));
        }
        if self.version != VERSION {
            return Err(mismatch(
                "version",
                self.version.to_string(),
                VERSION.to_string(),
            ));
        }
        if let Err(e) = self.learner.params.validate() {
            return Err(mismatch(
                &format!("learner.params.{}", e.field),
                e.found,
                e.expected,
            ));
        }
        let h = RescueHierarchy::new();
        let nodes = h.nodes();
        let l = &self.learner;
        if l.nodes != nodes {
            return Err(mismatch(
                "learner.nodes",
                format!("{} nodes", l.nodes.len()),
                format!(
                    "the USAR task graph ({})",
                    nodes
                        .iter()
                        .map(|n| n.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
        if l.v.len() != nodes.len() || l.c.len() != nodes.len() || l.c_tilde.len() != nodes.len() {
            return Err(mismatch(
                "learner tables",
                format!("{}/{}/{} tables", l.v.len(), l.c.len(), l.c_tilde.len()),
                format!("{} of each", nodes.len()),
            ));
        }
        for (k, n) in nodes.iter().enumerate() {
            let (v_len, c_len) = match &n.kind {
                NodeKind::Primitive { .. } => (n.states, 0),
                NodeKind::Composite { children } => (0, n.states * children.len()),
            };
            for (field, table, len) in [
                ("v", &l.v[k], v_len),
                ("c", &l.c[k], c_len),
                ("c_tilde", &l.c_tilde[k], c_len),
            ] {
                if table.values.len() != len || table.written.len() != len {
                    return Err(mismatch(
                        &format!("learner.{field}[{}]", n.name),
                        format!("{} values", table.values.len()),
                        format!("{len}"),
                    ));
                }
                if let Some(bad) = table.values.iter().find(|v| !v.is_finite()) {
                    return Err(mismatch(
                        &format!("learner.{field}[{}]", n.name),
                        format!("the value {bad}"),
                        "finite numbers".into(),
                    ));
                }
            }
        }
        Ok(())
    }
}

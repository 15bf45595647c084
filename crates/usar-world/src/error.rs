//! Errors of the world crate: every one names the file, and the line or field, that was wrong.

use std::path::Path;

/// Why a scene, map or scenario could not be read, validated or written.
#[derive(Debug, thiserror::Error)]
pub enum WorldError {
    /// The file could not be opened, read or written.
    #[error("{path}: {io}")]
    Io { path: String, io: std::io::Error },
    /// The file's syntax is wrong at a known place (`location` is e.g. "line 3" or "byte 17").
    #[error("{path}: {location}: {message}")]
    Syntax {
        path: String,
        location: String,
        message: String,
    },
    /// A field holds a value outside what the format allows.
    #[error("{path}: field `{field}`: found {found}, expected {expected}")]
    InvalidField {
        path: String,
        field: String,
        found: String,
        expected: String,
    },
    /// The file is of a known format but a version this build cannot read.
    #[error("{path}: unsupported {format} version {found}, expected {expected}")]
    UnsupportedVersion {
        path: String,
        format: String,
        found: String,
        expected: String,
    },
    /// A file that another file refers to is missing or unreadable.
    #[error("{path}: field `{field}` refers to {target}, which cannot be read: {io}")]
    MissingReference {
        path: String,
        field: String,
        target: String,
        io: std::io::Error,
    },
    /// An image could not be decoded.
    #[error("{path}: cannot decode image: {message}")]
    Image { path: String, message: String },
}

impl WorldError {
    pub fn io(path: &Path, io: std::io::Error) -> Self {
        WorldError::Io {
            path: path.display().to_string(),
            io,
        }
    }

    pub fn invalid(
        path: &Path,
        field: impl Into<String>,
        found: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        WorldError::InvalidField {
            path: path.display().to_string(),
            field: field.into(),
            found: found.to_string(),
            expected: expected.into(),
        }
    }

    pub fn syntax(path: &Path, location: impl Into<String>, message: impl Into<String>) -> Self {
        WorldError::Syntax {
            path: path.display().to_string(),
            location: location.into(),
            message: message.into(),
        }
    }
}

pub type Result<T, E = WorldError> = std::result::Result<T, E>;

//! Why a campaign could not be read, run, merged or reported. Every message names the file and
//! the field, line or run, what was found and what was expected.

/// An error of the experiment engine.
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// The campaign file (or a result database) has a problem a user can fix: bad TOML, an
    /// unknown factor or key, a wrong value, a foreign or mismatched database.
    #[error("{0}")]
    Input(String),
    /// The database failed while working (disk full, I/O error).
    #[error("{path}: database error: {message}")]
    Database { path: String, message: String },
    /// A run failed: because of its configuration (`RunError::Input`) or on its own.
    #[error("run {run} ({config}) failed: {error}")]
    Run {
        run: u64,
        config: String,
        error: crate::runner::RunError,
    },
    /// Writing an output file failed.
    #[error(transparent)]
    Write(#[from] usar_world::WorldError),
    /// A plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] usar_plot::PlotError),
}

impl CampaignError {
    /// Whether the error comes from the input (exit code 2) rather than from the work itself.
    pub fn is_input(&self) -> bool {
        match self {
            CampaignError::Input(_) => true,
            CampaignError::Run { error, .. } => error.is_input(),
            _ => false,
        }
    }

    pub(crate) fn db(path: &std::path::Path, e: rusqlite::Error) -> Self {
        CampaignError::Database {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    }
}

pub type Result<T> = std::result::Result<T, CampaignError>;

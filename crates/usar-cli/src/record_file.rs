//! `--record FILE.mcap`: the recording is written as `FILE.partial` and named FILE only once
//! it is complete; a run that fails leaves no file behind.

use crate::failure::{CmdResult, bad_input};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use usar_record::{RecordError, Recording};
use usar_world::partial_path;

/// A recording being written.
pub struct RecordFile {
    path: PathBuf,
    partial: PathBuf,
}

impl RecordFile {
    /// Opens `FILE.partial` for `path`; a file that cannot be made is bad input.
    pub fn create(path: &Path) -> CmdResult<(Self, Recording<BufWriter<File>>)> {
        let partial = partial_path(path);
        let file = File::create(&partial)
            .map_err(|e| bad_input(anyhow::anyhow!("--record {}: {e}", path.display())))?;
        let me = Self {
            path: path.to_path_buf(),
            partial,
        };
        let recording = Recording::new(BufWriter::new(file)).map_err(|e| me.fail(e))?;
        Ok((me, recording))
    }

    fn fail(&self, e: RecordError) -> anyhow::Error {
        let _ = std::fs::remove_file(&self.partial);
        anyhow::anyhow!("--record {}: {e}", self.path.display())
    }

    /// Names the file once its recorder `finished` without an error; the messages written.
    pub fn done(self, finished: Result<u64, RecordError>) -> CmdResult<u64> {
        let messages = finished.map_err(|e| self.fail(e))?;
        std::fs::rename(&self.partial, &self.path)?;
        Ok(messages)
    }

    /// The run failed: no file is left.
    pub fn abandon(self) {
        let _ = std::fs::remove_file(&self.partial);
    }
}

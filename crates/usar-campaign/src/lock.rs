//! Advisory locks on campaign folders, so that two processes never write one folder at once.
//!
//! A folder's lock is the file [`LOCK_FILE`] in it, locked with the operating system's advisory
//! file lock (`flock` on Unix, `LockFileEx` on Windows). The kernel releases the lock when its
//! holder ends, however it ends (`kill -9`, power loss), so a lock is never left stale; the file
//! itself stays and is reused. Locks are taken without waiting: a folder in use is refused at
//! once, naming the process that holds it (its pid and command, which the holder writes into
//! the lock file).
//!
//! - `usar campaign run` holds the result folder's lock exclusively for the whole run,
//!   including the creation of `results.sqlite`.
//! - `usar campaign merge` holds its new folder's lock exclusively and a shared lock on each
//!   input folder (a shard still being run is refused rather than merged half done).
//! - `usar campaign report` holds the lock of `DIR/report/` exclusively (one report at a time
//!   writes there); it reads the results committed so far, also while a run is going on.

use crate::error::{CampaignError, Result};
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// The lock file's name inside a locked folder.
pub const LOCK_FILE: &str = ".usar-campaign.lock";

/// A held lock on a folder; released when dropped.
#[derive(Debug)]
pub struct FolderLock {
    file: File,
    path: PathBuf,
    exclusive: bool,
}

impl FolderLock {
    /// Takes `dir`'s lock exclusively for `command` (e.g. `campaign run`), or refuses at once
    /// if another process holds it. `dir` must exist.
    pub fn exclusive(dir: &Path, command: &str) -> Result<Self> {
        let path = dir.join(LOCK_FILE);
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| cannot(&path, e))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Err(busy(dir, &path)),
            Err(TryLockError::Error(e)) => return Err(cannot(&path, e)),
        }
        // Who holds it, for the message of a process refused: written over the old text (never
        // leaving the file empty), then cut to length; readers take the first line.
        let text = format!("{} {command}\n", std::process::id());
        let written = file
            .seek(SeekFrom::Start(0))
            .and_then(|_| file.write_all(text.as_bytes()))
            .and_then(|_| file.set_len(text.len() as u64));
        written.map_err(|e| cannot(&path, e))?;
        Ok(Self {
            file,
            path,
            exclusive: true,
        })
    }

    /// Takes `dir`'s lock shared (for reading), or refuses at once if a process holds it
    /// exclusively. `None` when there is no lock file and none can be made (a read-only
    /// folder, which no process can be writing results into either).
    pub fn shared(dir: &Path) -> Result<Option<Self>> {
        let path = dir.join(LOCK_FILE);
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .or_else(|_| File::open(&path));
        let Ok(file) = file else {
            return Ok(None);
        };
        match file.try_lock_shared() {
            Ok(()) => Ok(Some(Self {
                file,
                path,
                exclusive: false,
            })),
            Err(TryLockError::WouldBlock) => Err(busy(dir, &path)),
            Err(TryLockError::Error(e)) => Err(cannot(&path, e)),
        }
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        if self.exclusive {
            // No holder any more; the lock itself is released when the file closes.
            let _ = self.file.set_len(0);
        }
    }
}

/// The process holding `path` as its lock file says: `pid N, usar campaign run`.
fn holder(path: &Path) -> Option<String> {
    let mut text = String::new();
    File::open(path).ok()?.read_to_string(&mut text).ok()?;
    let line = text.lines().next()?.trim();
    let (pid, command) = line.split_once(' ')?;
    let pid: u32 = pid.parse().ok()?;
    Some(format!("`usar {}` (pid {pid})", command.trim()))
}

fn busy(dir: &Path, path: &Path) -> CampaignError {
    let who = holder(path).unwrap_or_else(|| "usar process".into());
    CampaignError::Input(format!(
        "{}: another {who} is using this folder; wait for it to finish or use another folder",
        dir.display()
    ))
}

fn cannot(path: &Path, e: std::io::Error) -> CampaignError {
    CampaignError::Input(format!("{}: cannot lock the folder: {e}", path.display()))
}

//! Resource limits on what an input may make us allocate or do.
//!
//! A small file can declare a huge thing: a 76 KB 1-bit PNG of 20 000 × 20 000 pixels, a scene
//! whose compressed layers inflate to gigabytes, a robot with a hundred million laser beams, a
//! training run of four billion trials. Every loader checks what a file *declares* against these
//! limits **before** allocating for it, and refuses with an error naming the file and field.
//!
//! The limits are process-wide (a program sets them once, at start, from its command line:
//! `usar --max-cells … --max-file-mb … --max-beams … --max-trials …`); a library user may call
//! [`set_limits`] the same way. The defaults are far above every real map and robot we know of:
//!
//! | limit | default | what it bounds |
//! |---|---|---|
//! | `max_cells` | 25 000 000 (5 000 × 5 000, 500 m × 500 m at 0.1 m) | cells of any grid read from a file (image, scene, MovingAI map) |
//! | `max_file_bytes` | 128 MiB | bytes read from any one input file |
//! | `max_beams` | 65 536 | beams of one laser or depth sensor |
//! | `max_trials` | 1 000 000 (paper 000 trains 1 800) | trials of one training run |

use crate::error::{Result, WorldError};
use std::io::Read;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// The limits in force (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Cells of one grid read from a file.
    pub max_cells: u64,
    /// Bytes read from one input file.
    pub max_file_bytes: u64,
    /// Beams of one range sensor.
    pub max_beams: u64,
    /// Trials of one training run.
    pub max_trials: u64,
}

impl Limits {
    /// The defaults of the table above.
    pub const DEFAULT: Limits = Limits {
        max_cells: 25_000_000,
        max_file_bytes: 128 << 20,
        max_beams: 65_536,
        max_trials: 1_000_000,
    };
}

impl Default for Limits {
    fn default() -> Self {
        Self::DEFAULT
    }
}

static MAX_CELLS: AtomicU64 = AtomicU64::new(Limits::DEFAULT.max_cells);
static MAX_FILE_BYTES: AtomicU64 = AtomicU64::new(Limits::DEFAULT.max_file_bytes);
static MAX_BEAMS: AtomicU64 = AtomicU64::new(Limits::DEFAULT.max_beams);
static MAX_TRIALS: AtomicU64 = AtomicU64::new(Limits::DEFAULT.max_trials);

/// Sets the process-wide limits (call once, before loading anything).
pub fn set_limits(limits: Limits) {
    MAX_CELLS.store(limits.max_cells, Ordering::Relaxed);
    MAX_FILE_BYTES.store(limits.max_file_bytes, Ordering::Relaxed);
    MAX_BEAMS.store(limits.max_beams, Ordering::Relaxed);
    MAX_TRIALS.store(limits.max_trials, Ordering::Relaxed);
}

/// The limits in force.
pub fn limits() -> Limits {
    Limits {
        max_cells: MAX_CELLS.load(Ordering::Relaxed),
        max_file_bytes: MAX_FILE_BYTES.load(Ordering::Relaxed),
        max_beams: MAX_BEAMS.load(Ordering::Relaxed),
        max_trials: MAX_TRIALS.load(Ordering::Relaxed),
    }
}

/// Checks a grid of `width × height` cells declared by `field` of `path` against `max_cells`.
pub fn check_cells(path: &Path, field: &str, width: u64, height: u64) -> Result<()> {
    let max = limits().max_cells;
    let cells = width.saturating_mul(height);
    if cells > max {
        return Err(WorldError::invalid(
            path,
            field,
            format!("{width}×{height} = {cells} cells"),
            format!("at most {max} cells (raise the limit with --max-cells)"),
        ));
    }
    Ok(())
}

/// Reads a whole input file, refusing one longer than `max_file_bytes` before reading it (a
/// regular file) or once that many bytes have come (a pipe, a device such as `/dev/zero`).
pub fn read_file(path: &Path) -> Result<Vec<u8>> {
    let max = limits().max_file_bytes;
    let too_large = |found: String| {
        WorldError::invalid(
            path,
            "file size",
            found,
            format!("at most {max} bytes (raise the limit with --max-file-mb)"),
        )
    };
    let file = std::fs::File::open(path).map_err(|e| WorldError::io(path, e))?;
    let meta = file.metadata().map_err(|e| WorldError::io(path, e))?;
    if meta.is_dir() {
        return Err(WorldError::io(
            path,
            std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a folder, not a file"),
        ));
    }
    if meta.is_file() && meta.len() > max {
        return Err(too_large(format!("{} bytes", meta.len())));
    }
    // Grown by hand, doubling but never past max + 1: `read_to_end` would double a full
    // 128 MiB buffer to 256 MiB to learn that one more byte came.
    let cap = usize::try_from(max.saturating_add(1)).unwrap_or(usize::MAX);
    let mut bytes = Vec::with_capacity(if meta.is_file() {
        usize::try_from(meta.len()).map_or(cap, |n| n.saturating_add(1).min(cap))
    } else {
        CHUNK
    });
    let mut reader = file.take(max.saturating_add(1));
    let mut chunk = vec![0u8; CHUNK];
    loop {
        let n = match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(WorldError::io(path, e)),
        };
        if bytes.len() + n > bytes.capacity() {
            let want = bytes
                .capacity()
                .saturating_mul(2)
                .clamp(bytes.len() + n, cap);
            bytes.reserve_exact(want - bytes.len());
        }
        bytes.extend_from_slice(&chunk[..n]);
    }
    if bytes.len() as u64 > max {
        return Err(too_large(format!("more than {max} bytes")));
    }
    Ok(bytes)
}

/// The read size of [`read_file`].
const CHUNK: usize = 64 << 10;

/// [`read_file`] as UTF-8 text; invalid UTF-8 is an error naming the byte where it starts.
pub fn read_text(path: &Path) -> Result<String> {
    String::from_utf8(read_file(path)?).map_err(|e| {
        WorldError::syntax(
            path,
            format!("byte {}", e.utf8_error().valid_up_to()),
            "invalid UTF-8, expected a text file",
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_past_the_limit_is_refused_and_one_within_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        std::fs::write(&path, b"hello").unwrap();
        assert_eq!(read_text(&path).unwrap(), "hello");
        std::fs::write(&path, [0xff, 0xfe]).unwrap();
        assert!(read_text(&path).unwrap_err().to_string().contains("byte 0"));
        let err = read_file(dir.path()).unwrap_err().to_string();
        assert!(err.contains("folder"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_device_stops_at_the_limit() {
        // /dev/zero never ends; the default limit is read, then refused (128 MiB: fast).
        let err = read_file(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(
            err.contains("file size") && err.contains("--max-file-mb"),
            "{err}"
        );
    }

    #[test]
    fn cells_past_the_limit_name_the_field() {
        let err = check_cells(Path::new("m.png"), "image size", 20_000, 20_000)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("m.png") && err.contains("400000000 cells"),
            "{err}"
        );
        assert!(check_cells(Path::new("m.png"), "image size", 5_000, 5_000).is_ok());
    }
}

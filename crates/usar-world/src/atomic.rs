//! Writing files so that a reader never sees half of one: write a temporary file beside the
//! target, flush it, then rename it over the target.

use crate::error::{Result, WorldError};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Where a file written while work goes on (a map built as a robot drives, a recording) lives
/// until it is complete: `out` with `.partial` appended, renamed to `out` at the end, so that
/// nothing half written ever carries the final name.
pub fn partial_path(out: &Path) -> PathBuf {
    let mut name = out.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

/// Writes `bytes` to `path` atomically (temporary file in the same folder, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{file_name}.tmp-{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(io) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(WorldError::io(path, io));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn write_atomic_replaces_the_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        super::write_atomic(&path, b"one").unwrap();
        super::write_atomic(&path, b"two").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"two");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn write_atomic_into_a_missing_folder_fails_with_the_path() {
        let err = super::write_atomic(std::path::Path::new("/nonexistent/x/a.txt"), b"x");
        assert!(
            err.unwrap_err()
                .to_string()
                .contains("/nonexistent/x/a.txt")
        );
    }
}

//! Atomic file output: write to a temporary file in the destination's directory, then rename it
//! over the destination (a rename within one file system is atomic on POSIX).

use std::path::{Path, PathBuf};

use super::OutputError;

/// Calls `write` with a temporary path beside `path`, then renames the result to `path`. On
/// failure the temporary file is removed and `path` is left as it was.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    let io = |source| OutputError::Io { path: path.display().to_string(), source };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let temporary = temporary_path(path);
    let result = write(&temporary).and_then(|()| std::fs::rename(&temporary, path).map_err(io));
    if result.is_err() {
        // Best effort: the temporary file may not exist if `write` failed before creating it.
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Writes `text` to `path` atomically.
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    write_atomically(path, |tmp| {
        std::fs::write(tmp, text)
            .map_err(|source| OutputError::Io { path: path.display().to_string(), source })
    })
}

/// `dir/.name.tmp-PID.ext`, keeping the extension so encoders that look at it still work.
fn temporary_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().map_or_else(|| "output".into(), |s| s.to_string_lossy().into_owned());
    let ext = path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    path.with_file_name(format!(".{stem}.tmp-{}{ext}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_write_leaves_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("image.exr");
        let result = write_atomically(&target, |tmp| {
            std::fs::write(tmp, b"partial").unwrap();
            Err(OutputError::Codec { path: "x".into(), message: "simulated crash".into() })
        });
        assert!(result.is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn successful_write_lands_under_the_final_name() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("sub/image.png");
        write_atomically(&target, |tmp| {
            std::fs::write(tmp, b"ok").map_err(|source| OutputError::Io { path: "t".into(), source })
        })
        .unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"ok");
        assert_eq!(std::fs::read_dir(target.parent().unwrap()).unwrap().count(), 1);
    }
}

//! Atomic file output: write to a temporary file in the target's directory, then rename, so a
//! reader never sees a half-written file and a failed write leaves the old file intact.

use std::io::Write;
use std::path::{Path, PathBuf};

/// A temporary path beside `path` that keeps its extension (libraries pick formats by it).
pub fn temp_path_for(path: &Path) -> PathBuf {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    dir.join(format!(".{name}.tmp-{}{ext}", std::process::id()))
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = temp_path_for(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Checks that a file can be created in `path`'s directory (by creating and removing a probe).
pub fn check_dir_writable(path: &Path) -> std::io::Result<()> {
    let probe = temp_path_for(path);
    std::fs::File::create(&probe)?;
    std::fs::remove_file(&probe)
}

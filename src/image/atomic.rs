//! Atomic replacement of an output file: write a temporary beside it, then rename.
//!
//! `rename(2)` within one directory replaces the destination atomically, so a reader sees
//! either the old file or the complete new one, and a failed write never touches the old file.

use std::fs::{self, OpenOptions};
use std::io::ErrorKind;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::ImageError;

/// Distinguishes temporaries of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A reserved temporary file beside the destination; removed on drop unless committed.
pub(crate) struct TempFile {
    temp: PathBuf,
    dest: PathBuf,
    committed: bool,
}

/// The directory holding `dest` (`.` for a bare file name).
fn parent_dir(dest: &Path) -> PathBuf {
    match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `.stem.tmp-<pid>-<n>.ext`: hidden, unique, and ending in the real extension so that
/// extension-driven writers (OIIO) pick the right format.
fn temp_name(dest: &Path, n: u64) -> PathBuf {
    let stem = dest.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = dest.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    let name = format!(".{stem}.tmp-{}-{n}{ext}", std::process::id());
    parent_dir(dest).join(name)
}

impl TempFile {
    /// Creates (exclusively) an empty temporary file beside `dest`.
    pub(crate) fn create(dest: &Path) -> Result<Self, ImageError> {
        let dir = parent_dir(dest);
        if !dir.exists() {
            return Err(ImageError::MissingDirectory { path: dest.to_path_buf(), dir });
        }
        if !dir.is_dir() {
            return Err(ImageError::Unwritable { path: dest.to_path_buf(), dir, reason: "not a directory".into() });
        }
        loop {
            let temp = temp_name(dest, COUNTER.fetch_add(1, Ordering::Relaxed));
            match OpenOptions::new().write(true).create_new(true).open(&temp) {
                Ok(_) => return Ok(Self { temp, dest: dest.to_path_buf(), committed: false }),
                Err(e) if e.kind() == ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(ImageError::Unwritable { path: dest.to_path_buf(), dir, reason: e.to_string() }),
            }
        }
    }

    /// Where the writer should put the data.
    pub(crate) fn path(&self) -> &Path {
        &self.temp
    }

    /// Renames the temporary over the destination.
    pub(crate) fn commit(mut self) -> Result<(), ImageError> {
        fs::rename(&self.temp, &self.dest).map_err(|e| ImageError::Write {
            path: self.dest.clone(),
            reason: format!("cannot move the finished file into place: {e}"),
        })?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.committed {
            // Best effort: the write already failed, and that error is what gets reported.
            let _ = fs::remove_file(&self.temp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temp_name_keeps_extension_and_directory() {
        let t = temp_name(Path::new("out/dir/render.exr"), 7);
        assert_eq!(t.parent().unwrap(), Path::new("out/dir"));
        let name = t.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".render.tmp-"), "{name}");
        assert!(name.ends_with("-7.exr"), "{name}");
        assert_eq!(temp_name(Path::new("a.png"), 0).parent().unwrap(), Path::new("."));
    }
}

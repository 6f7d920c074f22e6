//! Atomic file output: write to a temporary file in the target's directory, then rename, so a
//! reader never sees a half-written file and a failed write leaves the old file intact.
//! `rename(2)` within one directory replaces the destination atomically.

use std::fs::{self, OpenOptions};
use std::io::{ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Distinguishes temporaries of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// The temporaries not yet committed or dropped, for [`remove_live_temporaries`].
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Removes every temporary this process is still writing (best effort), for a process about
/// to exit before its writes finish: a rename that has already happened left a whole file, one
/// that has not finds no temporary and fails.
pub fn remove_live_temporaries() {
    remove_live_temporaries_where(|_| true);
}

/// [`remove_live_temporaries`] for the temporaries `doomed` picks.
fn remove_live_temporaries_where(doomed: impl Fn(&Path) -> bool) {
    live().retain(|temp| {
        let doomed = doomed(temp);
        if doomed {
            let _ = fs::remove_file(temp);
        }
        !doomed
    });
}

/// The directory holding `dest` (`.` for a bare file name).
pub fn parent_dir(dest: &Path) -> PathBuf {
    match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `.stem.tmp-<pid>-<n>.ext`: hidden, unique, and ending in the real extension so that
/// extension-driven writers (OIIO, plotters) pick the right format.
fn temp_name(dest: &Path, n: u64) -> PathBuf {
    let stem = dest.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = dest.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    parent_dir(dest).join(format!(".{stem}.tmp-{}-{n}{ext}", std::process::id()))
}

/// A reserved temporary file beside the destination; removed on drop unless committed.
pub struct TempFile {
    temp: PathBuf,
    dest: PathBuf,
    committed: bool,
}

impl TempFile {
    /// Creates (exclusively) an empty temporary file beside `dest`.
    pub fn create(dest: &Path) -> std::io::Result<Self> {
        loop {
            let temp = temp_name(dest, COUNTER.fetch_add(1, Ordering::Relaxed));
            match OpenOptions::new().write(true).create_new(true).open(&temp) {
                Ok(_) => {
                    live().push(temp.clone());
                    return Ok(Self { temp, dest: dest.to_path_buf(), committed: false });
                }
                Err(e) if e.kind() == ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    /// Where the writer should put the data.
    pub fn path(&self) -> &Path {
        &self.temp
    }

    /// Renames the temporary over the destination.
    pub fn commit(mut self) -> std::io::Result<()> {
        fs::rename(&self.temp, &self.dest)?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        live().retain(|t| t != &self.temp);
        if !self.committed {
            // Best effort: the write already failed, and that error is what gets reported.
            let _ = fs::remove_file(&self.temp);
        }
    }
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let temp = TempFile::create(path)?;
    let mut f = fs::File::create(temp.path())?;
    f.write_all(bytes)?;
    f.sync_all()?;
    temp.commit()
}

/// Checks that a file can be created in `path`'s directory (by creating and removing a probe).
pub fn check_dir_writable(path: &Path) -> std::io::Result<()> {
    TempFile::create(path).map(drop)
}

/// Memory the system could give this process now without swapping [bytes] (Linux's
/// `MemAvailable`), `None` where unknown.
pub fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
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

    #[test]
    fn failed_write_leaves_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("prism-io-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let dest = dir.join("out.txt");
        write_atomic(&dest, b"old").unwrap();
        let temp = TempFile::create(&dest).unwrap();
        drop(temp); // a writer that failed before commit
        assert_eq!(fs::read(&dest).unwrap(), b"old");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1, "temporary left behind");
        write_atomic(&dest, b"new").unwrap();
        assert_eq!(fs::read(&dest).unwrap(), b"new");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn live_temporaries_are_removed_on_request_and_then_cannot_commit() {
        let dir = std::env::temp_dir().join(format!("prism-io-live-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let dest = dir.join("out.txt");
        let temp = TempFile::create(&dest).unwrap();
        fs::write(temp.path(), b"half").unwrap();
        // (Only this test's: the others of this process run beside it.)
        remove_live_temporaries_where(|t| t.starts_with(&dir));
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0, "temporary left behind");
        assert!(temp.commit().is_err() && !dest.exists());
        fs::remove_dir_all(&dir).unwrap();
    }
}

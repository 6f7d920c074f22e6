//! What identifies the files a scene reads: size and a hash of the contents of each, so that a
//! cached result or a saved film is only reused while every input is byte for byte the same.

use std::io::Read;
use std::path::{Path, PathBuf};

/// One input file's identity.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct InputStamp {
    /// The file, relative to the directory the stamps were taken against when it lies below it.
    pub file: String,
    /// Size [bytes]; `None` if the file cannot be read.
    pub bytes: Option<u64>,
    /// 64-bit FNV-1a hash of the contents, in hex; `None` if the file cannot be read.
    pub fnv1a: Option<String>,
}

/// Stamps of `files` (in their order), each named relative to `base` where it lies below it, so
/// the same scene read through different paths (another machine, another working directory)
/// has the same stamps.
pub fn input_stamps(files: &[PathBuf], base: &Path) -> Vec<InputStamp> {
    files
        .iter()
        .map(|f| {
            let file = f.strip_prefix(base).unwrap_or(f).display().to_string();
            match content_hash(f) {
                Ok((bytes, h)) => InputStamp { file, bytes: Some(bytes), fnv1a: Some(format!("{h:016x}")) },
                Err(_) => InputStamp { file, bytes: None, fnv1a: None },
            }
        })
        .collect()
}

/// (size [bytes], 64-bit FNV-1a hash) of the file at `path`, read in blocks.
fn content_hash(path: &Path) -> std::io::Result<(u64, u64)> {
    let mut f = std::fs::File::open(path)?;
    let mut buf = vec![0u8; 1 << 16];
    let (mut bytes, mut h) = (0u64, FNV_OFFSET);
    loop {
        let n = f.read(&mut buf)?;
        if n == 0 {
            return Ok((bytes, h));
        }
        bytes += n as u64;
        h = fnv1a(h, &buf[..n]);
    }
}

/// FNV-1a's 64-bit offset basis and prime (Fowler, Noll, Vo).
const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0100_0000_01b3;

fn fnv1a(h: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(h, |h, &b| (h ^ b as u64).wrapping_mul(FNV_PRIME))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        // From the FNV reference test suite (isthe.com/chongo/tech/comp/fnv).
        assert_eq!(fnv1a(FNV_OFFSET, b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(FNV_OFFSET, b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(FNV_OFFSET, b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn stamps_follow_contents_not_paths() {
        let dir = std::env::temp_dir().join(format!("prism-stamps-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let f = dir.join("sub").join("mesh.obj");
        std::fs::write(&f, "v 0 0 0\n").unwrap();
        let a = input_stamps(std::slice::from_ref(&f), &dir);
        assert_eq!(a[0].file, Path::new("sub").join("mesh.obj").display().to_string());
        assert_eq!(a[0].bytes, Some(8));
        // The same bytes written again: the same stamp; one byte changed: another hash.
        std::fs::write(&f, "v 0 0 0\n").unwrap();
        assert_eq!(input_stamps(std::slice::from_ref(&f), &dir), a);
        std::fs::write(&f, "v 0 0 1\n").unwrap();
        let b = input_stamps(std::slice::from_ref(&f), &dir);
        assert_eq!(b[0].bytes, a[0].bytes);
        assert_ne!(b[0].fnv1a, a[0].fnv1a);
        let missing = input_stamps(&[dir.join("none.ply")], &dir);
        assert_eq!((missing[0].bytes.as_ref(), missing[0].fnv1a.as_ref()), (None, None));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

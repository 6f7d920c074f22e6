//! Reading the files a scene names (included scene text, meshes), transparently decompressing
//! gzip (RFC 1952) ones: pbrt-v4 scenes ship `.pbrt.gz` includes and `.ply.gz` meshes. A file is
//! gzip when it starts with gzip's magic bytes, whatever its name.

use flate2::read::MultiGzDecoder;
use std::io::Read;
use std::path::Path;

/// The two bytes every gzip member starts with.
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// Largest decompressed size accepted [bytes]: a bound against decompression bombs, far above
/// any real scene's meshes (pbrt-v4's largest test scenes hold a few GB).
pub const MAX_DECOMPRESSED_BYTES: u64 = 64 << 30;

/// Files from this size on are read by every thread, a chunk each at a time [bytes].
const PARALLEL_READ_BYTES: u64 = 64 << 20;

/// The contents of `path`, decompressed when it is gzip.
pub fn read(path: &Path) -> std::io::Result<Vec<u8>> {
    let bytes = read_file(path)?;
    if !bytes.starts_with(&GZIP_MAGIC) {
        return Ok(bytes);
    }
    gunzip(&bytes, decompression_limit())
}

/// The bytes of `path`; a big file is read in chunks by all threads, so that the copies out of
/// the page cache and the first touches of the buffer's pages run side by side.
#[cfg(unix)]
fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    use rayon::prelude::*;
    use std::os::unix::fs::FileExt;
    const CHUNK: usize = 8 << 20;
    let file = std::fs::File::open(path)?;
    let len = file.metadata()?.len();
    if len < PARALLEL_READ_BYTES {
        return std::fs::read(path);
    }
    let len = usize::try_from(len).map_err(|_| std::io::ErrorKind::OutOfMemory)?;
    // A failed reservation is an error; the zeroed buffer is then mapped, not written, until read into.
    Vec::<u8>::new().try_reserve_exact(len).map_err(|_| std::io::ErrorKind::OutOfMemory)?;
    let mut bytes = vec![0u8; len];
    bytes.par_chunks_mut(CHUNK).enumerate().try_for_each(|(i, chunk)| file.read_exact_at(chunk, (i * CHUNK) as u64))?;
    // A file that grew since its size was read is read again whole.
    if file.read_at(&mut [0u8], len as u64)? != 0 {
        return std::fs::read(path);
    }
    Ok(bytes)
}

#[cfg(not(unix))]
fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    std::fs::read(path)
}

/// The decompressed size accepted now: [`MAX_DECOMPRESSED_BYTES`], or less when less memory is
/// available (the output is held in memory whole).
fn decompression_limit() -> u64 {
    crate::io::available_memory().map_or(MAX_DECOMPRESSED_BYTES, |m| m.min(MAX_DECOMPRESSED_BYTES))
}

/// Decompresses every gzip member of `bytes`, refusing output beyond `limit` bytes and buffers
/// that cannot be allocated (an error, never an abort).
fn gunzip(bytes: &[u8], limit: u64) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    out.try_reserve(bytes.len().saturating_mul(4)).map_err(|_| std::io::ErrorKind::OutOfMemory)?;
    let mut decoder = MultiGzDecoder::new(bytes).take(limit + 1);
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        let n = decoder.read(&mut chunk).map_err(|e| std::io::Error::new(e.kind(), format!("gzip: {e}")))?;
        if n == 0 {
            break;
        }
        if out.len() as u64 + n as u64 > limit {
            return Err(std::io::Error::other(format!(
                "gzip: decompresses to more than {limit} bytes (the lesser of {MAX_DECOMPRESSED_BYTES} and the memory \
                 available)"
            )));
        }
        out.try_reserve(n).map_err(|_| std::io::ErrorKind::OutOfMemory)?;
        out.extend_from_slice(&chunk[..n]);
    }
    Ok(out)
}

/// The text of `path` (decompressed when gzip), which must be UTF-8.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    String::from_utf8(read(path)?).map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::write::GzEncoder;
    use std::io::Write;

    fn gzip(data: &[u8]) -> Vec<u8> {
        let mut e = GzEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(data).unwrap();
        e.finish().unwrap()
    }

    #[test]
    fn a_big_file_read_in_chunks_is_its_bytes() {
        let dir = std::env::temp_dir().join(format!("prism-big-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("big.ply");
        // Not a whole number of chunks, and a pattern that no chunk repeats at the same offset.
        let data: Vec<u8> = (0..PARALLEL_READ_BYTES as usize + 12_345).map(|i| (i % 251) as u8).collect();
        std::fs::write(&path, &data).unwrap();
        assert!(read(&path).unwrap() == data);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn gzip_members_decompress_and_plain_bytes_pass_through() {
        let dir = std::env::temp_dir().join(format!("prism-gzip-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let plain = dir.join("a.pbrt");
        std::fs::write(&plain, b"WorldBegin\n").unwrap();
        assert_eq!(read(&plain).unwrap(), b"WorldBegin\n");
        // Two members concatenated (as `cat a.gz b.gz` makes) are one stream.
        let mut two = gzip(b"Shape ");
        two.extend(gzip("\"sphere\" é\n".as_bytes()));
        let gz = dir.join("b.pbrt.gz");
        std::fs::write(&gz, &two).unwrap();
        assert_eq!(read_text(&gz).unwrap(), "Shape \"sphere\" é\n");
        // Truncated: an error, not a panic or a short read taken as the whole file.
        std::fs::write(&gz, &two[..two.len() - 5]).unwrap();
        assert!(read(&gz).is_err());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn output_beyond_the_limit_is_refused() {
        let big = gzip(&vec![0u8; 100_000]);
        assert_eq!(gunzip(&big, 100_000).unwrap().len(), 100_000);
        let e = gunzip(&big, 99_999).unwrap_err();
        assert!(e.to_string().contains("more than 99999 bytes"), "{e}");
    }

    #[test]
    fn the_decompression_limit_is_within_available_memory() {
        let limit = decompression_limit();
        assert!(limit <= MAX_DECOMPRESSED_BYTES);
        if let Some(avail) = crate::io::available_memory() {
            assert!(limit <= avail, "{limit} > {avail}");
        }
    }
}

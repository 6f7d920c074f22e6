//! Film files: the accumulated sums of a render with the sample range they hold and a fingerprint
//! of the settings that produced them. Used for checkpoints (`--checkpoint-every`, `--resume`) and
//! for renders split into parts (`--part i/N`, `prism merge`). Written atomically.
//!
//! Layout: the magic line `PRISMFILM 1\n`, a u32 little-endian header length, a JSON header, then
//! per pixel X, Y, Z, weight as f64 and the sample count as u64, all little-endian; then, when
//! the header says so, per pixel the geometry buffers' sums, then per pixel the spectral
//! buckets' sums, then per pixel the splatted X, Y, Z sums (f64, little-endian; the number of
//! light paths the splats hold is in the header).

use crate::film::{AovPixel, Film, Pixel, SpectralSettings};
use crate::image::CropWindow;
use glam::DVec3;
use std::io::Read;
use std::ops::Range;
use std::path::Path;

const MAGIC: &[u8] = b"PRISMFILM 1\n";
/// Largest image a film file may describe (guards allocation on corrupt input).
const MAX_PIXELS: u64 = 1 << 28;
/// Bytes per pixel of the splat sums.
const SPLAT_BYTES: usize = 24;

/// What a film file holds besides the pixels.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FilmHeader {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Sample indices accumulated (every pixel has the same).
    pub samples: Range<u64>,
    /// Total samples per pixel the whole render is meant to have.
    pub spp_total: u64,
    /// Settings and scene fingerprint ([`crate::fingerprint`]): parts and checkpoints only
    /// combine when equal.
    pub fingerprint: String,
    /// Where a cropped film lies in the full image (`None`: the film is the whole image).
    #[serde(default)]
    pub window: Option<CropWindow>,
    /// The colour space the render writes its image in (`None`: sRGB).
    #[serde(default)]
    pub color_space: Option<String>,
    /// OpenEXR output in 32-bit floats (the scene's Film "savefp16" false) instead of halves.
    #[serde(default)]
    pub exr_float: bool,
    /// The film holds geometry buffers: after the pixels, per pixel the sums of
    /// [`crate::film::AovPixel::write_le`].
    #[serde(default)]
    pub aov: bool,
    /// The film holds spectral buckets: after the geometry buffers, per pixel the
    /// [`SpectralSettings::stride`] sums of [`crate::film::SpectralSums`].
    #[serde(default)]
    pub spectral: Option<SpectralSettings>,
    /// The film holds splatted light ([`crate::film::SplatBuffer`]) from this many light paths:
    /// after the spectral buckets, per pixel the splatted X, Y, Z sums.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub splat_paths: Option<u64>,
}

impl FilmHeader {
    /// Pixels of the full image the film belongs to (it may be a crop of it).
    pub fn full_pixels(&self) -> u64 {
        match &self.window {
            Some(w) => w.full_width as u64 * w.full_height as u64,
            None => self.width as u64 * self.height as u64,
        }
    }
}

/// Errors reading or combining film files.
#[derive(Debug, thiserror::Error)]
pub enum FilmFileError {
    /// I/O failure.
    // The cause is part of the message, not a `source` (which the CLI would print a second
    // time when it joins an error's chain).
    #[error("{path}: {cause}")]
    Io {
        /// File.
        path: String,
        /// Cause.
        cause: std::io::Error,
    },
    /// Not a prism film file or damaged.
    #[error("{0}: not a prism film file, or damaged ({1})")]
    Format(String, String),
    /// Files that do not belong together.
    #[error("{0}")]
    Mismatch(String),
    /// The film or its file buffer does not fit in memory.
    #[error(transparent)]
    Memory(#[from] crate::film::FilmAllocError),
}

/// Serialises `film` with `header` to `path` atomically (the header's `splat_paths` taken from
/// the film).
pub fn save(path: &Path, film: &Film, header: &FilmHeader) -> Result<(), FilmFileError> {
    let header = FilmHeader { splat_paths: film.splats.as_ref().map(|s| s.paths), ..header.clone() };
    let json = serde_json::to_vec(&header).expect("header serialises");
    let aov_bytes = film.aov.as_ref().map_or(0, |a| a.len() * AovPixel::FILE_BYTES);
    let spectral_bytes = film.spectral.as_ref().map_or(0, |s| s.sums.len() * 8);
    let splat_bytes = film.splats.as_ref().map_or(0, |s| s.xyz_sum.len() * SPLAT_BYTES);
    let size = MAGIC.len() + 4 + json.len() + film.pixels.len() * 40 + aov_bytes + spectral_bytes + splat_bytes;
    let mut buf = Vec::new();
    buf.try_reserve_exact(size).map_err(|_| Film::alloc_error(film.width, film.height, size))?;
    buf.extend_from_slice(MAGIC);
    buf.extend_from_slice(&(json.len() as u32).to_le_bytes());
    buf.extend_from_slice(&json);
    for p in &film.pixels {
        for v in [p.xyz_sum.x, p.xyz_sum.y, p.xyz_sum.z, p.weight_sum] {
            buf.extend_from_slice(&v.to_le_bytes());
        }
        buf.extend_from_slice(&p.samples.to_le_bytes());
    }
    for a in film.aov.iter().flatten() {
        a.write_le(&mut buf);
    }
    for v in film.spectral.iter().flat_map(|s| &s.sums) {
        buf.extend_from_slice(&v.to_le_bytes());
    }
    for v in film.splats.iter().flat_map(|s| &s.xyz_sum) {
        for c in [v.x, v.y, v.z] {
            buf.extend_from_slice(&c.to_le_bytes());
        }
    }
    crate::io::write_atomic(path, &buf).map_err(|e| FilmFileError::Io { path: path.display().to_string(), cause: e })
}

/// Reads a film file.
pub fn load(path: &Path) -> Result<(Film, FilmHeader), FilmFileError> {
    let name = path.display().to_string();
    let io = |e| FilmFileError::Io { path: name.clone(), cause: e };
    let bad = |why: &str| FilmFileError::Format(name.clone(), why.to_string());
    let mut f = std::fs::File::open(path).map_err(io)?;
    let mut magic = [0u8; 12];
    f.read_exact(&mut magic).map_err(|_| bad("too short"))?;
    if magic != MAGIC {
        return Err(bad("wrong magic"));
    }
    let mut len = [0u8; 4];
    f.read_exact(&mut len).map_err(|_| bad("too short"))?;
    let len = u32::from_le_bytes(len) as usize;
    if len > 1 << 20 {
        return Err(bad("header too large"));
    }
    let mut json = vec![0u8; len];
    f.read_exact(&mut json).map_err(|_| bad("truncated header"))?;
    let header: FilmHeader = serde_json::from_slice(&json).map_err(|e| bad(&e.to_string()))?;
    let n = header.width as u64 * header.height as u64;
    if n == 0 || n > MAX_PIXELS {
        return Err(bad("absurd image size"));
    }
    if header.samples.start > header.samples.end || header.samples.end > header.spp_total {
        return Err(bad("its sample range does not lie within its samples per pixel"));
    }
    if let Some(w) = &header.window {
        let inside = |at: u32, len: u32, full: u32| at as u64 + len as u64 <= full as u64;
        if !inside(w.x0, header.width, w.full_width) || !inside(w.y0, header.height, w.full_height) {
            return Err(bad("its crop window does not lie within its full image"));
        }
    }
    let mut data = Vec::new();
    f.read_to_end(&mut data).map_err(io)?;
    if let Some(s) = &header.spectral {
        s.check().map_err(|e| bad(&format!("its spectral buckets: {e}")))?;
        if s.buckets > 1 << 16 {
            return Err(bad("absurd number of spectral buckets"));
        }
    }
    let aov_bytes = if header.aov { AovPixel::FILE_BYTES as u64 } else { 0 };
    let spectral_bytes = header.spectral.map_or(0, |s| s.stride() as u64 * 8);
    let splat_bytes = if header.splat_paths.is_some() { SPLAT_BYTES as u64 } else { 0 };
    if data.len() as u64 != n * (40 + aov_bytes + spectral_bytes + splat_bytes) {
        return Err(bad("pixel data has the wrong length"));
    }
    let (data, rest) = data.split_at(n as usize * 40);
    let (aov_data, rest) = rest.split_at((n * aov_bytes) as usize);
    let (spectral_data, splat_data) = rest.split_at((n * spectral_bytes) as usize);
    let mut film = Film::try_new(header.width, header.height)?;
    if header.aov {
        film = film.try_with_aov()?;
        for (a, c) in film.aov.iter_mut().flatten().zip(aov_data.chunks_exact(AovPixel::FILE_BYTES)) {
            *a = AovPixel::read_le(c).ok_or_else(|| bad("a pixel's geometry buffers hold a non-finite sum"))?;
        }
    }
    if let Some(s) = header.spectral {
        film = film.try_with_spectral(s)?;
        for (v, c) in film.spectral.iter_mut().flat_map(|s| &mut s.sums).zip(spectral_data.chunks_exact(8)) {
            *v = f64::from_le_bytes(c.try_into().expect("8 bytes"));
            if !v.is_finite() {
                return Err(bad("a pixel's spectral buckets hold a non-finite sum"));
            }
        }
    }
    if let Some(paths) = header.splat_paths {
        film = film.try_with_splats(header.full_pixels())?;
        let splats = film.splats.as_mut().expect("just made");
        splats.paths = paths;
        for (v, c) in splats.xyz_sum.iter_mut().zip(splat_data.chunks_exact(SPLAT_BYTES)) {
            let f64_at = |i: usize| f64::from_le_bytes(c[i * 8..i * 8 + 8].try_into().expect("8 bytes"));
            *v = DVec3::new(f64_at(0), f64_at(1), f64_at(2));
            if !v.is_finite() {
                return Err(bad("a pixel's splatted light is not finite"));
            }
        }
    }
    let range_len = header.samples.end - header.samples.start;
    for (p, c) in film.pixels.iter_mut().zip(data.chunks_exact(40)) {
        let f64_at = |i: usize| f64::from_le_bytes(c[i * 8..i * 8 + 8].try_into().expect("8 bytes"));
        *p = Pixel {
            xyz_sum: DVec3::new(f64_at(0), f64_at(1), f64_at(2)),
            weight_sum: f64_at(3),
            samples: u64::from_le_bytes(c[32..40].try_into().expect("8 bytes")),
        };
        // A render keeps no non-finite sample, and a pixel holds at most the range's samples.
        if !p.xyz_sum.is_finite() || !p.weight_sum.is_finite() || p.samples > range_len {
            return Err(bad("a pixel holds a non-finite sum or more samples than its range"));
        }
    }
    Ok((film, header))
}

/// Combines parts of one render: same size and fingerprint, disjoint sample ranges that leave no
/// gap between them. The result holds the union of the samples, summed in the order of their
/// sample ranges.
pub fn merge(mut parts: Vec<(Film, FilmHeader)>) -> Result<(Film, FilmHeader), FilmFileError> {
    if parts.is_empty() {
        return Err(FilmFileError::Mismatch("no parts to merge".into()));
    }
    parts.sort_by_key(|(_, h)| h.samples.start);
    let (mut film, mut header) = parts.remove(0);
    for (f, h) in parts {
        if (h.width, h.height) != (header.width, header.height) {
            return Err(FilmFileError::Mismatch(format!(
                "parts differ in size: {}x{} vs {}x{}",
                h.width, h.height, header.width, header.height
            )));
        }
        if h.aov != header.aov {
            return Err(FilmFileError::Mismatch("one part holds geometry buffers, another not".into()));
        }
        if h.spectral != header.spectral {
            return Err(FilmFileError::Mismatch(
                "the parts hold different spectral buckets (or one holds none)".into(),
            ));
        }
        if h.splat_paths.is_some() != header.splat_paths.is_some() {
            return Err(FilmFileError::Mismatch("one part holds splatted light, another not".into()));
        }
        if let Some(d) = crate::fingerprint::difference(&header.fingerprint, &h.fingerprint) {
            return Err(FilmFileError::Mismatch(format!("parts come from different scenes or settings: {d}")));
        }
        if h.samples.start < header.samples.end {
            return Err(FilmFileError::Mismatch(format!(
                "sample ranges overlap: {:?} and {:?}",
                header.samples, h.samples
            )));
        }
        // A film holds one range of samples: a missing part between two others cannot be
        // described, and the image would silently lack its samples.
        if h.samples.start > header.samples.end {
            return Err(FilmFileError::Mismatch(format!(
                "samples {}..{} are in no part: a part is missing",
                header.samples.end, h.samples.start
            )));
        }
        film.merge(&f);
        header.samples.end = h.samples.end;
        header.splat_paths = film.splats.as_ref().map(|s| s.paths);
    }
    Ok((film, header))
}

/// The sample range of part `i` (1-based) of `n` of a render with `spp` samples per pixel.
pub fn part_range(i: u64, n: u64, spp: u64) -> Range<u64> {
    // In 128 bits: i · spp overflows 64 for large i and spp.
    let at = |k: u64| (k as u128 * spp as u128 / n as u128) as u64;
    at(i - 1)..at(i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn film(seed: f32) -> Film {
        let mut f = Film::new(3, 2);
        for y in 0..2 {
            for x in 0..3 {
                f.add_sample(x, y, Vec3::new(seed + x as f32, y as f32, 0.5), 1.0);
            }
        }
        f
    }

    #[test]
    fn save_load_round_trip_and_merge() {
        let dir = std::env::temp_dir().join(format!("prism-film-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let h = |r: Range<u64>| FilmHeader {
            width: 3,
            height: 2,
            samples: r,
            spp_total: 4,
            fingerprint: "x".into(),
            window: Some(CropWindow { x0: 1, y0: 2, full_width: 8, full_height: 6 }),
            color_space: Some("rec2020".into()),
            exr_float: true,
            aov: false,
            spectral: None,
            splat_paths: None,
        };
        let (a, b) = (film(1.0), film(2.0));
        save(&dir.join("a.film"), &a, &h(0..2)).unwrap();
        save(&dir.join("b.film"), &b, &h(2..4)).unwrap();
        let la = load(&dir.join("a.film")).unwrap();
        assert_eq!(la.0.pixels, a.pixels);
        assert_eq!(la.1, h(0..2));
        let lb = load(&dir.join("b.film")).unwrap();
        let (m, mh) = merge(vec![lb, la.clone()]).unwrap();
        assert_eq!(mh.samples, 0..4);
        assert_eq!(m.pixels[0].samples, 2);
        assert!(merge(vec![la.clone(), la]).is_err(), "overlapping ranges must be refused");
        std::fs::write(dir.join("bad.film"), b"PRISMFILM 1\n\xff\xff\xff\x7f").unwrap();
        assert!(matches!(load(&dir.join("bad.film")), Err(FilmFileError::Format(..))));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn merge_refuses_parts_that_leave_samples_out() {
        let part = |samples: Range<u64>| {
            let h = FilmHeader {
                width: 3,
                height: 2,
                samples,
                spp_total: 6,
                fingerprint: "x".into(),
                window: None,
                color_space: None,
                exr_float: false,
                aov: false,
                spectral: None,
                splat_paths: None,
            };
            (film(1.0), h)
        };
        // Parts 1 and 3 of 3 (2 samples each): samples 2..4 are in neither.
        let e = merge(vec![part(0..2), part(4..6)]).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains("samples 2..4 are in no part"), "{e:?}");
        assert_eq!(merge(vec![part(4..6), part(2..4), part(0..2)]).unwrap().1.samples, 0..6);
    }

    #[test]
    fn parts_cover_the_samples_disjointly() {
        for (n, spp) in [(1, 7), (3, 7), (4, 16), (5, 3)] {
            let mut next = 0;
            for i in 1..=n {
                let r = part_range(i, n, spp);
                assert_eq!(r.start, next);
                next = r.end;
            }
            assert_eq!(next, spp);
        }
    }

    #[test]
    fn films_with_non_finite_pixels_or_inconsistent_headers_are_refused() {
        let dir = std::env::temp_dir().join(format!("prism-film-validate-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let header = |samples: Range<u64>, spp_total: u64, window: Option<CropWindow>| FilmHeader {
            width: 3,
            height: 2,
            samples,
            spp_total,
            fingerprint: "f".into(),
            window,
            color_space: None,
            exr_float: false,
            aov: false,
            spectral: None,
            splat_paths: None,
        };
        let check = |name: &str, film: &Film, h: &FilmHeader, needle: &str| {
            let path = dir.join(name);
            save(&path, film, h).unwrap();
            let e = load(&path).err().map(|e| e.to_string()).unwrap_or_default();
            assert!(e.contains(needle), "{name}: {e:?} should say {needle:?}");
        };
        let good = film(1.0);
        let ok = header(0..1, 4, None);
        save(&dir.join("ok.film"), &good, &ok).unwrap();
        assert!(load(&dir.join("ok.film")).is_ok());
        let mut nan = good.clone();
        nan.pixels[4].xyz_sum.y = f64::NAN;
        check("nan.film", &nan, &ok, "non-finite");
        check("range.film", &good, &header(Range { start: 3, end: 2 }, 4, None), "sample range");
        check("spp.film", &good, &header(0..5, 4, None), "sample range");
        let outside = CropWindow { x0: 2, y0: 0, full_width: 4, full_height: 2 };
        check("window.film", &good, &header(0..1, 4, Some(outside)), "crop window");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn parts_of_huge_counts_do_not_overflow() {
        // i · spp exceeds 64 bits here: the last of 2⁶⁴ − 1 parts of 16 samples is the 16th.
        assert_eq!(part_range(u64::MAX, u64::MAX, 16), 15..16);
        assert_eq!(part_range(u64::MAX, u64::MAX, u64::MAX), (u64::MAX - 1)..u64::MAX);
        assert_eq!(part_range(1, 3, u64::MAX), 0..u64::MAX / 3);
    }
}

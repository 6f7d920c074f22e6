//! Round trips, backend agreement, error messages and the atomic-write guarantee.

use super::*;
use std::cell::Cell;
use std::fs;
use std::path::PathBuf;

thread_local! {
    /// Makes the next `write_with` on this thread fail after the backend has written the
    /// temporary file, as an encoder failing at the last moment would.
    static FAIL_NEXT_WRITE: Cell<bool> = const { Cell::new(false) };
}

/// Hook called by `write_with` between encoding and the final rename.
pub(super) fn injected_failure() -> Result<(), String> {
    if FAIL_NEXT_WRITE.with(|f| f.replace(false)) {
        Err("injected failure after encoding".into())
    } else {
        Ok(())
    }
}

/// A scratch directory removed on drop.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("prism-image-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }
    fn path(&self, file: &str) -> PathBuf {
        self.0.join(file)
    }
    /// Names of all entries, sorted.
    fn entries(&self) -> Vec<String> {
        let mut v: Vec<String> =
            fs::read_dir(&self.0).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

/// A deterministic test pattern; `range` scales it (HDR content beyond 1 when > 1).
fn pattern(width: u32, height: u32, channels: u32, range: f32) -> Image {
    let mut img = Image::new(width, height, channels);
    let c = channels as usize;
    for (i, v) in img.data.iter_mut().enumerate() {
        let (p, ch) = (i / c, i % c);
        let x = (p as u32 % width) as f32 / width as f32;
        let y = (p as u32 / width) as f32 / height as f32;
        // Smooth in x and y so JPEG's block transform has little to lose.
        *v = range * (0.5 + 0.45 * ((x * 3.0 + ch as f32).sin() * (y * 2.0 + 1.0).cos()));
    }
    img
}

fn opts(backend: Backend) -> WriteOptions {
    WriteOptions { backend, ..WriteOptions::default() }
}

fn max_encoded_diff(a: &Image, b: &Image) -> f32 {
    let c = a.channels as usize;
    a.data
        .iter()
        .zip(&b.data)
        .enumerate()
        .map(|(i, (&x, &y))| {
            let e = |v: f32| {
                if srgb::is_alpha(i % c, c) {
                    v.clamp(0.0, 1.0)
                } else {
                    srgb::encode(v.clamp(0.0, 1.0))
                }
            };
            (e(x) - e(y)).abs()
        })
        .fold(0.0, f32::max)
}

#[test]
fn exr_float_round_trip_is_exact() {
    let dir = Scratch::new("exr-float");
    for &backend in Backend::available() {
        for channels in 1..=4 {
            let mut img = pattern(7, 5, channels, 10.0);
            img.data[0] = -3.25e-7; // negative, tiny and huge values survive float storage
            img.data[1] = 1.0e30;
            let path = dir.path(&format!("f{channels}.exr"));
            let o = WriteOptions { exr_sample: ExrSample::Float, ..opts(backend) };
            write_with(&path, &img, &o).unwrap();
            let back = read_with(&path, backend).unwrap();
            assert_eq!(back, img, "{backend:?}, {channels} channels");
        }
    }
}

#[test]
fn exr_half_round_trip_is_within_half_precision() {
    let dir = Scratch::new("exr-half");
    for &backend in Backend::available() {
        let img = pattern(9, 4, 3, 100.0); // values in [5, 95]: normal halves
        let path = dir.path("h.exr");
        write_with(&path, &img, &opts(backend)).unwrap();
        let back = read_with(&path, backend).unwrap();
        assert_eq!((back.width, back.height, back.channels), (9, 4, 3));
        for (&r, &v) in back.data.iter().zip(&img.data) {
            // 10 stored mantissa bits: round-to-nearest error ≤ 2⁻¹¹ relative.
            assert!((r - v).abs() <= v.abs() * 2f32.powi(-11), "{backend:?}: {v} → {r}");
        }
        assert_ne!(back.data, img.data, "half storage must actually round");
    }
}

#[test]
fn exr_default_is_zip_compressed_half_with_conventional_names() {
    use exr::prelude::{Compression, MetaData, SampleType};
    let dir = Scratch::new("exr-header");
    for &backend in Backend::available() {
        for channels in 1..=4 {
            let path = dir.path(&format!("d{channels}.exr"));
            write_with(&path, &pattern(3, 2, channels, 1.0), &opts(backend)).unwrap();
            let meta = MetaData::read_from_file(&path, false).unwrap();
            let header = &meta.headers[0];
            assert_eq!(header.compression, Compression::ZIP16, "{backend:?}");
            let mut names: Vec<String> = Vec::new();
            for ch in &header.channels.list {
                assert_eq!(ch.sample_type, SampleType::F16, "{backend:?}");
                names.push(ch.name.to_string());
            }
            let expected: &[&str] = match channels {
                1 => &["Y"],
                2 => &["A", "Y"],
                3 => &["B", "G", "R"],
                _ => &["A", "B", "G", "R"],
            }; // stored alphabetically, as OpenEXR requires
            assert_eq!(names, expected, "{backend:?}");
        }
    }
}

#[test]
fn png_and_tiff_round_trip_within_half_a_code() {
    let dir = Scratch::new("png");
    for &backend in Backend::available() {
        for channels in 1..=4 {
            // Range 1.2 pushes some values past 1 to exercise clamping.
            let img = pattern(11, 6, channels, 1.2);
            for (ext, sixteen, code) in [("png", false, 255.0), ("tif", false, 255.0), ("tiff", true, 65535.0)] {
                if channels == 2 && ext != "png" {
                    continue; // TIFF takes Y, RGB or RGBA
                }
                let path = dir.path(&format!("p{channels}.{ext}"));
                let o = WriteOptions { tiff_16bit: sixteen, ..opts(backend) };
                write_with(&path, &img, &o).unwrap();
                let back = read_with(&path, backend).unwrap();
                assert_eq!((back.width, back.height, back.channels), (11, 6, channels));
                let d = max_encoded_diff(&back, &img);
                // Quantisation error ≤ ½ code; f32 rounding of the curve adds < 1e-6.
                assert!(d <= 0.5 / code + 1e-6, "{backend:?} .{ext} {channels}ch: {d}");
            }
        }
    }
}

#[test]
fn jpeg_round_trip_is_close_on_smooth_content() {
    let dir = Scratch::new("jpeg");
    for &backend in Backend::available() {
        let img = pattern(32, 16, 3, 1.0);
        let path = dir.path("j.jpg");
        write_with(&path, &img, &opts(backend)).unwrap();
        let back = read_with(&path, backend).unwrap();
        assert_eq!((back.width, back.height, back.channels), (32, 16, 3));
        let d = max_encoded_diff(&back, &img);
        eprintln!("{backend:?} jpeg max encoded diff {d}");
        assert!(d < 0.05, "{backend:?}: {d}");
    }
}

#[test]
fn hdr_round_trip_is_within_rgbe_precision() {
    let dir = Scratch::new("hdr");
    for &backend in Backend::available() {
        let img = pattern(8, 8, 3, 50.0);
        let path = dir.path("r.hdr");
        write_with(&path, &img, &opts(backend)).unwrap();
        let back = read_with(&path, backend).unwrap();
        assert_eq!((back.width, back.height, back.channels), (8, 8, 3));
        for (pb, pi) in back.data.chunks(3).zip(img.data.chunks(3)) {
            // RGBE: 8-bit mantissas sharing the exponent of the largest component, so the
            // step is ≤ 2⁻⁷ of that component (truncation may cost a full step).
            let m = pi.iter().copied().fold(0.0, f32::max);
            for (r, v) in pb.iter().zip(pi) {
                assert!((r - v).abs() <= m * 2f32.powi(-7), "{backend:?}: {v} → {r}");
            }
        }
    }
}

#[test]
fn backends_read_each_others_files_identically() {
    if Backend::available().len() < 2 {
        return;
    }
    let dir = Scratch::new("agree");
    for channels in [1, 3, 4] {
        let img = pattern(13, 7, channels, 1.5);
        for (ext, tiff_16bit) in [("exr", false), ("png", false), ("tif", false), ("tif", true)] {
            let mut reads = Vec::new();
            for writer in [Backend::Oiio, Backend::Rust] {
                let path = dir.path(&format!("{writer:?}-{channels}-{tiff_16bit}.{ext}"));
                let o = WriteOptions { tiff_16bit, ..opts(writer) };
                write_with(&path, &img, &o).unwrap();
                for reader in [Backend::Oiio, Backend::Rust] {
                    reads.push((writer, reader, read_with(&path, reader).unwrap()));
                }
            }
            // Identical quantisation and identical decoding: all four reads agree exactly.
            for (w, r, im) in &reads[1..] {
                assert_eq!(im, &reads[0].2, ".{ext} {channels}ch written by {w:?}, read by {r:?}");
            }
        }
    }
}

#[test]
fn unsupported_extension_names_the_supported_ones() {
    let dir = Scratch::new("ext");
    let img = pattern(2, 2, 3, 1.0);
    for &backend in Backend::available() {
        let err = write_with(&dir.path("out.bmp"), &img, &opts(backend)).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, ImageError::UnsupportedExtension { .. }));
        assert!(msg.contains("unsupported image extension \".bmp\""), "{msg}");
        assert!(msg.contains(".exr, .png, .jpg"), "{msg}");
        assert!(read_with(&dir.path("in.gif"), backend).is_err());
    }
    assert!(dir.entries().is_empty(), "nothing may be created: {:?}", dir.entries());
}

#[test]
fn unwritable_destinations_are_reported() {
    let dir = Scratch::new("unwritable");
    let img = pattern(2, 2, 3, 1.0);
    fs::write(dir.path("plain-file"), b"x").unwrap();
    for &backend in Backend::available() {
        let missing = dir.path("no/such/dir/out.exr");
        let err = write_with(&missing, &img, &opts(backend)).unwrap_err();
        assert!(matches!(err, ImageError::MissingDirectory { .. }), "{err}");
        assert!(err.to_string().contains("does not exist"), "{err}");
        let under_file = dir.path("plain-file/out.png");
        let err = write_with(&under_file, &img, &opts(backend)).unwrap_err();
        assert!(matches!(err, ImageError::Unwritable { .. }), "{err}");
        assert!(err.to_string().contains("not a directory"), "{err}");
    }
}

#[test]
fn failed_write_keeps_the_old_file_and_leaves_no_temporary() {
    let dir = Scratch::new("atomic");
    let old = b"previous render".to_vec();
    for &backend in Backend::available() {
        // An encoder failing after the temporary file was written.
        let target = dir.path("render.jpg");
        fs::write(&target, &old).unwrap();
        FAIL_NEXT_WRITE.with(|f| f.set(true));
        let err = write_with(&target, &pattern(4, 4, 3, 1.0), &opts(backend)).unwrap_err();
        assert!(matches!(err, ImageError::Write { .. }), "{backend:?}: {err}");
        assert_eq!(fs::read(&target).unwrap(), old, "{backend:?}");
        assert_eq!(dir.entries(), vec!["render.jpg"], "{backend:?}");

        // Over JPEG's size limit: refused before any file is made (OIIO's libjpeg would
        // otherwise exit the process).
        let err = write_with(&target, &Image::new(70_000, 1, 3), &opts(backend)).unwrap_err();
        assert!(matches!(err, ImageError::TooLarge { .. }), "{backend:?}: {err}");
        assert_eq!(fs::read(&target).unwrap(), old, "{backend:?}");
        assert_eq!(dir.entries(), vec!["render.jpg"], "{backend:?}");

        // The final rename fails when the destination is a directory: it stays, the
        // temporary goes.
        let target = dir.path("taken.png");
        fs::create_dir(&target).unwrap();
        let err = write_with(&target, &pattern(2, 2, 3, 1.0), &opts(backend)).unwrap_err();
        assert!(matches!(err, ImageError::Write { .. }), "{backend:?}: {err}");
        assert!(target.is_dir());
        assert_eq!(dir.entries(), vec!["render.jpg", "taken.png"], "{backend:?}");
        fs::remove_dir(&target).unwrap();

        // A successful write replaces the old file completely.
        let target = dir.path("render.png");
        fs::write(&target, &old).unwrap();
        write_with(&target, &pattern(3, 3, 3, 1.0), &opts(backend)).unwrap();
        assert_eq!(read_with(&target, backend).unwrap().width, 3);
        assert_eq!(dir.entries(), vec!["render.jpg", "render.png"], "{backend:?}");
        fs::remove_file(&target).unwrap();
    }
}

#[test]
fn bad_images_and_channel_counts_are_rejected_before_writing() {
    let dir = Scratch::new("invalid");
    let broken = Image { width: 4, height: 4, channels: 3, data: vec![0.0; 47] };
    for &backend in Backend::available() {
        let err = write_with(&dir.path("a.exr"), &broken, &opts(backend)).unwrap_err();
        assert_eq!(err.to_string(), "invalid image: 47 samples for 4x4x3");
        let err = write_with(&dir.path("a.exr"), &Image::new(0, 4, 3), &opts(backend));
        assert!(matches!(err, Err(ImageError::InvalidImage(_))));
        // Five unnamed channels: only `write_channels` with names writes more than four.
        let err = write_with(&dir.path("a.exr"), &Image::new(1, 1, 5), &opts(backend));
        assert!(matches!(err, Err(ImageError::UnsupportedChannels { .. })));
        let err = write_with(&dir.path("a.jpg"), &Image::new(2, 2, 4), &opts(backend)).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{}: JPEG cannot store 4 channel(s) (it takes 1 or 3)", dir.path("a.jpg").display())
        );
        let err = write_with(&dir.path("a.hdr"), &Image::new(2, 2, 1), &opts(backend));
        assert!(matches!(err, Err(ImageError::UnsupportedChannels { .. })));
        let err = write_with(&dir.path("a.tif"), &Image::new(2, 2, 2), &opts(backend));
        assert!(matches!(err, Err(ImageError::UnsupportedChannels { .. })));
    }
    assert!(dir.entries().is_empty(), "{:?}", dir.entries());
}

#[test]
fn reading_missing_or_corrupt_files_fails_cleanly() {
    let dir = Scratch::new("read-errors");
    fs::write(dir.path("garbage.png"), b"this is not a png").unwrap();
    fs::write(dir.path("garbage.exr"), b"\x76\x2f\x31\x01 truncated").unwrap();
    for &backend in Backend::available() {
        let err = read_with(&dir.path("absent.exr"), backend).unwrap_err();
        assert!(matches!(err, ImageError::NotFound { .. }), "{err}");
        assert!(err.to_string().ends_with("absent.exr: no such file"), "{err}");
        for f in ["garbage.png", "garbage.exr"] {
            let err = read_with(&dir.path(f), backend).unwrap_err();
            assert!(matches!(err, ImageError::Decode { .. }), "{backend:?} {f}: {err}");
            assert!(!err.to_string().contains('\n'), "one line: {err}");
        }
    }
}

#[test]
fn a_cropped_exr_keeps_its_place_in_the_full_image() {
    // pbrt-v4 writes a crop as the data window inside the full image's display window.
    let dir = Scratch::new("window");
    let img = pattern(3, 2, 3, 4.0);
    let window = CropWindow { x0: 5, y0: 7, full_width: 20, full_height: 10 };
    for &backend in Backend::available() {
        let path = dir.path(&format!("crop-{backend:?}.exr"));
        let opts = WriteOptions { backend, window: Some(window), exr_sample: ExrSample::Float, ..Default::default() };
        write_with(&path, &img, &opts).unwrap();
        let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
        let header = &meta.headers[0];
        let data = header.data_window();
        assert_eq!((data.position.x(), data.position.y(), data.size.x(), data.size.y()), (5, 7, 3, 2), "{backend:?}");
        let display = header.shared_attributes.display_window;
        assert_eq!((display.position.x(), display.position.y()), (0, 0), "{backend:?}");
        assert_eq!((display.size.x(), display.size.y()), (20, 10), "{backend:?}");
        // Read back by either backend: the crop's own pixels.
        for &reader in Backend::available() {
            assert_eq!(read_with(&path, reader).unwrap(), img, "{backend:?} → {reader:?}");
        }
    }
    // Without a window the image is whole: data window = display window.
    let path = dir.path("whole.exr");
    write_with(&path, &img, &WriteOptions::default()).unwrap();
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    assert_eq!(meta.headers[0].shared_attributes.display_window, meta.headers[0].data_window());
}

/// Rewrites the `dataWindow` attribute of the OpenEXR file at `path` to (0,0)–(`max`,`max`).
fn patch_exr_data_window(path: &Path, max: i32) {
    let mut bytes = fs::read(path).unwrap();
    let key = b"dataWindow\0box2i\0";
    let at = bytes.windows(key.len()).position(|w| w == key).expect("dataWindow attribute") + key.len() + 4;
    for (k, v) in [0, 0, max, max].into_iter().enumerate() {
        bytes[at + 4 * k..at + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
    }
    fs::write(path, bytes).unwrap();
}

#[test]
fn images_too_large_to_read_are_refused_from_their_header_naming_file_and_size() {
    let dir = Scratch::new("huge");
    // A few hundred bytes declaring 2^40 pixels.
    let exr = dir.path("huge.exr");
    write(&exr, &pattern(1, 1, 3, 1.0)).unwrap();
    patch_exr_data_window(&exr, 1_048_575);
    assert!(fs::metadata(&exr).unwrap().len() < 1000);
    let err = read(&exr).unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, ImageError::TooManyPixels { .. }), "{msg}");
    assert!(msg.contains("huge.exr") && msg.contains("1048576x1048576"), "{msg}");
    assert!(msg.contains(&MAX_READ_PIXELS.to_string()) && !msg.contains('\n'), "{msg}");

    // A Radiance HDR whose header declares 100000x3000 pixels (3·10^8 > 2^28).
    let hdr = dir.path("huge.hdr");
    fs::write(&hdr, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 3000 +X 100000\n\0\0\0\0").unwrap();
    let msg = read(&hdr).unwrap_err().to_string();
    assert!(msg.contains("huge.hdr") && msg.contains("100000x3000"), "{msg}");

    // A binary PPM named .jpg: the Rust decoders cannot read it, OpenImageIO can.
    let ppm = dir.path("huge.jpg");
    fs::write(&ppm, b"P6 100000 3000\n255\n\0\0\0").unwrap();
    for &backend in Backend::available() {
        let msg = read_with(&ppm, backend).unwrap_err().to_string();
        if backend == Backend::Oiio {
            assert!(msg.contains("huge.jpg") && msg.contains("100000x3000"), "{msg}");
        }
        assert!(!msg.contains('\n'), "{msg}");
    }
    let msg = read(&ppm).unwrap_err().to_string();
    if Backend::available().contains(&Backend::Oiio) {
        assert!(msg.contains("100000x3000") && msg.contains("exceeds"), "{msg}");
    }
}

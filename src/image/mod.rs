//! Image files: writing and reading linear float images, and comparing them.
//!
//! Formats are chosen by extension ([`SUPPORTED_EXTENSIONS`]). OpenEXR and Radiance HDR hold
//! linear values; PNG, JPEG and TIFF hold sRGB-encoded integers, so writing applies the sRGB
//! curve (IEC 61966-2-1) to colour channels (never to alpha) and reading removes it.
//!
//! Two backends do the work: a pure-Rust path (`exr` and `image` crates), which reads and writes
//! by default, and OpenImageIO through the C++ shim in `cpp/` (feature `oiio`), loaded on first
//! use, which reads what the Rust decoders cannot (TIFFs of 64-bit floats or of 16- and 32-bit
//! signed or 32-bit unsigned integers, among others). Every write is atomic: data goes to a
//! temporary file beside the destination that is renamed over it only once complete.

mod colormap;
pub mod compose;
mod error;
mod format;
mod meta;
pub mod metrics;
#[cfg(feature = "oiio")]
mod oiio;
mod rust_io;
mod srgb;

use crate::io::TempFile;
use std::path::Path;

pub use colormap::viridis_image;
pub use error::ImageError;
pub use format::{FileFormat, SUPPORTED_EXTENSIONS};
pub use meta::{Chromaticities, ImageMeta};
pub use metrics::{compare, false_colour_difference, Metrics};

/// A linear image: `data` holds `width·height·channels` samples, row-major from the top row,
/// channels interleaved (Y, YA, RGB or RGBA; alpha straight, not premultiplied).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub channels: u32,
    /// Interleaved linear samples.
    pub data: Vec<f32>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32, channels: u32) -> Self {
        let n = width as usize * height as usize * channels as usize;
        Self { width, height, channels, data: vec![0.0; n] }
    }

    /// The samples of pixel (`x`, `y`); `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<&[f32]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let c = self.channels as usize;
        let i = (y as usize * self.width as usize + x as usize) * c;
        self.data.get(i..i + c)
    }

    /// Number of samples the size implies, `None` on overflow.
    fn expected_len(&self) -> Option<usize> {
        (self.width as usize).checked_mul(self.height as usize)?.checked_mul(self.channels as usize)
    }

    /// Checks that the fields agree and describe a non-empty image (which channel counts a
    /// format takes is the format's check).
    pub fn validate(&self) -> Result<(), ImageError> {
        if self.width == 0 || self.height == 0 {
            return Err(ImageError::InvalidImage(format!("empty size {}x{}", self.width, self.height)));
        }
        if self.channels == 0 {
            return Err(ImageError::InvalidImage("no channels".into()));
        }
        match self.expected_len() {
            Some(n) if n == self.data.len() => Ok(()),
            _ => Err(ImageError::InvalidImage(format!(
                "{} samples for {}x{}x{}",
                self.data.len(),
                self.width,
                self.height,
                self.channels
            ))),
        }
    }
}

/// Which implementation reads and writes files.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// OpenImageIO through the C++ shim; only when built with feature `oiio`.
    Oiio,
    /// The `exr` and `image` crates.
    Rust,
}

impl Backend {
    /// The Rust path: it handles every supported format, and loading OpenImageIO costs a process
    /// 0.26 s, so OpenImageIO is kept for the files the Rust path cannot decode ([`read`]).
    pub fn preferred() -> Self {
        Self::Rust
    }

    /// The backends compiled into this build.
    pub fn available() -> &'static [Backend] {
        if cfg!(feature = "oiio") {
            &[Self::Oiio, Self::Rust]
        } else {
            &[Self::Rust]
        }
    }
}

/// Sample type of OpenEXR output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExrSample {
    /// 16-bit half floats (≈3 significant digits, max 65504): small files.
    Half,
    /// 32-bit floats: exact.
    Float,
}

/// How [`write_with`] stores an image.
#[derive(Clone, Debug, PartialEq)]
pub struct WriteOptions {
    /// Implementation to use.
    pub backend: Backend,
    /// OpenEXR sample type (default half, as OIIO and pbrt-v4 write).
    pub exr_sample: ExrSample,
    /// TIFF with 16-bit instead of 8-bit samples.
    pub tiff_16bit: bool,
    /// JPEG quality, 1–100.
    pub jpeg_quality: u8,
    /// For OpenEXR: the image is the part of a larger one (a crop), stored as the file's data
    /// window inside that display window, as pbrt-v4 writes crops. Other formats ignore it.
    pub window: Option<CropWindow>,
    /// What the file says about the image: colour space (OpenEXR chromaticities, PNG cICP) and
    /// how it was rendered (OpenEXR attributes).
    pub meta: ImageMeta,
}

/// Where an image lies in the full image it was cropped from [pixels].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct CropWindow {
    /// Column of the image's first pixel in the full image.
    pub x0: u32,
    /// Row of the image's first pixel in the full image.
    pub y0: u32,
    /// Width of the full image.
    pub full_width: u32,
    /// Height of the full image.
    pub full_height: u32,
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self {
            backend: Backend::preferred(),
            exr_sample: ExrSample::Half,
            tiff_16bit: false,
            jpeg_quality: 95,
            window: None,
            meta: ImageMeta::default(),
        }
    }
}

/// Writes `img` to `path` with default options, the format chosen by extension.
pub fn write(path: &Path, img: &Image) -> Result<(), ImageError> {
    write_with(path, img, &WriteOptions::default())
}

/// Writes `img` to `path` atomically: an existing file is replaced only by a complete new
/// one, and on any error it is left as it was with no temporary file behind.
pub fn write_with(path: &Path, img: &Image, opts: &WriteOptions) -> Result<(), ImageError> {
    let format = FileFormat::from_path(path)?;
    img.validate()?;
    format.check_channels(path, img.channels)?;
    format.check_size(path, img.width, img.height)?;
    check_backend(opts.backend)?;
    write_file(path, |temp| match opts.backend {
        #[cfg(feature = "oiio")]
        Backend::Oiio => oiio::write(temp, format, img, opts).map_err(|e| e.to_string()),
        _ => rust_io::write(temp, format, img, opts).map_err(|e| e.to_string()),
    })
}

/// Writes `img`, whose channels are called `names` (e.g. pbrt-v4's geometry buffers: "R", "G",
/// "B", "Albedo.R", …), to the OpenEXR file `path`, atomically as [`write_with`]. Through the
/// `exr` crate whatever `opts.backend` says: channel names are OpenEXR's alone.
pub fn write_channels(path: &Path, img: &Image, names: &[&str], opts: &WriteOptions) -> Result<(), ImageError> {
    let format = FileFormat::from_path(path)?;
    img.validate()?;
    if format != FileFormat::Exr {
        return Err(ImageError::NamedChannels {
            path: path.to_path_buf(),
            format: format.name(),
            channels: img.channels,
        });
    }
    if names.len() != img.channels as usize {
        return Err(ImageError::InvalidImage(format!("{} channel names for {} channels", names.len(), img.channels)));
    }
    format.check_size(path, img.width, img.height)?;
    write_file(path, |temp| rust_io::write_exr(temp, img, names, opts).map_err(|e| e.to_string()))
}

/// Runs `encode` on a temporary file beside `path` and moves the result into place.
fn write_file(path: &Path, encode: impl FnOnce(&Path) -> Result<(), String>) -> Result<(), ImageError> {
    let temp = create_temp(path)?;
    let result = encode(temp.path());
    #[cfg(test)]
    let result = result.and_then(|()| tests::injected_failure());
    result.map_err(|reason| ImageError::Write { path: path.to_path_buf(), reason })?;
    temp.commit().map_err(|e| ImageError::Write {
        path: path.to_path_buf(),
        reason: format!("cannot move the finished file into place: {e}"),
    })
}

/// A temporary file beside `path`, with the errors a user can act on.
fn create_temp(path: &Path) -> Result<TempFile, ImageError> {
    let dir = crate::io::parent_dir(path);
    if !dir.exists() {
        return Err(ImageError::MissingDirectory { path: path.to_path_buf(), dir });
    }
    if !dir.is_dir() {
        return Err(ImageError::Unwritable { path: path.to_path_buf(), dir, reason: "not a directory".into() });
    }
    TempFile::create(path).map_err(|e| ImageError::Unwritable { path: path.to_path_buf(), dir, reason: e.to_string() })
}

/// For an OpenEXR file, the indices (into [`read`]'s channels: R, G, B, A first) of its first
/// three channels in the order the file lists them, which OpenEXR sorts by name: [2, 1, 0]
/// (B, G, R) for an RGB image, [3, 2, 1] (A, B, G) with alpha. `None` for other formats, or
/// fewer than three channels.
pub fn exr_channels_in_file_order(path: &Path) -> Option<[usize; 3]> {
    match FileFormat::from_path(path) {
        Ok(FileFormat::Exr) => rust_io::exr_channels_in_file_order(path),
        _ => None,
    }
}

/// Reads `path` into linear floats with the preferred backend, or, when it cannot decode the
/// file and OpenImageIO is built in, with OpenImageIO.
pub fn read(path: &Path) -> Result<Image, ImageError> {
    match read_with(path, Backend::preferred()) {
        Err(ImageError::Decode { path, reason }) if Backend::available().contains(&Backend::Oiio) => {
            read_with(&path, Backend::Oiio).map_err(|e| match e {
                ImageError::Decode { reason: oiio, .. } => {
                    ImageError::Decode { path: path.clone(), reason: format!("{reason} (OpenImageIO: {oiio})") }
                }
                other => other,
            })
        }
        result => result,
    }
}

/// Reads `path` into linear floats: OpenEXR and HDR as stored, PNG/JPEG/TIFF sRGB-decoded.
pub fn read_with(path: &Path, backend: Backend) -> Result<Image, ImageError> {
    let format = FileFormat::from_path(path)?;
    check_backend(backend)?;
    if !path.is_file() {
        return Err(ImageError::NotFound { path: path.to_path_buf() });
    }
    // The Rust decoders read most headers; OpenImageIO checks the rest itself.
    if let Some((width, height)) = rust_io::dimensions(path, format) {
        check_read_size(path, width, height)?;
    }
    let result = match backend {
        #[cfg(feature = "oiio")]
        Backend::Oiio => oiio::read(path).map_err(|e| e.to_string()),
        _ => rust_io::read(path, format).map_err(|e| e.to_string()),
    };
    result.map_err(|reason| ImageError::Decode { path: path.to_path_buf(), reason: one_line(&reason) })
}

/// A decoder's message as one line: its lines trimmed and joined by spaces (some decoders end
/// their messages in a newline or spread them over several lines).
fn one_line(message: &str) -> String {
    message.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" ")
}

/// Most pixels an input image may have: 2^28 (16384², 4 GiB as four channels of `f32`).
pub const MAX_READ_PIXELS: u64 = 1 << 28;

/// Refuses, from its header's size, an image with more than [`MAX_READ_PIXELS`] pixels or one
/// whose samples (up to four `f32` channels) would not fit in the memory available now.
pub(crate) fn check_read_size(path: &Path, width: u64, height: u64) -> Result<(), ImageError> {
    let pixels = width.saturating_mul(height);
    let limit = if pixels > MAX_READ_PIXELS {
        format!("the limit of {MAX_READ_PIXELS} pixels")
    } else {
        let need = pixels.saturating_mul(16);
        match crate::io::available_memory() {
            Some(avail) if need > avail => {
                let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
                format!("available memory ({:.1} GiB needed, {:.1} GiB available)", gib(need), gib(avail))
            }
            _ => return Ok(()),
        }
    };
    Err(ImageError::TooManyPixels { path: path.to_path_buf(), width, height, limit })
}

fn check_backend(backend: Backend) -> Result<(), ImageError> {
    if Backend::available().contains(&backend) {
        Ok(())
    } else {
        Err(ImageError::BackendUnavailable)
    }
}

#[cfg(test)]
mod tests;

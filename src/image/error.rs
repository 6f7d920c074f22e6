//! Errors of image reading, writing and comparison.

use std::path::PathBuf;

/// Everything that can go wrong reading, writing or comparing images; each renders as one line.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The file extension names no format prism can write or read.
    #[error("{path}: unsupported image extension {ext:?} (supported: {supported})")]
    UnsupportedExtension { path: PathBuf, ext: String, supported: &'static str },
    /// The format cannot hold this many channels (e.g. alpha in JPEG, anything but RGB in .hdr).
    #[error("{path}: {format} cannot store {channels} channel(s) (it takes {accepted})")]
    UnsupportedChannels { path: PathBuf, format: &'static str, channels: u32, accepted: &'static str },
    /// Named channels (AOVs) asked of a format without channel names.
    #[error("{path}: {format} cannot store named channels ({channels} of them): write an .exr")]
    NamedChannels { path: PathBuf, format: &'static str, channels: u32 },
    /// The image exceeds the format's size limit.
    #[error("{path}: {format} images are at most {max} pixels wide and high, not {width}x{height}")]
    TooLarge { path: PathBuf, format: &'static str, width: u32, height: u32, max: u32 },
    /// An input image too large to read: more pixels than [`super::MAX_READ_PIXELS`] or more
    /// memory than is available; refused from its header, before any pixel is decoded.
    #[error("{path}: a {width}x{height} image exceeds {limit}")]
    TooManyPixels { path: PathBuf, width: u64, height: u64, limit: String },
    /// The image's own fields disagree (size, channel count, data length).
    #[error("invalid image: {0}")]
    InvalidImage(String),
    /// The output's directory does not exist.
    #[error("{path}: directory {dir} does not exist")]
    MissingDirectory { path: PathBuf, dir: PathBuf },
    /// The output's directory exists but a file cannot be created in it.
    #[error("{path}: cannot write in directory {dir}: {reason}")]
    Unwritable { path: PathBuf, dir: PathBuf, reason: String },
    /// Encoding or writing the file failed; the previous file at `path`, if any, is untouched.
    #[error("{path}: write failed: {reason}")]
    Write { path: PathBuf, reason: String },
    /// The input file does not exist.
    #[error("{path}: no such file")]
    NotFound { path: PathBuf },
    /// The input exists but could not be decoded.
    #[error("{path}: cannot decode image: {reason}")]
    Decode { path: PathBuf, reason: String },
    /// The OpenImageIO backend was asked for in a build without feature `oiio`.
    #[error("the OpenImageIO backend is not compiled in (build with feature `oiio`)")]
    BackendUnavailable,
    /// Two images to compare differ in size or channel count.
    #[error("image size mismatch: {a_width}x{a_height}x{a_channels} vs {b_width}x{b_height}x{b_channels}")]
    SizeMismatch { a_width: u32, a_height: u32, a_channels: u32, b_width: u32, b_height: u32, b_channels: u32 },
}

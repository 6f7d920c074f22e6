//! Why an Embree call fails: the device's and the library's errors. `LibraryMismatch` (the
//! loaded library is not the one this build's declarations describe) and `EmbreeError` hold each
//! other, so they live in one file below the device and the library check.

use std::fmt;
use std::sync::Arc;

/// Why an Embree call failed.
#[derive(Debug, thiserror::Error)]
pub enum EmbreeError {
    /// `rtcNewDevice` returned null.
    #[error("could not create the Embree device: {0}")]
    Device(String),
    /// A later call reported an error through the device.
    #[error("Embree error: {0}")]
    Call(String),
    /// The loaded library is not the version, or does not write the hit layout, that this
    /// build's declarations describe (`library_check`).
    #[error("Embree library mismatch: {0}")]
    Library(LibraryMismatch),
}

/// Why the loaded Embree library is not the one this build's declarations describe; the verdict
/// is kept for the process, so it is `Clone`.
#[derive(Clone, Debug, thiserror::Error)]
pub enum LibraryMismatch {
    /// A version outside [`super::ffi::SUPPORTED_VERSIONS`].
    #[error(
        "prism was built for {name} (library versions {min} to {max}), but the Embree library loaded is version {found}"
    )]
    Version {
        /// [`super::ffi::NAME`].
        name: &'static str,
        /// The first supported version.
        min: EmbreeVersion,
        /// The last supported version.
        max: EmbreeVersion,
        /// The library's version.
        found: EmbreeVersion,
    },
    /// The probe's hit record differs from [`super::ffi::RTCHit`].
    #[error(
        "the {name} library {version} writes a hit record other than prism's declarations (RTCHit of \
         {hit_bytes} bytes ending with {instance_words} instance words): hit {hit:?}, instance words \
         {words:x?}, words written past the record at {past:?}"
    )]
    HitLayout {
        /// [`super::ffi::NAME`].
        name: &'static str,
        /// The library's version.
        version: EmbreeVersion,
        /// `size_of::<RTCHit>()`.
        hit_bytes: usize,
        /// [`super::ffi::HIT_INSTANCE_WORDS`].
        instance_words: usize,
        /// geomID, primID and distance of the probe's hit.
        hit: (u32, u32, f32),
        /// The instance words Embree left.
        words: Vec<u32>,
        /// Words written past the declared record.
        past: Vec<usize>,
    },
    /// Building or committing the probe's scene failed.
    #[error("{0}")]
    Probe(Arc<EmbreeError>),
}

/// An Embree version, packed as MAJOR·10000 + MINOR·100 + PATCH; displayed dotted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EmbreeVersion(pub isize);

impl fmt::Display for EmbreeVersion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&dotted(self.0))
    }
}

/// Embree's packed version (MAJOR·10000 + MINOR·100 + PATCH) as "MAJOR.MINOR.PATCH".
pub(super) fn dotted(v: isize) -> String {
    format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100)
}

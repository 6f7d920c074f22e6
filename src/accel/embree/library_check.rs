//! The start-up check of the Embree library a device runs on, once per process: its version must
//! be one the declarations in [`super::ffi`] describe, and a hit must end where
//! [`ffi::RTCHit`] says. Embree writes the hit record of its own build (`instID[L]`, and since
//! 4.3 `instPrimID[L]`, for the `L` instance levels it was configured with); a record declared
//! smaller would let every `rtcIntersect1` write past the caller's struct.
//!
//! The layout is measured, not assumed: one ray is traced at a one-triangle scene into a hit
//! whose words, and a canary after the ray-hit, are filled with a pattern; Embree must write
//! exactly the words the declarations name (Ng, u, v, primID, geomID and the instance words)
//! and nothing after them.

use std::sync::{Arc, OnceLock};

use glam::Vec3;

use super::device::{Device, CONFIG_ENV};
use super::error::{EmbreeError, EmbreeVersion, LibraryMismatch};
use super::ffi;
use super::scene::{Scene, SceneHandle};
use super::TriangleTest;
use crate::geometry::{Mesh, Ray};

/// Fills the probed words; a value Embree never writes into a hit of this scene.
const PATTERN: u32 = 0xA5A5_A5A5;

/// Words of a hit before the instance words: Ng (3), u, v, primID, geomID.
const HIT_HEAD_WORDS: usize = 7;

/// A ray-hit followed by a canary, contiguous (`repr(C)`: the canary starts at
/// `size_of::<RTCRayHit>()`).
#[repr(C)]
pub(super) struct GuardedRayHit {
    pub(super) rh: ffi::RTCRayHit,
    canary: [u32; 16],
}

impl GuardedRayHit {
    /// `ray` with a hit and canary filled with [`PATTERN`] (geomID invalid, as Embree expects).
    pub(super) fn new(ray: ffi::RTCRay) -> Self {
        let mut g = Self { rh: ffi::RTCRayHit { ray, hit: ffi::RTCHit::default() }, canary: [PATTERN; 16] };
        g.hit_words_mut().fill(PATTERN);
        g.rh.hit.geomID = ffi::RTC_INVALID_GEOMETRY_ID;
        g
    }

    fn hit_words_mut(&mut self) -> &mut [u32] {
        let n = std::mem::size_of::<ffi::RTCHit>() / 4;
        // SAFETY: RTCHit is a repr(C) struct of 4-byte floats and integers (and tail padding to
        // its 16-byte alignment), so it is `n` initialised-or-padding u32 words; we own it
        // mutably, and every bit pattern is a valid f32/u32.
        unsafe { std::slice::from_raw_parts_mut((&mut self.rh.hit as *mut ffi::RTCHit).cast::<u32>(), n) }
    }

    /// The hit's words, then the canary's.
    pub(super) fn words(&self) -> Vec<u32> {
        let n = std::mem::size_of::<ffi::RTCHit>() / 4;
        // SAFETY: as in `hit_words_mut`, read-only.
        let hit = unsafe { std::slice::from_raw_parts((&self.rh.hit as *const ffi::RTCHit).cast::<u32>(), n) };
        hit.iter().chain(&self.canary).copied().collect()
    }

    /// Words after the ones a hit record of [`ffi`]'s declarations holds (the hit's tail padding
    /// and the canary) that no longer hold [`PATTERN`]: bytes written past the record.
    pub(super) fn overwritten_past_record(&self) -> Vec<usize> {
        let w = self.words();
        (HIT_HEAD_WORDS + ffi::HIT_INSTANCE_WORDS..w.len()).filter(|&k| w[k] != PATTERN).collect()
    }

    /// The instance words of the hit (after geomID).
    pub(super) fn instance_words(&self) -> Vec<u32> {
        self.words()[HIT_HEAD_WORDS..HIT_HEAD_WORDS + ffi::HIT_INSTANCE_WORDS].to_vec()
    }
}

// The checked constructors live beside the check: it builds a scene, which needs a device.
impl Device {
    /// Creates a device with the configuration in [`CONFIG_ENV`] (Embree's defaults if unset).
    pub fn new() -> Result<Self, EmbreeError> {
        Self::with_config(&std::env::var(CONFIG_ENV).unwrap_or_default())
    }

    /// Creates a device from an Embree configuration string. A failure (an unknown option, an
    /// unsupported CPU, no memory) is an error carrying Embree's code and message; so is a
    /// library other than the one this build's declarations describe (checked once per process,
    /// module docs).
    pub fn with_config(config: &str) -> Result<Self, EmbreeError> {
        let device = Self::unchecked(config)?;
        check_once(&device)?;
        Ok(device)
    }
}

/// Runs [`check_library`] on the first device of the process and returns its verdict after.
pub(super) fn check_once(device: &Device) -> Result<(), EmbreeError> {
    static VERDICT: OnceLock<Result<(), LibraryMismatch>> = OnceLock::new();
    VERDICT.get_or_init(|| check_library(device)).clone().map_err(EmbreeError::Library)
}

/// The version and hit-layout check (module docs).
fn check_library(device: &Device) -> Result<(), LibraryMismatch> {
    // SAFETY: `device` holds a valid device; the property is a plain query.
    let version =
        unsafe { ffi::rtcGetDeviceProperty(device.raw(), ffi::RTCDeviceProperty_RTC_DEVICE_PROPERTY_VERSION) };
    let range = ffi::SUPPORTED_VERSIONS;
    if !range.contains(&version) {
        return Err(LibraryMismatch::Version {
            name: ffi::NAME,
            min: EmbreeVersion(range.start),
            max: EmbreeVersion(range.end - 1),
            found: EmbreeVersion(version),
        });
    }
    let tri = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
    let probe = |e: EmbreeError| LibraryMismatch::Probe(Arc::new(e));
    let mut scene =
        SceneHandle::new(device, ffi::RTCBuildQuality_RTC_BUILD_QUALITY_LOW, TriangleTest::Embree).map_err(probe)?;
    scene.attach_mesh(device, &tri, 0).map_err(probe)?;
    scene.commit(device).map_err(probe)?;
    let ray = Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::NEG_Z);
    let mut g = GuardedRayHit::new(Scene::rtc_ray(&ray));
    let mut ctx = Scene::context();
    // SAFETY: committed scene; ctx and g are valid, aligned locals; the canary behind the
    // ray-hit absorbs what a larger hit record than declared would write.
    unsafe { ffi::intersect1(scene.raw, ctx.as_mut_ptr(), &mut g.rh) };
    let past = g.overwritten_past_record();
    let found = (g.rh.hit.geomID, g.rh.hit.primID, g.rh.ray.tfar);
    // The distance is 1 up to the rounding of the kernel Embree picks for the CPU (its AVX2
    // kernel returns 1 − 2⁻²⁴ here, its AVX-512 kernel exactly 1).
    let hit_found = found.0 == 0 && found.1 == 0 && (found.2 - 1.0).abs() <= 4.0 * f32::EPSILON;
    let instances_written = g.instance_words().iter().all(|&w| w == ffi::RTC_INVALID_GEOMETRY_ID);
    if !past.is_empty() || !hit_found || !instances_written {
        return Err(LibraryMismatch::HitLayout {
            name: ffi::NAME,
            version: EmbreeVersion(version),
            hit_bytes: std::mem::size_of::<ffi::RTCHit>(),
            instance_words: ffi::HIT_INSTANCE_WORDS,
            hit: found,
            words: g.instance_words(),
            past,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::error::dotted;
    use super::*;

    #[test]
    fn packed_versions_read_as_major_minor_patch() {
        assert_eq!(dotted(40400), "4.4.0");
        assert_eq!(dotted(31305), "3.13.5");
    }

    #[test]
    fn the_probe_pattern_marks_every_word_after_the_record_as_unwritten() {
        let g = GuardedRayHit::new(ffi::RTCRay::default());
        assert!(g.overwritten_past_record().is_empty());
        let mut h = GuardedRayHit::new(ffi::RTCRay::default());
        h.canary[0] = 0;
        let first_canary = std::mem::size_of::<ffi::RTCHit>() / 4;
        assert_eq!(h.overwritten_past_record(), vec![first_canary]);
    }
}

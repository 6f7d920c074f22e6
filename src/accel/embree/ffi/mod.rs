//! The Embree C API, version 3 (feature `embree`) or 4 (feature `embree4`), behind one set of
//! names. Private to `accel::embree`.
//!
//! Both versions are re-exported under the names bindgen gives Embree 3's declarations (types,
//! `Enum_CONSTANT` constants, `rtc*` functions). Where the two APIs differ, each version module
//! provides the same small shims, and the rest of the backend uses only those:
//! - [`QueryContext`] and [`query_context`]: the per-query context (`RTCIntersectContext` in
//!   Embree 3; `RTCRayQueryContext` in Embree 4, whose flags moved into the arguments struct);
//! - [`intersect1`] and [`occluded1`]: `rtcIntersect1`/`rtcOccluded1` (Embree 4 takes the context
//!   inside `RTCIntersectArguments`/`RTCOccludedArguments`);
//! - [`hit_instance_ids`]: the words a user-geometry hit copies from the context after `geomID`
//!   (`instID[L]`, and in Embree 4 with instance arrays also `instPrimID[L]`);
//! - [`SUPPORTED_VERSIONS`] and [`NAME`]: which library versions the declarations match.
//!
//! Ray masks need no shim: prism's rays carry mask 0xFFFFFFFF, which hits every geometry whatever
//! its default mask (0xFFFFFFFF in Embree 3, 0x1 in Embree 4). No filter function is used, so
//! Embree 4's `RTC_SCENE_FLAG_FILTER_FUNCTION_IN_ARGUMENTS` and `INVOKE_ARGUMENT_FILTER` are not
//! needed, and no stream query (`rtcIntersect1M`, gone in Embree 4) is used.

#[cfg(feature = "embree")]
mod embree3;
#[cfg(feature = "embree")]
pub use embree3::*;

#[cfg(feature = "embree4")]
mod embree4;
#[cfg(feature = "embree4")]
mod embree4_api;
#[cfg(feature = "embree4")]
pub use embree4::*;

#[cfg(all(feature = "embree", feature = "embree4"))]
compile_error!(
    "features `embree` (Embree 3) and `embree4` are mutually exclusive (both libraries export the \
     same rtc* symbols): build with `--no-default-features --features embree4,oiio`"
);

/// `RTC_INVALID_GEOMETRY_ID`, `(unsigned int)-1` in both versions (a macro with a cast, which
/// bindgen does not emit).
pub const RTC_INVALID_GEOMETRY_ID: u32 = u32::MAX;

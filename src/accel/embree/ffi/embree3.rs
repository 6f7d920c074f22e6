//! Embree 3: the bindings bindgen generated from `embree3/rtcore.h` in build.rs, and the shims
//! of [`super`] written for its API.
#![allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code, clippy::all)]

include!(concat!(env!("OUT_DIR"), "/embree3_bindings.rs"));

use super::RTC_INVALID_GEOMETRY_ID;

/// The library this build links, for messages.
pub const NAME: &str = "Embree 3";

/// Library versions (`RTC_DEVICE_PROPERTY_VERSION`, e.g. 31305 for 3.13.5) whose layouts these
/// bindings match: any Embree 3, since bindgen read the installed header.
pub const SUPPORTED_VERSIONS: std::ops::Range<isize> = 30000..40000;

/// The context every query passes (the user-geometry callbacks receive this pointer).
pub type QueryContext = RTCIntersectContext;

/// `rtcInitIntersectContext` (force-inlined in rtcore_ray.h, so bindgen does not emit it):
/// incoherent rays, no filter, an empty instance stack.
#[inline(always)]
pub fn query_context() -> QueryContext {
    RTCIntersectContext {
        flags: RTCIntersectContextFlags_RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
        filter: None,
        instID: [RTC_INVALID_GEOMETRY_ID; RTC_MAX_INSTANCE_LEVEL_COUNT as usize],
    }
}

/// Words of a hit record after `geomID` that a user geometry copies from the context.
pub const HIT_INSTANCE_WORDS: usize = RTC_MAX_INSTANCE_LEVEL_COUNT as usize;

/// The context's instance stack, as a hit stores it: `instID[0..L]`.
#[inline(always)]
pub fn hit_instance_ids(ctx: &QueryContext) -> [u32; HIT_INSTANCE_WORDS] {
    ctx.instID
}

/// Closest hit of one ray.
///
/// # Safety
/// `scene` is committed; `ctx` and `rayhit` point to valid, aligned, writable structs.
#[inline(always)]
pub unsafe fn intersect1(scene: RTCScene, ctx: *mut QueryContext, rayhit: *mut RTCRayHit) {
    // SAFETY: by the caller's contract.
    unsafe { rtcIntersect1(scene, ctx, rayhit) }
}

/// Any hit of one ray (Embree sets `tfar = −∞` when there is one).
///
/// # Safety
/// As [`intersect1`].
#[inline(always)]
pub unsafe fn occluded1(scene: RTCScene, ctx: *mut QueryContext, ray: *mut RTCRay) {
    // SAFETY: by the caller's contract.
    unsafe { rtcOccluded1(scene, ctx, ray) }
}

/// Which lanes of a packet of sixteen to trace (−1) or skip (0); Embree loads it as one
/// vector, so it is aligned as the packet.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug, Default)]
pub struct Valid16(pub [i32; 16]);

/// Closest hits of a packet of sixteen rays.
///
/// # Safety
/// `scene` is committed; `ctx` and `rayhit` point to valid, writable structs, `rayhit` 64-byte
/// aligned (`RTCRayHit16` is).
#[inline(always)]
pub unsafe fn intersect16(valid: &Valid16, scene: RTCScene, ctx: *mut QueryContext, rayhit: *mut RTCRayHit16) {
    // SAFETY: by the caller's contract; `valid` is 16 ints, 64-byte aligned.
    unsafe { rtcIntersect16(valid.0.as_ptr(), scene, ctx, rayhit) }
}

/// Any hits of a packet of sixteen rays (Embree sets `tfar = −∞` in the lanes that have one).
///
/// # Safety
/// As [`intersect16`].
#[inline(always)]
pub unsafe fn occluded16(valid: &Valid16, scene: RTCScene, ctx: *mut QueryContext, ray: *mut RTCRay16) {
    // SAFETY: by the caller's contract.
    unsafe { rtcOccluded16(valid.0.as_ptr(), scene, ctx, ray) }
}

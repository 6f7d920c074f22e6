//! Embree 4: the declarations of [`super::embree4_api`] and the shims of [`super`] written for
//! its API (Embree 4 API changes: the context initialisers are inline header functions, the
//! query flags and context travel in `RTCIntersectArguments`/`RTCOccludedArguments`).

pub use super::embree4_api::*;
use super::RTC_INVALID_GEOMETRY_ID;

/// The library this build links, for messages.
pub const NAME: &str = "Embree 4";

/// Library versions (`RTC_DEVICE_PROPERTY_VERSION`, e.g. 40400 for 4.4.0) whose layouts the
/// declarations match: 4.3 introduced `instPrimID` in hits and contexts.
pub const SUPPORTED_VERSIONS: std::ops::Range<isize> = 40300..50000;

/// The context every query passes (the user-geometry callbacks receive this pointer).
pub type QueryContext = RTCRayQueryContext;

/// `rtcInitRayQueryContext` (an inline function of rtcore_common.h): empty instance stacks.
#[inline(always)]
pub fn query_context() -> QueryContext {
    RTCRayQueryContext {
        instID: [RTC_INVALID_GEOMETRY_ID; RTC_MAX_INSTANCE_LEVEL_COUNT as usize],
        instPrimID: [RTC_INVALID_GEOMETRY_ID; RTC_MAX_INSTANCE_LEVEL_COUNT as usize],
    }
}

/// Words of a hit record after `geomID` that a user geometry copies from the context.
pub const HIT_INSTANCE_WORDS: usize = 2 * RTC_MAX_INSTANCE_LEVEL_COUNT as usize;

/// The context's instance stacks, as a hit stores them: `instID[0..L]`, then `instPrimID[0..L]`.
#[inline(always)]
pub fn hit_instance_ids(ctx: &QueryContext) -> [u32; HIT_INSTANCE_WORDS] {
    const L: usize = RTC_MAX_INSTANCE_LEVEL_COUNT as usize;
    let mut words = [RTC_INVALID_GEOMETRY_ID; HIT_INSTANCE_WORDS];
    words[..L].copy_from_slice(&ctx.instID);
    words[L..].copy_from_slice(&ctx.instPrimID);
    words
}

/// Closest hit of one ray: `rtcIntersect1` with the arguments `rtcInitIntersectArguments` gives
/// (incoherent rays, every feature, no filter, no argument callback) and `ctx` as the context.
///
/// # Safety
/// `scene` is committed; `ctx` and `rayhit` point to valid, aligned, writable structs.
#[inline(always)]
pub unsafe fn intersect1(scene: RTCScene, ctx: *mut QueryContext, rayhit: *mut RTCRayHit) {
    let mut args = RTCIntersectArguments {
        flags: RTCRayQueryFlags_RTC_RAY_QUERY_FLAG_INCOHERENT,
        feature_mask: RTCFeatureFlags_RTC_FEATURE_FLAG_ALL,
        context: ctx,
        filter: None,
        intersect: None,
        minWidthDistanceFactor: 0.0,
    };
    // SAFETY: by the caller's contract; `args` lives for the call.
    unsafe { rtcIntersect1(scene, rayhit, &mut args) }
}

/// Any hit of one ray (Embree sets `tfar = −∞` when there is one): `rtcOccluded1` with the
/// arguments `rtcInitOccludedArguments` gives and `ctx` as the context.
///
/// # Safety
/// As [`intersect1`].
#[inline(always)]
pub unsafe fn occluded1(scene: RTCScene, ctx: *mut QueryContext, ray: *mut RTCRay) {
    let mut args = RTCOccludedArguments {
        flags: RTCRayQueryFlags_RTC_RAY_QUERY_FLAG_INCOHERENT,
        feature_mask: RTCFeatureFlags_RTC_FEATURE_FLAG_ALL,
        context: ctx,
        filter: None,
        occluded: None,
        minWidthDistanceFactor: 0.0,
    };
    // SAFETY: by the caller's contract; `args` lives for the call.
    unsafe { rtcOccluded1(scene, ray, &mut args) }
}

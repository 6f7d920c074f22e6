//! The context every Embree query passes: Embree's own, extended with the per-ray data the
//! user-geometry callbacks read.

use super::ffi;
use crate::accel::watertight::LaneRay;
use glam::Vec3;
use std::cell::Cell;

/// The context of every query: Embree's, extended with per-ray data for the user-geometry
/// callbacks (Embree passes the caller's context pointer through to them, so it may start a
/// larger struct; `RTCIntersectContext` in Embree 3, `RTCRayQueryContext` in Embree 4).
#[repr(C)]
pub(super) struct RayContext {
    pub(super) rtc: ffi::QueryContext,
    /// The watertight test's per-ray constants, computed by the first triangle test of a ray.
    pub(super) shear: ShearCache,
}

impl RayContext {
    /// The pointer to hand to `rtcIntersect1`/`rtcOccluded1` (to the whole struct, so the
    /// callbacks may read `shear` through it).
    #[inline]
    pub(super) fn as_mut_ptr(&mut self) -> *mut ffi::QueryContext {
        (self as *mut Self).cast()
    }
}

/// The watertight test's per-ray constants for the last ray seen (keyed by the bits of its
/// origin and direction, which differ under each instance's transform), so that the shear's
/// three divisions are done once per ray and not once per triangle.
#[derive(Default)]
pub(super) struct ShearCache(Cell<Option<([u32; 6], Option<LaneRay>)>>);

impl ShearCache {
    /// [`LaneRay::new`]`(o, d)`, computed at most once per (o, d) in a row.
    #[inline(always)]
    pub(super) fn get(&self, o: Vec3, d: Vec3) -> Option<LaneRay> {
        let key = [o.x, o.y, o.z, d.x, d.y, d.z].map(f32::to_bits);
        match self.0.get() {
            Some((k, ray)) if k == key => ray,
            _ => {
                let ray = LaneRay::new(o, d);
                self.0.set(Some((key, ray)));
                ray
            }
        }
    }
}

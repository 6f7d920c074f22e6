//! pbrt-v4's curves as Embree *user geometry* (`RTC_GEOMETRY_TYPE_USER`), intersected by
//! prism's own curve test ([`intersect_curve`], pbrt-v4's `Curve::IntersectRay`, PBR 4th ed.
//! §6.7.2) so that Embree finds the hits the obvhs backend finds.
//!
//! Why not Embree's own curves (`curves.rs`): Embree's flat curves are ray-facing quads, four
//! per segment by default (its tessellation rate), so a strongly bent segment renders as a
//! polyline, and pbrt-v4 subdivides each segment until it is straight to a twentieth of the width
//! and measures the ray's distance from the curve point nearest the chord's. Embree's
//! `NORMAL_ORIENTED_BEZIER_CURVE` is a true surface swept across the normal curve that Embree
//! interpolates from per-control-point normals, while pbrt-v4 orients a ribbon at u by the
//! spherical interpolation of its two end normals and intersects the strip facing the ray,
//! w·|n(u)·d̂| wide, at the centre line's depth. Both differ from pbrt-v4's curves by far more
//! than rounding (docs/benchmarks.md, "Curves on Embree").
//!
//! The primitives are the curve pieces (each segment split into 2^splitdepth u ranges, as the
//! obvhs curve BVH and pbrt-v4 split them), boxed by their control hulls grown by half their
//! width. The hit record is t, u along the segment, primID = the segment's index (as Embree's own
//! curves report), Ng = 0; the interaction recomputes the surface from the ray and u
//! ([`crate::geometry::curve_hit::curve_surface`]). Conventions, those of the quadrics' user
//! geometry (`quadrics.rs`): a closest hit is accepted for tnear ≤ t ≤ tfar (a tie keeps the
//! smaller (instID, geomID, primID)), an occlusion for tnear ≤ t < tfar; `valid[i]` is set to 0
//! for a lane that missed. Curves are static: rays reach the callbacks without a time.

use super::device::{Device, EmbreeError};
use super::ffi;
use super::ray_context::RayContext;
use super::user_triangles::{for_each_valid_lane, new_user_geometry, UserCallbacks};
use crate::geometry::curve_hit::intersect_curve;
use crate::geometry::{CurveSegment, Curves, Ray};
use glam::Vec3;

/// One Embree primitive: a u range of a segment.
#[derive(Clone, Copy, Debug)]
struct Piece {
    /// Index into `UserCurves::segments`.
    segment: u32,
    /// The segment's index in its curves (the hit's primID).
    prim_id: u32,
    u: [f32; 2],
}

/// The segments of one curve shape and their pieces; Embree's user primitive `k` is
/// `pieces[k]`. Boxed by its owner: Embree holds its address as the geometry's user pointer.
pub(super) struct UserCurves {
    segments: Vec<CurveSegment>,
    pieces: Vec<Piece>,
}

impl UserCurves {
    /// The pieces of `curves` whose control points and widths are finite.
    fn new(curves: &Curves) -> Self {
        let finite = |s: &CurveSegment| s.cp.iter().all(|p| p.is_finite()) && s.width.iter().all(|w| w.is_finite());
        let mut index = vec![u32::MAX; curves.segments.len()];
        let mut segments = Vec::new();
        for (prim, s) in curves.segments.iter().enumerate().filter(|(_, s)| finite(s)) {
            index[prim] = segments.len() as u32;
            segments.push(*s);
        }
        let pieces = curves
            .pieces()
            .filter(|&(prim, _)| index[prim as usize] != u32::MAX)
            .map(|(prim, u)| Piece { segment: index[prim as usize], prim_id: prim, u })
            .collect();
        Self { segments, pieces }
    }

    /// Bytes of segment and piece storage (held by prism, not by Embree's allocator).
    pub(super) fn bytes(&self) -> usize {
        std::mem::size_of_val(&self.segments[..]) + std::mem::size_of_val(&self.pieces[..])
    }

    /// The closest hit (t, u) of `ray` on piece `k` with t ≤ `t_max`, or with `any` the first
    /// found.
    #[inline]
    fn hit(&self, k: usize, ray: &Ray, t_max: f32, any: bool) -> Option<(f32, f32, u32)> {
        let p = self.pieces[k];
        let h = intersect_curve(&self.segments[p.segment as usize], p.u[0], p.u[1], ray, t_max, any)?;
        Some((h.t, h.u, p.prim_id))
    }
}

/// Creates a committed user geometry for `curves`, not yet attached. The returned
/// box must outlive every scene the geometry is attached to.
pub(super) fn new_geometry(
    device: &Device,
    curves: &Curves,
) -> Result<(ffi::RTCGeometry, Box<UserCurves>), EmbreeError> {
    let user = Box::new(UserCurves::new(curves));
    let count = user.pieces.len() as u32;
    let geom = new_user_geometry(device, &*user, count, UserCallbacks { bounds, intersect, occluded })?;
    Ok((geom, user))
}

unsafe extern "C" fn bounds(args: *const ffi::RTCBoundsFunctionArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call; the user pointer is
    // the UserCurves given to rtcSetGeometryBoundsFunction, and primID < its piece count.
    unsafe {
        let args = &*args;
        let r = &*(args.geometryUserPtr as *const UserCurves);
        let p = r.pieces[args.primID as usize];
        let b = r.segments[p.segment as usize].bounds(p.u[0], p.u[1]);
        *args.bounds_o = ffi::RTCBounds {
            lower_x: b.min.x,
            lower_y: b.min.y,
            lower_z: b.min.z,
            align0: 0.0,
            upper_x: b.max.x,
            upper_y: b.max.y,
            upper_z: b.max.z,
            align1: 0.0,
        };
    }
}

unsafe extern "C" fn intersect(args: *const ffi::RTCIntersectFunctionNArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call: `valid` has N entries,
    // `rayhit` is an RTCRayHitN of width N (all fields up to the last instance word), `context`
    // is the caller's RayContext (every query passes one: Scene::context), and the user pointer
    // is the geometry's UserCurves with primID < its piece count.
    unsafe {
        let args = &*args;
        let r = &*(args.geometryUserPtr as *const UserCurves);
        let ctx = &*(args.context as *const RayContext);
        let inst = ffi::hit_instance_ids(&ctx.rtc);
        for_each_valid_lane(args.valid, args.N, args.rayhit as *mut f32, |lane| {
            let (o, d, tnear, tfar) = lane.ray();
            let hit = r.hit(args.primID as usize, &Ray::segment(o, d, tfar), tfar, false);
            let Some((t, u, prim_id)) = hit.filter(|h| h.0 >= tnear) else { return false };
            lane.record_hit(t, Vec3::ZERO, (u, 0.0), (args.geomID, prim_id), &inst)
        });
    }
}

unsafe extern "C" fn occluded(args: *const ffi::RTCOccludedFunctionNArguments) {
    // SAFETY: as in `intersect`; `ray` is an RTCRayN of width N.
    unsafe {
        let args = &*args;
        let r = &*(args.geometryUserPtr as *const UserCurves);
        for_each_valid_lane(args.valid, args.N, args.ray as *mut f32, |lane| {
            let (o, d, tnear, tfar) = lane.ray();
            let hit = r.hit(args.primID as usize, &Ray::segment(o, d, tfar), tfar, true);
            if hit.is_some_and(|(t, _, _)| t >= tnear && t < tfar) {
                lane.mark_occluded();
                return true;
            }
            false
        });
    }
}

#[cfg(test)]
#[path = "user_curves_tests.rs"]
mod tests;

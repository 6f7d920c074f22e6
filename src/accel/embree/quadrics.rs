//! Quadrics as Embree *user geometry* (`RTC_GEOMETRY_TYPE_USER`): one geometry of one primitive
//! per quadric, whose bounds callback gives its world box and whose intersect and occluded
//! callbacks run the exact object-space test ([`PlacedQuadric::intersect`]) on the rays that may
//! meet that box. (Embree tests no box before the callback of a geometry's only primitive, so
//! without the slab test every ray of the scene paid for the object-space test.) The hit record
//! carries only t (and the geometry id): the interaction recomputes the surface from the ray and
//! t, as for the obvhs backend's quadrics, so both backends shade the same point.
//!
//! Conventions, those of the watertight triangles' user geometry (`user_triangles.rs`): a
//! closest hit is accepted for tnear ≤ t ≤ tfar (a tie keeps the smaller geometry id), an
//! occlusion for tnear ≤ t < tfar; `valid[i]` is set to 0 for a lane that missed; the instance
//! stack is copied from the query context. Only static quadrics are attached here (rays reach
//! the callbacks without prism's time): moving ones stay in the BVH beside the scene.

use glam::Vec3;

use super::device::{Device, EmbreeError};
use super::ffi;
use super::ray_context::RayContext;
use super::user_triangles::{for_each_valid_lane, new_user_geometry, UserCallbacks};
use crate::geometry::{Bounds3, PlacedQuadric, Ray};
use crate::math::offset::next_float_up;

/// A quadric with its world box, as the callbacks read it.
pub(super) struct UserQuadric {
    quadric: PlacedQuadric,
    bounds: Bounds3,
}

impl UserQuadric {
    /// The nearest hit's t in [tnear, `t_max`) of the lane's ray, if the ray may meet the box.
    #[inline(always)]
    fn hit(&self, o: Vec3, d: Vec3, tnear: f32, t_max: f32) -> Option<f32> {
        if !self.bounds.may_hit(o, d, t_max) {
            return None;
        }
        self.quadric.intersect(&ray(o, d, t_max), t_max).filter(|&t| t >= tnear)
    }
}

/// Creates a committed user geometry for `quadric`, not yet attached. The returned box must
/// outlive every scene the geometry is attached to.
pub(super) fn new_geometry(
    device: &Device,
    quadric: &PlacedQuadric,
) -> Result<(ffi::RTCGeometry, Box<UserQuadric>), EmbreeError> {
    let user = Box::new(UserQuadric { quadric: quadric.clone(), bounds: quadric.bounds() });
    let geom = new_user_geometry(device, &*user, 1, UserCallbacks { bounds, intersect, occluded })?;
    Ok((geom, user))
}

unsafe extern "C" fn bounds(args: *const ffi::RTCBoundsFunctionArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call; the user pointer is
    // the UserQuadric given to rtcSetGeometryBoundsFunction.
    unsafe {
        let args = &*args;
        let b = (*(args.geometryUserPtr as *const UserQuadric)).bounds;
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

/// The world ray of a lane (time 0: only static quadrics are attached).
#[inline(always)]
fn ray(o: Vec3, d: Vec3, tfar: f32) -> Ray {
    Ray::segment(o, d, tfar)
}

unsafe extern "C" fn intersect(args: *const ffi::RTCIntersectFunctionNArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call: `valid` has N entries,
    // `rayhit` is an RTCRayHitN of width N (all fields up to the last instance word), `context`
    // is the caller's RayContext (every query passes one: Scene::context), and the user pointer
    // is the geometry's UserQuadric.
    unsafe {
        let args = &*args;
        let q = &*(args.geometryUserPtr as *const UserQuadric);
        let ctx = &*(args.context as *const RayContext);
        let inst = ffi::hit_instance_ids(&ctx.rtc);
        for_each_valid_lane(args.valid, args.N, args.rayhit as *mut f32, |lane| {
            let (o, d, tnear, tfar) = lane.ray();
            // Quadric::intersect excludes its limit; a closest hit may equal tfar.
            let Some(t) = q.hit(o, d, tnear, next_float_up(tfar)) else {
                return false;
            };
            lane.record_hit(t, Vec3::ZERO, (0.0, 0.0), (args.geomID, 0), &inst)
        });
    }
}

unsafe extern "C" fn occluded(args: *const ffi::RTCOccludedFunctionNArguments) {
    // SAFETY: as in `intersect`; `ray` is an RTCRayN of width N.
    unsafe {
        let args = &*args;
        let q = &*(args.geometryUserPtr as *const UserQuadric);
        for_each_valid_lane(args.valid, args.N, args.ray as *mut f32, |lane| {
            let (o, d, tnear, tfar) = lane.ray();
            if q.hit(o, d, tnear, tfar).is_some() {
                lane.mark_occluded();
                return true;
            }
            false
        });
    }
}

//! Triangle meshes as Embree *user geometry* (`RTC_GEOMETRY_TYPE_USER`) whose intersect and
//! occluded callbacks run prism's watertight ray–triangle test ([`crate::accel::watertight`],
//! Woop, Benthin, Wald 2013) instead of Embree's triangle kernel.
//!
//! Why: Embree 3.13's robust triangle kernel (`BVH8Triangle4vIntersector1Pluecker`) lets rays
//! aimed exactly at a vertex through a closed mesh (docs/benchmarks.md, "Why Embree leaks at
//! vertices"); no flag or kernel choice of Embree 3 fixes it, and Embree 4.4's
//! `RTC_SCENE_FLAG_ROBUST` behaves the same. Embree still builds and traverses the BVH (over our
//! per-triangle boxes); only the leaf test is ours.
//!
//! Conventions, those of the triangle path (scene.rs) and of obvhs:
//! - A closest hit is accepted for tnear ≤ t ≤ tfar; the hit record is t (in tfar), u, v (the
//!   weights of p1 and p2), Ng = (p1−p0)×(p2−p0) in the geometry's space (object space under an
//!   instance, as Embree reports for triangles), primID = the mesh's triangle index, geomID, and
//!   the instance stacks copied from the query context (Embree leaves that to user geometry):
//!   `instID`, and in Embree 4 also `instPrimID` ([`ffi::hit_instance_ids`]).
//! - Each callback leaves `valid[i] = -1` for a ray it hit and sets `valid[i] = 0` for one it
//!   missed: Embree 4 reads the mask back as the callback's answer (an occluded callback that
//!   leaves −1 stops the ray as occluded); Embree 3 ignores it.
//! - Equally distant hits are resolved by the smallest (instID, geomID, primID), as the obvhs
//!   backend does, so results do not depend on Embree's traversal order.
//! - An occlusion counts for tnear ≤ t < tfar (the `Accel::occluded` range (0, t_max)).
//!
//! - The shear constants of the test (three divisions) are computed once per ray: every query
//!   passes a [`RayContext`] that caches them, keyed by the ray as the callback sees it.
//!
//! Callbacks receive rays in Embree's structure-of-arrays layout of width N (rtcore_ray.h,
//! `RTCRayN_*`/`RTCHitN_*`: field k of ray i at float index k·N + i); `rtcIntersect1` passes
//! N = 1, whose layout is `RTCRayHit`'s.

use std::os::raw::{c_int, c_uint};

use glam::Vec3;

use super::device::{Device, EmbreeError};
use super::ffi;
use super::ray_context::RayContext;
use crate::accel::watertight::TriangleLanes;
use crate::geometry::Mesh;

/// Margin by which primitive boxes are grown, relative to the mesh's largest coordinate
/// magnitude M. A ray through a triangle's edge or vertex lies on its box's face and must never
/// be culled there; Embree traverses user geometry with its non-robust slab test,
/// t = lower·(1/d) − o·(1/d) (FMA), whose rounding is about 2⁻²⁴·|o|/|d|. A margin of 2⁻¹⁸·M
/// covers it for ray origins up to ~60·M from the origin of the mesh's space (object space
/// under an instance); it grows the boxes of the 1M-triangle benchmark terrain by ~0.2%.
const BOX_PAD: f32 = 1.0 / (1u32 << 18) as f32;

/// One triangle, lane-wise, with its index in the mesh; one 64-byte cache line.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct UserTriangle {
    lanes: TriangleLanes,
    prim_id: u32,
}

/// The triangles of one mesh that can be hit (finite, non-zero area, indices in range; the same
/// ones the obvhs backend keeps), in mesh order. Embree's user primitive `k` is `triangles[k]`.
/// Boxed by its owner: Embree holds its address as the geometry's user pointer.
pub(super) struct UserMesh {
    triangles: Vec<UserTriangle>,
    /// Absolute box margin: `BOX_PAD` × the largest vertex coordinate magnitude.
    pad: f32,
}

impl UserMesh {
    fn new(mesh: &Mesh) -> Self {
        let mut triangles = Vec::with_capacity(mesh.len());
        let mut magnitude = 0.0f32;
        for (prim_id, idx) in mesh.indices.iter().enumerate() {
            let Some(p) = idx.iter().map(|&i| mesh.positions.get(i as usize).copied()).collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            let p = [p[0], p[1], p[2]];
            if p.iter().all(|v| v.is_finite()) && (p[1] - p[0]).cross(p[2] - p[0]) != Vec3::ZERO {
                triangles.push(UserTriangle { lanes: TriangleLanes::new(p), prim_id: prim_id as u32 });
                magnitude = p.iter().fold(magnitude, |m, v| m.max(v.abs().max_element()));
            }
        }
        Self { triangles, pad: magnitude * BOX_PAD + f32::MIN_POSITIVE }
    }

    /// Bytes of triangle storage (held by prism, not by Embree's allocator).
    pub(super) fn bytes(&self) -> usize {
        std::mem::size_of_val(&self.triangles[..])
    }
}

/// Creates a committed user geometry for `mesh`, not yet attached. The returned `UserMesh`
/// must outlive every scene the geometry is attached to.
pub(super) fn new_geometry(device: &Device, mesh: &Mesh) -> Result<(ffi::RTCGeometry, Box<UserMesh>), EmbreeError> {
    let user = Box::new(UserMesh::new(mesh));
    let count = user.triangles.len() as u32;
    let geom = new_user_geometry(device, &*user, count, UserCallbacks { bounds, intersect, occluded })?;
    Ok((geom, user))
}

/// The three callbacks of a user geometry.
pub(super) struct UserCallbacks {
    pub bounds: unsafe extern "C" fn(*const ffi::RTCBoundsFunctionArguments),
    pub intersect: unsafe extern "C" fn(*const ffi::RTCIntersectFunctionNArguments),
    pub occluded: unsafe extern "C" fn(*const ffi::RTCOccludedFunctionNArguments),
}

/// A committed user geometry of `count` primitives whose callbacks read `user`. `user` must be
/// heap-allocated (its address fixed) and outlive every scene the geometry is attached to.
pub(super) fn new_user_geometry<T>(
    device: &Device,
    user: &T,
    count: u32,
    callbacks: UserCallbacks,
) -> Result<ffi::RTCGeometry, EmbreeError> {
    let ptr = user as *const T as *mut std::ffi::c_void;
    // SAFETY: valid device; `ptr` points to the caller's boxed data, whose heap address does not
    // change when the Box moves and which the caller keeps alive as long as the geometry; the
    // callbacks only read through it.
    let geom = unsafe {
        let geom = ffi::rtcNewGeometry(device.raw(), ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_USER);
        if geom.is_null() {
            return Err(EmbreeError::Call(device.take_error().unwrap_or_default()));
        }
        ffi::rtcSetGeometryUserPrimitiveCount(geom, count);
        ffi::rtcSetGeometryUserData(geom, ptr);
        ffi::rtcSetGeometryBoundsFunction(geom, Some(callbacks.bounds), ptr);
        ffi::rtcSetGeometryIntersectFunction(geom, Some(callbacks.intersect));
        ffi::rtcSetGeometryOccludedFunction(geom, Some(callbacks.occluded));
        ffi::rtcCommitGeometry(geom);
        geom
    };
    if let Some(e) = device.take_error() {
        // SAFETY: `geom` is a valid geometry we own one reference to.
        unsafe { ffi::rtcReleaseGeometry(geom) };
        return Err(EmbreeError::Call(e));
    }
    Ok(geom)
}

/// The triangle's box grown by `pad` (see [`BOX_PAD`]).
fn padded_bounds(t: &UserTriangle, pad: f32) -> ffi::RTCBounds {
    let [a, b, c] = t.lanes.vertices();
    let (lo, hi) = (a.min(b).min(c) - pad, a.max(b).max(c) + pad);
    ffi::RTCBounds {
        lower_x: lo.x,
        lower_y: lo.y,
        lower_z: lo.z,
        align0: 0.0,
        upper_x: hi.x,
        upper_y: hi.y,
        upper_z: hi.z,
        align1: 0.0,
    }
}

unsafe extern "C" fn bounds(args: *const ffi::RTCBoundsFunctionArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call; the user pointer is
    // the UserMesh given to rtcSetGeometryBoundsFunction, and primID < the primitive count.
    unsafe {
        let args = &*args;
        let mesh = &*(args.geometryUserPtr as *const UserMesh);
        *args.bounds_o = padded_bounds(&mesh.triangles[args.primID as usize], mesh.pad);
    }
}

/// Float indices of `RTCRayHitN` fields, in units of N (rtcore_ray.h, the same in Embree 3 and 4).
pub(super) mod field {
    pub const ORG: usize = 0;
    pub const TNEAR: usize = 3;
    pub const DIR: usize = 4;
    pub const TFAR: usize = 8;
    pub const NG: usize = 12;
    pub const U: usize = 15;
    pub const V: usize = 16;
    pub const PRIM_ID: usize = 17;
    pub const GEOM_ID: usize = 18;
    /// `instID[0]`; the further instance words of [`super::ffi::hit_instance_ids`] follow.
    pub const INST_ID: usize = 19;
}

/// Ray `i` of a structure-of-arrays packet of width `n` starting at `base`.
pub(super) struct Lane {
    pub(super) base: *mut f32,
    pub(super) n: usize,
    pub(super) i: usize,
}

impl Lane {
    /// # Safety
    /// `k·n + i` must index a float of the packet.
    #[inline(always)]
    pub(super) unsafe fn get(&self, k: usize) -> f32 {
        // SAFETY: by the caller's contract.
        unsafe { *self.base.add(k * self.n + self.i) }
    }
    /// # Safety
    /// As [`Lane::get`], and the packet must be writable.
    #[inline(always)]
    pub(super) unsafe fn set(&self, k: usize, x: f32) {
        // SAFETY: by the caller's contract.
        unsafe { *self.base.add(k * self.n + self.i) = x }
    }
    /// # Safety
    /// As [`Lane::get`] for fields 0..=8.
    #[inline(always)]
    pub(super) unsafe fn ray(&self) -> (Vec3, Vec3, f32, f32) {
        // SAFETY: by the caller's contract.
        unsafe {
            let v = |k: usize| Vec3::new(self.get(k), self.get(k + 1), self.get(k + 2));
            (v(field::ORG), v(field::DIR), self.get(field::TNEAR), self.get(field::TFAR))
        }
    }

    /// Makes the hit at `t` (geometric normal `ng`, (u, v), `geom_id`, `prim_id`, in the
    /// instances `inst`) the lane's hit; `false`, changing nothing, when it ties the current hit
    /// (t = tfar) and that one has the smaller (instID, geomID, primID), as obvhs decides ties.
    ///
    /// # Safety
    /// As [`Lane::set`] for every field of an `RTCRayHitN` up to its last instance word.
    #[inline(always)]
    pub(super) unsafe fn record_hit(&self, t: f32, ng: Vec3, uv: (f32, f32), ids: (u32, u32), inst: &[u32]) -> bool {
        let (geom_id, prim_id) = ids;
        // SAFETY: by the caller's contract.
        unsafe {
            if t == self.get(field::TFAR) {
                let old_geom = self.get(field::GEOM_ID).to_bits();
                let old = (self.get(field::INST_ID).to_bits(), old_geom, self.get(field::PRIM_ID).to_bits());
                if old_geom != ffi::RTC_INVALID_GEOMETRY_ID && (inst[0], geom_id, prim_id) >= old {
                    return false;
                }
            }
            self.set(field::TFAR, t);
            for (k, x) in ng.to_array().into_iter().enumerate() {
                self.set(field::NG + k, x);
            }
            self.set(field::U, uv.0);
            self.set(field::V, uv.1);
            self.set(field::PRIM_ID, f32::from_bits(prim_id));
            self.set(field::GEOM_ID, f32::from_bits(geom_id));
            for (l, &id) in inst.iter().enumerate() {
                self.set(field::INST_ID + l, f32::from_bits(id));
            }
        }
        true
    }

    /// Marks the ray occluded, by Embree's convention: tfar = −∞.
    ///
    /// # Safety
    /// As [`Lane::set`] for tfar.
    #[inline(always)]
    pub(super) unsafe fn mark_occluded(&self) {
        // SAFETY: by the caller's contract.
        unsafe { self.set(field::TFAR, f32::NEG_INFINITY) }
    }
}

/// Calls `test` on each lane of a callback's packet that `valid` marks valid, and marks the lane
/// invalid (a miss) where `test` returns false.
///
/// # Safety
/// `valid` has `n` entries and `base` is a packet of width `n` holding every field `test` reads
/// or writes.
#[inline(always)]
pub(super) unsafe fn for_each_valid_lane(
    valid: *mut c_int,
    n: c_uint,
    base: *mut f32,
    mut test: impl FnMut(&Lane) -> bool,
) {
    let n = n as usize;
    if n == 1 {
        // One ray (rtcIntersect1/rtcOccluded1, every query of the path tracer): the lane's
        // field offsets are constants.
        // SAFETY: by the caller's contract, `valid` has one entry and `base` is one ray.
        unsafe {
            if *valid != 0 && !test(&Lane { base, n: 1, i: 0 }) {
                *valid = 0;
            }
        }
        return;
    }
    for i in 0..n {
        // SAFETY: by the caller's contract, `i` < n indexes `valid` and a lane of the packet.
        unsafe {
            let v = valid.add(i);
            if *v != 0 && !test(&Lane { base, n, i }) {
                *v = 0;
            }
        }
    }
}

unsafe extern "C" fn intersect(args: *const ffi::RTCIntersectFunctionNArguments) {
    // SAFETY: Embree passes valid arguments for the duration of the call: `valid` has N entries,
    // `rayhit` is an RTCRayHitN of width N (all fields up to the last instance word),
    // `context` is the caller's context, which every query in this module makes a RayContext
    // (Scene::context), and the user pointer is the geometry's UserMesh with primID < its count.
    unsafe {
        let args = &*args;
        let mesh = &*(args.geometryUserPtr as *const UserMesh);
        let tri = &mesh.triangles[args.primID as usize];
        let ctx = &*(args.context as *const RayContext);
        let inst = ffi::hit_instance_ids(&ctx.rtc);
        for_each_valid_lane(args.valid, args.N, args.rayhit as *mut f32, |lane| {
            let (o, d, tnear, tfar) = lane.ray();
            let hit = ctx.shear.get(o, d).and_then(|r| r.intersect_any_axis(&tri.lanes, tfar));
            let Some(h) = hit.filter(|h| h.t >= tnear) else { return false };
            let [p0, p1, p2] = tri.lanes.vertices();
            let ng = (p1 - p0).cross(p2 - p0);
            lane.record_hit(h.t, ng, (h.u, h.v), (args.geomID, tri.prim_id), &inst)
        });
    }
}

unsafe extern "C" fn occluded(args: *const ffi::RTCOccludedFunctionNArguments) {
    // SAFETY: as in `intersect`; `ray` is an RTCRayN of width N.
    unsafe {
        let args = &*args;
        let mesh = &*(args.geometryUserPtr as *const UserMesh);
        let tri = &mesh.triangles[args.primID as usize];
        let ctx = &*(args.context as *const RayContext);
        for_each_valid_lane(args.valid, args.N, args.ray as *mut f32, |lane| {
            let (o, d, tnear, tfar) = lane.ray();
            let hit = ctx.shear.get(o, d).and_then(|r| r.intersect_any_axis(&tri.lanes, tfar));
            if hit.is_some_and(|h| h.t >= tnear && h.t < tfar) {
                lane.mark_occluded();
                return true;
            }
            false
        });
    }
}

//! An Embree scene of triangle meshes: built and committed once, then queried from many threads.

use super::build_choice::BuildChoice;
use super::device::{Device, EmbreeError};
use super::ffi;
use super::quads::QuadPairs;
use super::ray_context::{RayContext, ShearCache};
use super::user_curves::UserCurves;
use super::user_triangles::{self, UserMesh};
use super::TriangleTest;
use crate::geometry::{Bounds3, Curves, Hit, Mesh, PlacedQuadric, Ray};
use glam::Vec3;
use std::sync::Arc;

/// Owns one `RTCScene` handle; released in Drop. The device must outlive it.
pub(super) struct SceneHandle {
    pub(super) raw: ffi::RTCScene,
    test: TriangleTest,
    /// Build quality of each triangle geometry (Embree reads it when the scene's is low).
    geometry_quality: ffi::RTCBuildQuality,
    /// Triangles of the user geometries ([`TriangleTest::Watertight`]); dropped after `raw` is
    /// released, since Embree's callbacks read them.
    /// Boxed: Embree holds each UserMesh's address, which must not move when the Vec grows.
    #[allow(clippy::vec_box)]
    user_meshes: Vec<Box<UserMesh>>,
    /// The quadrics of the quadric user geometries, kept as `user_meshes` are.
    #[allow(clippy::vec_box)]
    user_quadrics: Vec<Box<super::quadrics::UserQuadric>>,
    /// The ribbon curves of the ribbon user geometries, kept as `user_meshes` are.
    #[allow(clippy::vec_box)]
    user_curves: Vec<Box<UserCurves>>,
    /// Meshes whose vertex and index arrays Embree reads in place (shared buffers) instead of
    /// copying them; dropped after `raw` is released, as `user_meshes` are.
    shared: Option<Arc<[Mesh]>>,
    /// Attach triangle meshes as Embree quads ([`BuildChoice::quads`]).
    pair_quads: bool,
    /// By geometry id, the quads of the meshes attached as quads (Embree reads their index
    /// buffers in place); dropped after `raw` is released.
    quads: Vec<Option<QuadPairs>>,
}

impl SceneHandle {
    /// A new robust scene (RTC_SCENE_FLAG_ROBUST: no leaks through shared edges) of `quality`,
    /// whose meshes will be intersected by `test`.
    pub(super) fn new(device: &Device, quality: ffi::RTCBuildQuality, test: TriangleTest) -> Result<Self, EmbreeError> {
        let flags = ffi::RTCSceneFlags_RTC_SCENE_FLAG_ROBUST;
        Self::with_flags(device, quality, flags, test)
    }

    /// A new scene built as `choice` says (quality and leaf layout).
    pub(super) fn with_choice(device: &Device, choice: BuildChoice, test: TriangleTest) -> Result<Self, EmbreeError> {
        let mut scene = Self::with_flags(device, choice.quality.rtc(), choice.scene_flags(), test)?;
        scene.pair_quads(choice.quads);
        Ok(scene)
    }

    fn with_flags(
        device: &Device,
        quality: ffi::RTCBuildQuality,
        flags: ffi::RTCSceneFlags,
        test: TriangleTest,
    ) -> Result<Self, EmbreeError> {
        // SAFETY: `device` holds a valid device.
        let raw = unsafe { ffi::rtcNewScene(device.raw()) };
        if raw.is_null() {
            return Err(EmbreeError::Call(device.take_error().unwrap_or_else(|| "rtcNewScene failed".into())));
        }
        // SAFETY: `raw` is a valid, uncommitted scene.
        unsafe {
            ffi::rtcSetSceneFlags(raw, flags);
            ffi::rtcSetSceneBuildQuality(raw, quality);
        }
        Ok(Self {
            raw,
            test,
            geometry_quality: quality,
            user_meshes: Vec::new(),
            user_quadrics: Vec::new(),
            user_curves: Vec::new(),
            shared: None,
            pair_quads: false,
            quads: Vec::new(),
        })
    }

    /// Attaches the triangle meshes added from now on as Embree quads where they pair
    /// ([`BuildChoice::quads`]).
    pub(super) fn pair_quads(&mut self, on: bool) {
        self.pair_quads = on;
    }

    /// The triangle hit behind Embree's hit on primitive `prim` of geometry `geom` at (u, v),
    /// and its barycentrics: the same, or on a mesh attached as quads the triangle and its own
    /// barycentrics ([`QuadPairs::triangle_hit`]).
    #[inline]
    pub(super) fn triangle_hit(&self, geom: u32, prim: u32, u: f32, v: f32) -> (u32, f32, f32) {
        match self.quads.get(geom as usize) {
            Some(Some(quads)) => quads.triangle_hit(prim, u, v),
            _ => (prim, u, v),
        }
    }

    /// Lets Embree read the vertex and index arrays of `meshes` in place when they are attached
    /// ([`SceneHandle::attach_mesh`]) instead of copying them; the scene keeps `meshes` alive.
    pub(super) fn share(&mut self, meshes: Arc<[Mesh]>) {
        self.shared = Some(meshes);
    }

    /// True when `mesh` is one of the shared meshes and its arrays can be read in place: Embree
    /// loads 16 bytes at each vertex, 4 past the last one's 12, which must lie inside the
    /// allocation (spare capacity).
    fn can_share(&self, mesh: &Mesh) -> bool {
        let Some(shared) = &self.shared else { return false };
        shared.as_ptr_range().contains(&(mesh as *const Mesh)) && mesh.positions.capacity() > mesh.positions.len()
    }

    /// Bytes of triangle storage held by prism for the user geometries (Embree's own
    /// allocations are counted by the device).
    pub(super) fn user_bytes(&self) -> usize {
        self.user_meshes.iter().map(|m| m.bytes()).sum::<usize>()
            + self.user_quadrics.len() * std::mem::size_of::<PlacedQuadric>()
            + self.user_curves.iter().map(|r| r.bytes()).sum::<usize>()
            + self.quads.iter().flatten().map(QuadPairs::bytes).sum::<usize>()
    }

    /// Attaches `curves` as geometry `id`: user geometry running prism's curve test, pbrt-v4's
    /// (`user_curves.rs`), so that Embree finds the hits obvhs finds.
    pub(super) fn attach_curves(&mut self, device: &Device, curves: &Curves, id: u32) -> Result<(), EmbreeError> {
        let (geom, user) = super::user_curves::new_geometry(device, curves)?;
        self.user_curves.push(user);
        // SAFETY: valid scene and committed geometry; the scene takes its own reference, and the
        // curves it points to are kept in `user_curves` until after the release.
        unsafe {
            ffi::rtcAttachGeometryByID(self.raw, geom, id);
            ffi::rtcReleaseGeometry(geom);
        }
        device.take_error().map_or(Ok(()), |e| Err(EmbreeError::Call(e)))
    }

    /// Attaches `quadric` as user geometry `id` (`quadrics.rs`).
    pub(super) fn attach_quadric(
        &mut self,
        device: &Device,
        quadric: &PlacedQuadric,
        id: u32,
    ) -> Result<(), EmbreeError> {
        let (geom, user) = super::quadrics::new_geometry(device, quadric)?;
        self.user_quadrics.push(user);
        // SAFETY: valid scene and committed geometry; the scene takes its own reference, and the
        // quadric it points to is kept in `user_quadrics` until after the release.
        unsafe {
            ffi::rtcAttachGeometryByID(self.raw, geom, id);
            ffi::rtcReleaseGeometry(geom);
        }
        device.take_error().map_or(Ok(()), |e| Err(EmbreeError::Call(e)))
    }

    /// Builds the BVH over everything attached.
    pub(super) fn commit(&self, device: &Device) -> Result<(), EmbreeError> {
        // SAFETY: all geometries are committed and attached.
        unsafe { ffi::rtcCommitScene(self.raw) };
        match device.take_error() {
            Some(e) => Err(EmbreeError::Call(e)),
            None => Ok(()),
        }
    }

    /// Attaches `mesh` as geometry `id`: Embree triangle geometry, or user geometry running
    /// the watertight test, as chosen at [`SceneHandle::new`].
    pub(super) fn attach_mesh(&mut self, device: &Device, mesh: &Mesh, id: u32) -> Result<(), EmbreeError> {
        match self.test {
            TriangleTest::Embree if self.pair_quads => self.attach_quads(device, mesh, id),
            TriangleTest::Embree => self.attach_polygons(device, mesh, id, None),
            TriangleTest::Watertight => {
                let (geom, user) = user_triangles::new_geometry(device, mesh)?;
                self.user_meshes.push(user);
                // SAFETY: valid scene and committed geometry; the scene takes its own reference,
                // and the UserMesh it points to is kept in `user_meshes` until after the release.
                unsafe {
                    ffi::rtcAttachGeometryByID(self.raw, geom, id);
                    ffi::rtcReleaseGeometry(geom);
                }
                device.take_error().map_or(Ok(()), |e| Err(EmbreeError::Call(e)))
            }
        }
    }

    /// Attaches `mesh` as quad geometry `id` ([`QuadPairs`]). A mesh of which fewer than half
    /// the triangles pair up is attached as triangles: its quads would hold more bytes (21 per
    /// quad) than the BVH saves.
    fn attach_quads(&mut self, device: &Device, mesh: &Mesh, id: u32) -> Result<(), EmbreeError> {
        let quads = QuadPairs::new(&mesh.indices);
        if 4 * quads.len() > 3 * mesh.len() {
            return self.attach_polygons(device, mesh, id, None);
        }
        self.attach_polygons(device, mesh, id, Some(&quads))?;
        let slot = id as usize;
        if self.quads.len() <= slot {
            self.quads.resize_with(slot + 1, || None);
        }
        // Embree reads the quads' index array (a heap buffer that stays where it is when the
        // `QuadPairs` moves) until the scene is released, which happens before this drops.
        self.quads[slot] = Some(quads);
        Ok(())
    }

    /// Attaches `mesh` as Embree triangle geometry `id`, or as the quad geometry of `quads`
    /// (which the caller keeps until the scene is released): its arrays read in place when
    /// shared ([`SceneHandle::share`]), else copied into Embree's buffers; quad indices read in
    /// place.
    fn attach_polygons(
        &self,
        device: &Device,
        mesh: &Mesh,
        id: u32,
        quads: Option<&QuadPairs>,
    ) -> Result<(), EmbreeError> {
        let (vertex, index) = (ffi::RTCBufferType_RTC_BUFFER_TYPE_VERTEX, ffi::RTCBufferType_RTC_BUFFER_TYPE_INDEX);
        let (float3, uint3) = (ffi::RTCFormat_RTC_FORMAT_FLOAT3, ffi::RTCFormat_RTC_FORMAT_UINT3);
        let kind = match quads {
            Some(_) => ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_QUAD,
            None => ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_TRIANGLE,
        };
        let out_of_memory = |geom| {
            // SAFETY: `geom` is the new geometry, not attached, released once here.
            unsafe { ffi::rtcReleaseGeometry(geom) };
            Err(EmbreeError::Call(device.take_error().unwrap_or_else(|| "out of memory for geometry buffers".into())))
        };
        // SAFETY: valid device; the geometry is released below after attaching (the scene keeps
        // its own reference).
        unsafe {
            let geom = ffi::rtcNewGeometry(device.raw(), kind);
            if geom.is_null() {
                return Err(EmbreeError::Call(device.take_error().unwrap_or_default()));
            }
            ffi::rtcSetGeometryBuildQuality(geom, self.geometry_quality);
            // `Vec3`, `[u32; 3]` and `[u32; 4]` are packed 4-byte values, as FLOAT3, UINT3 and
            // UINT4 are; `shared` keeps the mesh's arrays alive and unchanged (behind an Arc)
            // until after the scene is released, and `can_share` checked the vertex array's
            // padding. Embree-allocated buffers are padded for the 16-byte loads past the last
            // vertex.
            let shared = self.can_share(mesh);
            if shared {
                let (p, n) = (mesh.positions.as_ptr().cast(), mesh.positions.len());
                ffi::rtcSetSharedGeometryBuffer(geom, vertex, 0, float3, p, 0, 12, n);
            } else {
                let n = mesh.positions.len();
                let vb = ffi::rtcSetNewGeometryBuffer(geom, vertex, 0, float3, 12, n) as *mut [f32; 3];
                if vb.is_null() {
                    return out_of_memory(geom);
                }
                for (dst, p) in std::slice::from_raw_parts_mut(vb, n).iter_mut().zip(&mesh.positions) {
                    *dst = p.to_array();
                }
            }
            match quads {
                Some(q) => {
                    let (p, n) = (q.indices.as_ptr().cast(), q.len());
                    ffi::rtcSetSharedGeometryBuffer(geom, index, 0, ffi::RTCFormat_RTC_FORMAT_UINT4, p, 0, 16, n);
                }
                None if shared => {
                    let (p, n) = (mesh.indices.as_ptr().cast(), mesh.indices.len());
                    ffi::rtcSetSharedGeometryBuffer(geom, index, 0, uint3, p, 0, 12, n);
                }
                None => {
                    let n = mesh.indices.len();
                    let ib = ffi::rtcSetNewGeometryBuffer(geom, index, 0, uint3, 12, n) as *mut [u32; 3];
                    if ib.is_null() {
                        return out_of_memory(geom);
                    }
                    std::slice::from_raw_parts_mut(ib, n).copy_from_slice(&mesh.indices);
                }
            }
            ffi::rtcCommitGeometry(geom);
            ffi::rtcAttachGeometryByID(self.raw, geom, id);
            ffi::rtcReleaseGeometry(geom);
        }
        match device.take_error() {
            Some(e) => Err(EmbreeError::Call(e)),
            None => Ok(()),
        }
    }
}

impl Drop for SceneHandle {
    fn drop(&mut self) {
        // SAFETY: the handle came from rtcNewScene and is released exactly once; owners drop it
        // before their device.
        unsafe { ffi::rtcReleaseScene(self.raw) };
    }
}

/// A committed scene of triangle meshes (and the device that keeps it alive).
pub struct Scene {
    raw: SceneHandle,
    device: Device,
    bounds: Bounds3,
}

// SAFETY: after rtcCommitScene an Embree scene is immutable and its queries are thread-safe
// (Embree API docs, "rtcIntersect1"); we never modify it after construction.
unsafe impl Send for Scene {}
// SAFETY: see above.
unsafe impl Sync for Scene {}

impl Scene {
    /// Builds a robust scene with one triangle geometry per mesh; geometry ids equal mesh
    /// indices. Empty meshes are skipped.
    pub fn build(
        device: Device,
        meshes: &[Mesh],
        choice: BuildChoice,
        test: TriangleTest,
    ) -> Result<Self, EmbreeError> {
        Self::build_with_extra(device, meshes, Default::default(), choice, test, None)
    }

    /// [`Scene::build`] with curve and quadric geometries too: each pairs a geometry id (of an
    /// empty mesh) with its curves or its (static) quadric. When `shared` holds `meshes`,
    /// Embree reads their arrays in place ([`SceneHandle::share`]).
    pub fn build_with_extra(
        device: Device,
        meshes: &[Mesh],
        extra: crate::accel::ExtraShapes,
        choice: BuildChoice,
        test: TriangleTest,
        shared: Option<Arc<[Mesh]>>,
    ) -> Result<Self, EmbreeError> {
        let mut raw = SceneHandle::with_choice(&device, choice, test)?;
        if let Some(shared) = shared {
            raw.share(shared);
        }
        let mut bounds = Bounds3::EMPTY;
        for (id, mesh) in meshes.iter().enumerate() {
            if mesh.is_empty() {
                continue;
            }
            raw.attach_mesh(&device, mesh, id as u32)?;
            bounds = bounds.union(mesh.bounds());
        }
        for &(id, c) in extra.curves {
            raw.attach_curves(&device, c, id)?;
            bounds = bounds.union(c.bounds());
        }
        for &(id, q) in extra.quadrics {
            raw.attach_quadric(&device, q, id)?;
            bounds = bounds.union(q.bounds());
        }
        raw.commit(&device)?;
        Ok(Self { raw, device, bounds })
    }

    /// A scene of `curves` alone, attached as Embree's own curve geometry whatever their kind
    /// (ribbons as `NORMAL_ORIENTED_BEZIER_CURVE`), to measure Embree's ribbons against
    /// pbrt-v4's.
    #[cfg(test)]
    pub(super) fn native_curves(device: Device, curves: &Curves) -> Result<Self, EmbreeError> {
        let raw = SceneHandle::new(&device, ffi::RTCBuildQuality_RTC_BUILD_QUALITY_MEDIUM, TriangleTest::Embree)?;
        super::curves::attach(raw.raw, &device, curves, 0)?;
        raw.commit(&device)?;
        Ok(Self { raw, device, bounds: curves.bounds() })
    }

    /// Bytes held for this scene: Embree's (BVH and vertex/index copies) and the user
    /// geometries' triangles.
    pub fn memory_bytes(&self) -> usize {
        self.device.memory_bytes() + self.raw.user_bytes()
    }

    /// Bounds of all attached meshes.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// A fresh context for one query. Every query passes a [`RayContext`] (the user-geometry
    /// callbacks rely on it).
    #[inline]
    pub(super) fn context() -> RayContext {
        RayContext { rtc: ffi::query_context(), shear: ShearCache::default() }
    }

    /// True when Embree accepts the ray: |origin|, |direction| ≤ 1.844·10¹⁸ (Embree's
    /// `FLT_LARGE`) and t_max not NaN (`RayK::valid` in Embree 3 and 4). Debian's Embree is built with
    /// assertions, so any other ray would abort the process; such rays hit nothing.
    #[inline]
    pub(super) fn accepts(ray: &Ray) -> bool {
        const FLT_LARGE: f32 = 1.844e18;
        // `cmple` is false for NaN (unlike `max_element`, which skips NaN).
        let small = |v: Vec3| v.abs().cmple(Vec3::splat(FLT_LARGE)).all();
        small(ray.o) && small(ray.d) && !ray.t_max.is_nan()
    }

    #[inline]
    pub(super) fn rtc_ray(ray: &Ray) -> ffi::RTCRay {
        ffi::RTCRay {
            org_x: ray.o.x,
            org_y: ray.o.y,
            org_z: ray.o.z,
            // The Accel contract is t ∈ (0, t_max]: a spawned ray whose origin lies exactly on
            // its surface (zero error bound along an axis-aligned normal) must not re-hit it at
            // t = 0. The smallest normal f32 survives FTZ/DAZ.
            tnear: f32::MIN_POSITIVE,
            dir_x: ray.d.x,
            dir_y: ray.d.y,
            dir_z: ray.d.z,
            time: 0.0,
            tfar: ray.t_max,
            // Every bit set: hits geometries of any mask (Embree 3's default geometry mask is
            // 0xFFFFFFFF, Embree 4's is 0x1).
            mask: u32::MAX,
            id: 0,
            flags: 0,
        }
    }

    /// The hit Embree reported on primitive `prim` of geometry `geom` at (u, v): on a mesh
    /// attached as quads, the triangle and its own barycentrics ([`QuadPairs::triangle_hit`]);
    /// on a quad's diagonal `ng` may then be the other half's (the point is on both).
    #[inline]
    fn hit(&self, t: f32, geom: u32, prim: u32, u: f32, v: f32, ng: Vec3) -> Hit {
        let (prim_id, u, v) = self.raw.triangle_hit(geom, prim, u, v);
        Hit { t, geom_id: geom, prim_id, u, v, ng, inst_id: Hit::NO_INSTANCE }
    }

    /// Closest hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if !Self::accepts(ray) {
            return None;
        }
        let mut ctx = Self::context();
        let mut rh = ffi::RTCRayHit {
            ray: Self::rtc_ray(ray),
            hit: ffi::RTCHit { geomID: ffi::RTC_INVALID_GEOMETRY_ID, ..Default::default() },
        };
        // SAFETY: committed scene; ctx and rh are valid, properly aligned locals.
        unsafe { ffi::intersect1(self.raw.raw, ctx.as_mut_ptr(), &mut rh) };
        if rh.hit.geomID == ffi::RTC_INVALID_GEOMETRY_ID {
            return None;
        }
        let ng = Vec3::new(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
        Some(self.hit(rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, ng))
    }

    /// Any hit before `ray.t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        if !Self::accepts(ray) {
            return false;
        }
        let mut ctx = Self::context();
        let mut r = Self::rtc_ray(ray);
        // SAFETY: committed scene; ctx and r are valid, properly aligned locals.
        unsafe { ffi::occluded1(self.raw.raw, ctx.as_mut_ptr(), &mut r) };
        // Embree sets tfar to -inf when an occluder was found.
        r.tfar == f32::NEG_INFINITY
    }

    /// Up to sixteen rays in Embree's packet layout, and which lanes to trace (−1) or skip (0:
    /// past the end of `rays`, or a ray Embree would refuse).
    #[cfg(feature = "embree")]
    #[inline]
    fn rtc_ray16(rays: &[Ray]) -> (ffi::RTCRay16, ffi::Valid16) {
        let mut r = ffi::RTCRay16 { mask: [u32::MAX; 16], ..Default::default() };
        let mut valid = ffi::Valid16::default();
        for (i, ray) in rays.iter().enumerate() {
            let one = Self::rtc_ray(ray);
            (r.org_x[i], r.org_y[i], r.org_z[i], r.tnear[i]) = (one.org_x, one.org_y, one.org_z, one.tnear);
            (r.dir_x[i], r.dir_y[i], r.dir_z[i], r.tfar[i]) = (one.dir_x, one.dir_y, one.dir_z, one.tfar);
            valid.0[i] = if Self::accepts(ray) { -1 } else { 0 };
        }
        (r, valid)
    }

    /// Closest hits of up to sixteen rays traced as one packet (`rtcIntersect16`); only for
    /// Embree's own triangle kernel, since the user-geometry callbacks trace one ray at a time.
    #[cfg(feature = "embree")]
    #[inline]
    pub fn intersect16(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        let (ray, valid) = Self::rtc_ray16(rays);
        let mut rh = ffi::RTCRayHit16 {
            ray,
            hit: ffi::RTCHit16 { geomID: [ffi::RTC_INVALID_GEOMETRY_ID; 16], ..Default::default() },
        };
        let mut ctx = Self::context();
        // SAFETY: committed scene; ctx and rh are valid locals, RTCRayHit16 is 64-byte aligned.
        unsafe { ffi::intersect16(&valid, self.raw.raw, ctx.as_mut_ptr(), &mut rh) };
        let h = &rh.hit;
        for (i, out) in hits.iter_mut().enumerate().take(rays.len()) {
            *out = (valid.0[i] != 0 && h.geomID[i] != ffi::RTC_INVALID_GEOMETRY_ID).then(|| {
                let ng = Vec3::new(h.Ng_x[i], h.Ng_y[i], h.Ng_z[i]);
                self.hit(rh.ray.tfar[i], h.geomID[i], h.primID[i], h.u[i], h.v[i], ng)
            });
        }
    }

    /// Occlusion of up to sixteen rays traced as one packet (`rtcOccluded16`).
    #[cfg(feature = "embree")]
    #[inline]
    pub fn occluded16(&self, rays: &[Ray], blocked: &mut [bool]) {
        let (mut ray, valid) = Self::rtc_ray16(rays);
        let mut ctx = Self::context();
        // SAFETY: committed scene; ctx and ray are valid locals, RTCRay16 is 64-byte aligned.
        unsafe { ffi::occluded16(&valid, self.raw.raw, ctx.as_mut_ptr(), &mut ray) };
        for (i, b) in blocked.iter_mut().enumerate().take(rays.len()) {
            *b = valid.0[i] != 0 && ray.tfar[i] == f32::NEG_INFINITY;
        }
    }

    /// Raw closest-hit call on a prepared RTCRayHit, for the wrapper-overhead benchmark.
    #[doc(hidden)]
    pub fn raw_intersect(&self, rh: &mut ffi::RTCRayHit) {
        let mut ctx = Self::context();
        // SAFETY: committed scene; the caller's ray-hit is a valid, aligned struct.
        unsafe { ffi::intersect1(self.raw.raw, ctx.as_mut_ptr(), rh) };
    }
}

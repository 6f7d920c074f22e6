//! Two-level Embree scene: one committed `RTCScene` per prototype, instanced into a top-level
//! scene by `RTC_GEOMETRY_TYPE_INSTANCE` geometries (`rtcSetGeometryInstancedScene`,
//! `rtcSetGeometryTransform`, the same in Embree 3 and 4). World primitives sit in the top scene
//! beside the instances. A prototype holds triangle meshes, curves (Embree's curve geometry) and
//! static quadrics (user geometry, whose callbacks Embree hands the ray already carried into
//! the prototype's space), as the world does.
//!
//! Top-level geometry ids: world primitives take 0..W, instance `i` takes W + i. A hit reports
//! the instance in `instID[0]` and the geometry's id within its prototype scene in `geomID`,
//! both mapped back here to the scene's primitive ids.
//!
//! A moving instance has time steps (`motion`); rays carry their time mapped onto Embree's
//! [0, 1].

use glam::{Mat3, Vec3};

use super::device::{Device, EmbreeError};
use super::ffi;
use super::motion;
use super::scene::{Scene, SceneHandle};
use super::TriangleTest;
use crate::accel::ShapeTable;
use crate::geometry::{Bounds3, Hit, Mesh, Ray};
use crate::geometry::{Instance, InstanceSet, Motion};
use std::sync::Arc;

/// Prototype scenes, instances and world meshes in one top-level Embree scene.
pub struct InstancedScene {
    // Field order is drop order: the top scene, then the prototypes it instances, then the device.
    top: SceneHandle,
    prototypes: Vec<SceneHandle>,
    device: Device,
    /// Scene mesh id of top-level geometry `i < W`.
    world_ids: Vec<u32>,
    /// Scene mesh id of local geometry `g` of prototype `p`: `proto_ids[p][g]`.
    proto_ids: Vec<Vec<u32>>,
    /// Prototype and normal cofactor matrix of each instance (of its start placement when it
    /// moves).
    instances: Vec<(u32, Mat3)>,
    /// The moving instances by index: the cofactor at a hit's time comes from their motion.
    motions: Vec<Option<Arc<Motion>>>,
    /// The scene time that Embree's ray time 0 and 1 stand for (`None`: nothing moves).
    time_span: Option<(f32, f32)>,
    bounds: Bounds3,
}

// SAFETY: all scenes are committed before construction returns and never modified afterwards;
// Embree allows concurrent queries on committed scenes.
unsafe impl Send for InstancedScene {}
// SAFETY: see above.
unsafe impl Sync for InstancedScene {}

/// Attaches primitives `ids` to `scene`, each as geometry of its index in `ids`: its mesh, its
/// curves, or its quadric when static. Returns their bounds.
fn attach(
    scene: &mut SceneHandle,
    device: &Device,
    meshes: &[Mesh],
    shapes: &ShapeTable,
    ids: &[u32],
) -> Result<Bounds3, EmbreeError> {
    let mut bounds = Bounds3::EMPTY;
    for (local, &id) in ids.iter().enumerate() {
        let local = local as u32;
        let mesh = &meshes[id as usize];
        if !mesh.is_empty() {
            scene.attach_mesh(device, mesh, local)?;
            bounds = bounds.union(mesh.bounds());
        }
        if let Some(c) = shapes.curves(id) {
            scene.attach_curves(device, c, local)?;
            bounds = bounds.union(c.bounds());
        }
        if let Some(q) = shapes.quadric(id).filter(|q| !q.moves()) {
            scene.attach_quadric(device, q, local)?;
            bounds = bounds.union(q.bounds());
        }
    }
    Ok(bounds)
}

impl InstancedScene {
    /// Builds the prototype scenes and the top scene over the meshes, and the curves and static
    /// quadrics of `shapes` (moving ones are left out). Instances of empty prototypes are skipped.
    /// When `shared` holds `meshes`, Embree reads their arrays in place; with `quads`, triangle
    /// meshes are attached as Embree quads where they pair (`quads.rs`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn build(
        device: Device,
        meshes: &[Mesh],
        shapes: &ShapeTable,
        set: &InstanceSet,
        quality: ffi::RTCBuildQuality,
        test: TriangleTest,
        shared: Option<Arc<[Mesh]>>,
        quads: bool,
    ) -> Result<Self, EmbreeError> {
        let mut prototypes = Vec::with_capacity(set.prototypes.len());
        let mut proto_ids = Vec::with_capacity(set.prototypes.len());
        let mut proto_bounds = Vec::with_capacity(set.prototypes.len());
        let new_scene = || -> Result<SceneHandle, EmbreeError> {
            let mut scene = SceneHandle::new(&device, quality, test)?;
            scene.pair_quads(quads);
            if let Some(shared) = &shared {
                scene.share(shared.clone());
            }
            Ok(scene)
        };
        for p in &set.prototypes {
            let mut scene = new_scene()?;
            proto_bounds.push(attach(&mut scene, &device, meshes, shapes, &p.meshes)?);
            scene.commit(&device)?;
            prototypes.push(scene);
            proto_ids.push(p.meshes.clone());
        }
        let mut top = new_scene()?;
        let mut bounds = attach(&mut top, &device, meshes, shapes, &set.world_meshes)?;
        let first_instance = set.world_meshes.len() as u32;
        let time_span = motion::time_span(set.instances.iter().filter_map(|i| i.motion.as_deref()));
        for (i, inst) in set.instances.iter().enumerate() {
            let b = proto_bounds[inst.prototype as usize];
            if b.is_empty() {
                continue;
            }
            bounds = bounds.union(inst.world_bounds(b));
            // Embree's FLOAT3X4_COLUMN_MAJOR: the four columns of the affine 3×4 matrix.
            let m = inst.world_from_object.to_cols_array();
            let xfm: [f32; 12] = [m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10], m[12], m[13], m[14]];
            let proto = &prototypes[inst.prototype as usize];
            // SAFETY: valid device and committed prototype scene; Embree copies the transform
            // during the call; the geometry is released after attaching (the top scene keeps it).
            unsafe {
                let geom = ffi::rtcNewGeometry(device.raw(), ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_INSTANCE);
                if geom.is_null() {
                    return Err(EmbreeError::Call(device.take_error().unwrap_or_default()));
                }
                ffi::rtcSetGeometryInstancedScene(geom, proto.raw);
                match (&inst.motion, time_span) {
                    (Some(m), Some(span)) => {
                        let (steps, range) = motion::time_steps(m, span);
                        ffi::rtcSetGeometryTimeStepCount(geom, steps.len() as u32);
                        ffi::rtcSetGeometryTimeRange(geom, range.0, range.1);
                        for (k, qd) in steps.iter().enumerate() {
                            ffi::rtcSetGeometryTransformQuaternion(geom, k as u32, qd);
                        }
                    }
                    _ => ffi::rtcSetGeometryTransform(
                        geom,
                        0,
                        ffi::RTCFormat_RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR,
                        xfm.as_ptr() as *const std::ffi::c_void,
                    ),
                }
                ffi::rtcCommitGeometry(geom);
                ffi::rtcAttachGeometryByID(top.raw, geom, first_instance + i as u32);
                ffi::rtcReleaseGeometry(geom);
            }
            if let Some(e) = device.take_error() {
                return Err(EmbreeError::Call(e));
            }
        }
        top.commit(&device)?;
        let instances = set.instances.iter().map(|i| (i.prototype, i.normal_cofactor)).collect();
        let motions = set.instances.iter().map(|i| i.motion.clone()).collect();
        Ok(Self {
            top,
            prototypes,
            device,
            world_ids: set.world_meshes.clone(),
            proto_ids,
            instances,
            motions,
            time_span,
            bounds,
        })
    }

    /// The Embree ray for `ray`, its time mapped onto Embree's [0, 1].
    #[inline]
    fn rtc_ray(&self, ray: &Ray) -> ffi::RTCRay {
        let mut r = Scene::rtc_ray(ray);
        if let Some(span) = self.time_span {
            r.time = motion::embree_time(span, ray.time);
        }
        r
    }

    /// World bounds (instance boxes are the transformed corners of their prototypes' boxes).
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Bytes Embree holds for all scenes of this accelerator, and the user geometries' triangles.
    pub fn memory_bytes(&self) -> usize {
        self.device.memory_bytes()
            + self.top.user_bytes()
            + self.prototypes.iter().map(SceneHandle::user_bytes).sum::<usize>()
    }

    /// Closest hit, with mesh ids of the scene and a world-space normal.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if !Scene::accepts(ray) {
            return None;
        }
        let mut ctx = Scene::context();
        let mut rh = ffi::RTCRayHit {
            ray: self.rtc_ray(ray),
            hit: ffi::RTCHit { geomID: ffi::RTC_INVALID_GEOMETRY_ID, ..Default::default() },
        };
        // SAFETY: committed scene; ctx and rh are valid, properly aligned locals.
        unsafe { ffi::intersect1(self.top.raw, ctx.as_mut_ptr(), &mut rh) };
        if rh.hit.geomID == ffi::RTC_INVALID_GEOMETRY_ID {
            return None;
        }
        let ng = Vec3::new(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
        let top_id = rh.hit.instID[0];
        let (geom, prim, u, v) = (rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v);
        let (geom_id, inst_id, ng, (prim_id, u, v)) = if top_id == ffi::RTC_INVALID_GEOMETRY_ID {
            (self.world_ids[geom as usize], Hit::NO_INSTANCE, ng, self.top.triangle_hit(geom, prim, u, v))
        } else {
            let inst = top_id - self.world_ids.len() as u32;
            let (proto, mut cofactor) = self.instances[inst as usize];
            if let Some(m) = &self.motions[inst as usize] {
                if let Some(at) = Instance::new(proto, m.interpolate(ray.time)) {
                    cofactor = at.normal_cofactor;
                }
            }
            // Embree reports Ng of instanced geometry in object space.
            let hit = self.prototypes[proto as usize].triangle_hit(geom, prim, u, v);
            (self.proto_ids[proto as usize][geom as usize], inst, cofactor * ng, hit)
        };
        Some(Hit { t: rh.ray.tfar, geom_id, prim_id, u, v, ng, inst_id })
    }

    /// Raw closest-hit call of the top scene on a prepared RTCRayHit (the hit-record tests).
    #[cfg(test)]
    pub(super) fn raw_intersect(&self, rh: &mut ffi::RTCRayHit) {
        let mut ctx = Scene::context();
        // SAFETY: committed scene; the caller's ray-hit is a valid, aligned struct.
        unsafe { ffi::intersect1(self.top.raw, ctx.as_mut_ptr(), rh) };
    }

    /// Any hit before `ray.t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        if !Scene::accepts(ray) {
            return false;
        }
        let mut ctx = Scene::context();
        let mut r = self.rtc_ray(ray);
        // SAFETY: committed scene; ctx and r are valid, properly aligned locals.
        unsafe { ffi::occluded1(self.top.raw, ctx.as_mut_ptr(), &mut r) };
        r.tfar == f32::NEG_INFINITY
    }
}

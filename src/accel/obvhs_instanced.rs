//! Two-level obvhs traversal for object instances: a top-level CWBVH (the TLAS) over the
//! instances' world-space boxes; each instance carries the ray into object space by its inverse
//! transform and traverses its prototype's [`ObvhsAccel`] (the BLAS), with the prototype's curves
//! and quadrics in BVHs beside it ([`WithExtra`]) when it has any. World meshes have their own
//! BLAS, traced first without any transform.
//!
//! The parametric distance t is the same in both spaces (the direction is transformed, not
//! renormalised), so the nearest hit so far bounds every later BLAS query. Equal distances are
//! resolved by the smallest (instance, mesh, triangle) ids, so the result does not depend on
//! traversal order. Watertightness carries over: the object-space ray is one ray, and the BLAS
//! triangle test is watertight for any ray.
//!
//! A moving instance's TLAS box bounds it over its whole motion
//! ([`crate::geometry::AnimatedTransform::motion_bounds`]); a ray reaching it is carried into
//! object space by the inverse of the transform interpolated at the ray's time.

use std::time::Duration;

use ::obvhs::{aabb::Aabb, cwbvh::builder::build_cwbvh, cwbvh::CwBvh, ray::RayHit, BvhBuildParams};
use glam::{Mat3, Mat4, Vec3, Vec3A};

use super::obvhs::{max_depth, ObvhsAccel};

/// t seen by obvhs' top-level traversal = t · T_SCALE (a power of two, so scaling is exact): obvhs
/// culls boxes ending before t = 10⁻⁴, which the scaling puts far below f32 resolution.
const T_SCALE: f32 = (1u32 << 20) as f32;
/// Largest inverse-direction magnitude handed to obvhs' slab test (finite: avoids 0·∞ = NaN).
const INV_DIR_LIMIT: f32 = 1e30;
/// obvhs' traversal stack size (`cwbvh::TRAVERSAL_STACK_SIZE`, private in obvhs 0.4).
const OBVHS_STACK: u32 = 32;

/// The ray as obvhs sees it: direction scaled by 1/T_SCALE, sign-consistent finite 1/d.
fn obvhs_ray(ray: &Ray, t_max_scaled: f32) -> ::obvhs::ray::Ray {
    // Adding +0 turns -0 into +0: obvhs picks slab order from `d < 0`, so 1/d must agree in sign.
    let d = ray.d * (1.0 / T_SCALE) + Vec3::ZERO;
    let inv = |x: f32| if x == 0.0 { INV_DIR_LIMIT } else { (1.0 / x).clamp(-INV_DIR_LIMIT, INV_DIR_LIMIT) };
    ::obvhs::ray::Ray {
        origin: glam::Vec3A::from(ray.o),
        direction: glam::Vec3A::from(d),
        inv_direction: glam::Vec3A::new(inv(d.x), inv(d.y), inv(d.z)),
        tmin: 0.0,
        tmax: t_max_scaled,
    }
}
use super::{Accel, ExtraShapes, ShapeTable, WithExtra};
use crate::geometry::{Bounds3, Hit, Mesh, Ray};
use crate::geometry::{Instance, InstanceSet, Motion};
use std::sync::Arc;

/// One instance in TLAS primitive order.
struct Placed {
    /// Index in the scene's instance list (reported as `Hit::inst_id`).
    index: u32,
    /// Prototype index (which BLAS).
    proto: u32,
    object_from_world: Mat4,
    /// Maps object-space unnormalised normals to world space (see `Instance::normal_cofactor`).
    normal_cofactor: Mat3,
    /// The motion of a moving instance (shared: static instances stay small); the two matrices
    /// above are then those of its start time.
    motion: Option<Arc<Motion>>,
}

/// A prototype's BLAS: its triangles, or its triangles with curves and quadrics beside them.
enum Blas {
    Triangles(ObvhsAccel),
    Mixed(WithExtra),
}

impl Blas {
    /// The BLAS over `meshes` and the curves and quadrics of `extra` (ids local to the
    /// prototype, as the meshes').
    fn new(meshes: &[Mesh], extra: ExtraShapes) -> Self {
        let triangles = ObvhsAccel::new(meshes);
        if extra.is_empty() {
            return Blas::Triangles(triangles);
        }
        let curves = (!extra.curves.is_empty()).then(|| super::CurveBvh::new(extra.curves));
        let quadrics = (!extra.quadrics.is_empty()).then(|| super::QuadricBvh::new(extra.quadrics));
        Blas::Mixed(WithExtra::new(Box::new(triangles), curves, quadrics))
    }

    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Blas::Triangles(t) => t.intersect(ray),
            Blas::Mixed(m) => m.intersect(ray),
        }
    }

    #[inline]
    fn occluded(&self, ray: &Ray) -> bool {
        match self {
            Blas::Triangles(t) => t.occluded(ray),
            Blas::Mixed(m) => m.occluded(ray),
        }
    }

    fn bounds(&self) -> Bounds3 {
        match self {
            Blas::Triangles(t) => t.bounds(),
            Blas::Mixed(m) => m.bounds(),
        }
    }

    fn memory_bytes(&self) -> usize {
        match self {
            Blas::Triangles(t) => t.memory_bytes(),
            Blas::Mixed(m) => m.memory_bytes(),
        }
    }
}

impl Placed {
    /// The object-from-world matrix and normal cofactor at `time`.
    #[inline]
    fn at(&self, time: f32) -> (Mat4, Mat3) {
        match self.motion.as_deref().and_then(|m| Instance::new(self.proto, m.interpolate(time))) {
            None => (self.object_from_world, self.normal_cofactor),
            Some(i) => (i.object_from_world, i.normal_cofactor),
        }
    }
}

/// World meshes and instanced prototypes traced through a two-level obvhs BVH.
pub struct ObvhsInstancedAccel {
    world: ObvhsAccel,
    /// Scene mesh id of the world BLAS's geometry `g`.
    world_ids: Vec<u32>,
    blas: Vec<Blas>,
    /// Scene mesh id of geometry `g` of prototype `p`: `proto_ids[p][g]`.
    proto_ids: Vec<Vec<u32>>,
    /// TLAS primitive `k` is `placed[k]`.
    placed: Vec<Placed>,
    tlas: CwBvh,
    /// The TLAS is too deep for obvhs' traversal stack: test every instance instead.
    linear_fallback: bool,
    bounds: Bounds3,
}

fn gather(meshes: &[Mesh], ids: &[u32]) -> Vec<Mesh> {
    ids.iter().map(|&m| meshes[m as usize].clone()).collect()
}

/// Box grown by 2⁻²⁰ of its largest coordinate magnitude: more than the rounding of the corner
/// transforms (γ₃ ≈ 2⁻²²) and of the slab test, far less than any visible size.
fn padded(b: Bounds3) -> Aabb {
    let b = b.padded(1.0 / T_SCALE);
    Aabb::new(Vec3A::from(b.min), Vec3A::from(b.max))
}

impl ObvhsInstancedAccel {
    /// Builds one BLAS per prototype (its meshes, and its curves and quadrics from `shapes`) and
    /// per the world meshes, and the TLAS over the instances of non-empty prototypes. The world's
    /// curves and quadrics are not traced here.
    pub(crate) fn new(meshes: &[Mesh], shapes: &ShapeTable, set: &InstanceSet) -> Self {
        let world = ObvhsAccel::new(&gather(meshes, &set.world_meshes));
        let blas: Vec<Blas> = set
            .prototypes
            .iter()
            .map(|p| {
                let (curves, quadrics) = shapes.pick(&p.meshes, |k, _| k);
                Blas::new(&gather(meshes, &p.meshes), ExtraShapes { curves: &curves, quadrics: &quadrics })
            })
            .collect();
        let mut bounds = world.bounds();
        let mut placed = Vec::new();
        let mut boxes = Vec::new();
        for (i, inst) in set.instances.iter().enumerate() {
            let b = blas[inst.prototype as usize].bounds();
            if b.is_empty() {
                continue;
            }
            let wb = inst.world_bounds(b);
            if !wb.fits_bvh() {
                // Placed at infinity (or NaN) by its transform: nothing can hit it.
                continue;
            }
            bounds = bounds.union(wb);
            boxes.push(padded(wb));
            placed.push(Placed {
                index: i as u32,
                proto: inst.prototype,
                object_from_world: inst.object_from_world,
                normal_cofactor: inst.normal_cofactor,
                motion: inst.motion.clone(),
            });
        }
        let mut tlas = CwBvh::default();
        let mut linear_fallback = false;
        if !boxes.is_empty() {
            tlas = build_cwbvh(&boxes, BvhBuildParams::medium_build(), &mut Duration::default());
            linear_fallback = max_depth(&tlas.nodes) + 1 >= OBVHS_STACK;
            // Reorder so that TLAS primitive k is placed[k].
            let mut slots: Vec<Option<Placed>> = placed.into_iter().map(Some).collect();
            placed = tlas.primitive_indices.iter().map(|&k| slots[k as usize].take().expect("a permutation")).collect();
        }
        Self {
            world,
            world_ids: set.world_meshes.clone(),
            blas,
            proto_ids: set.prototypes.iter().map(|p| p.meshes.clone()).collect(),
            placed,
            tlas,
            linear_fallback,
            bounds,
        }
    }

    /// The ray in the object space of `object_from_world` (same t).
    #[inline]
    fn local_ray(object_from_world: &Mat4, ray: &Ray, t_max: f32) -> Ray {
        Ray::segment(object_from_world.transform_point3(ray.o), object_from_world.transform_vector3(ray.d), t_max)
            .at_time(ray.time)
    }

    /// Tests TLAS primitive `k`; replaces `best` when its hit is nearer, or equally near with
    /// smaller (instance, mesh, triangle) ids. Returns true when `best` changed.
    #[inline]
    fn visit(&self, k: usize, ray: &Ray, best: &mut Option<Hit>) -> bool {
        let p = &self.placed[k];
        let t_max = best.map_or(ray.t_max, |h| h.t);
        let (object_from_world, normal_cofactor) = p.at(ray.time);
        let Some(h) = self.blas[p.proto as usize].intersect(&Self::local_ray(&object_from_world, ray, t_max)) else {
            return false;
        };
        let hit = Hit {
            geom_id: self.proto_ids[p.proto as usize][h.geom_id as usize],
            ng: normal_cofactor * h.ng,
            inst_id: p.index,
            ..h
        };
        let better = best.is_none_or(|b| {
            hit.t < b.t || (hit.t == b.t && (hit.inst_id, hit.geom_id, hit.prim_id) < (b.inst_id, b.geom_id, b.prim_id))
        });
        if better {
            *best = Some(hit);
        }
        better
    }
}

fn usable(ray: &Ray) -> bool {
    ray.o.is_finite() && ray.d.is_finite() && ray.d != Vec3::ZERO && ray.t_max > 0.0
}

impl Accel for ObvhsInstancedAccel {
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if !usable(ray) {
            return None;
        }
        let mut best = self.world.intersect(ray).map(|h| Hit { geom_id: self.world_ids[h.geom_id as usize], ..h });
        if self.placed.is_empty() {
            return best;
        }
        if self.linear_fallback {
            for k in 0..self.placed.len() {
                self.visit(k, ray, &mut best);
            }
        } else {
            let t_max = best.map_or(ray.t_max, |h| h.t);
            // next_up: obvhs keeps a hit only when t' < tmax, and t = t_max is inside our range.
            let oray = obvhs_ray(ray, (t_max * T_SCALE).next_up());
            self.tlas.ray_traverse(oray, &mut RayHit::none(), |_, k| {
                if self.visit(k, ray, &mut best) {
                    best.map_or(f32::INFINITY, |h| (h.t * T_SCALE).next_up())
                } else {
                    f32::INFINITY
                }
            });
        }
        best
    }

    fn occluded(&self, ray: &Ray) -> bool {
        if !usable(ray) {
            return false;
        }
        if self.world.occluded(ray) {
            return true;
        }
        let blocks = |k: usize| {
            let p = &self.placed[k];
            self.blas[p.proto as usize].occluded(&Self::local_ray(&p.at(ray.time).0, ray, ray.t_max))
        };
        if self.linear_fallback {
            return (0..self.placed.len()).any(blocks);
        }
        if self.placed.is_empty() {
            return false;
        }
        let oray = obvhs_ray(ray, ray.t_max * T_SCALE);
        // The traversal stops at the first t' < tmax; 0 always is.
        !self.tlas.ray_traverse_miss(oray, |_, k| if blocks(k) { 0.0 } else { f32::INFINITY })
    }

    fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    fn memory_bytes(&self) -> usize {
        use std::mem::size_of_val;
        self.world.memory_bytes()
            + self.blas.iter().map(Blas::memory_bytes).sum::<usize>()
            + size_of_val(&self.tlas.nodes[..])
            + size_of_val(&self.tlas.primitive_indices[..])
            + size_of_val(&self.placed[..])
    }

    fn name(&self) -> &'static str {
        "obvhs"
    }
}

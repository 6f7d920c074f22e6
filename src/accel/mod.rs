//! Ray intersection. One trait, two backends: Intel Embree (feature `embree` for Embree 3 or
//! `embree4` for Embree 4; either sets `cfg(embree)`) and the pure-Rust obvhs BVH. Nothing backend-specific leaves this module.

#[cfg(embree)]
pub mod embree;
mod error;
mod extra;
pub mod huge_array;
pub mod obvhs;
pub mod obvhs_instanced;
pub mod watertight;

pub use self::error::AccelError;
pub use self::extra::WithExtra;
pub use self::obvhs::curves::CurveBvh;
pub use self::obvhs::quadrics::QuadricBvh;
pub use self::obvhs::{BuildQuality, BuildStats, ObvhsAccel};
pub use self::obvhs_instanced::ObvhsInstancedAccel;

use crate::geometry::InstanceSet;
use crate::geometry::{Bounds3, Curves, Hit, Mesh, PlacedQuadric, Ray};
use std::sync::Arc;

/// A ray-intersection accelerator over a set of triangle meshes.
pub trait Accel: Send + Sync {
    /// Closest hit with t in (0, ray.t_max], if any.
    fn intersect(&self, ray: &Ray) -> Option<Hit>;
    /// True when anything is hit with t in (0, ray.t_max) (shadow rays).
    fn occluded(&self, ray: &Ray) -> bool;
    /// Closest hits of a batch of rays, `hits[i]` for `rays[i]` (the wavefront loop's queues).
    /// The default traces them one by one; Embree traces them as 16-ray packets
    /// (`rtcIntersect16`).
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        rays.iter().zip(hits).for_each(|(r, h)| *h = self.intersect(r));
    }
    /// Occlusion of a batch of shadow rays, `blocked[i]` for `rays[i]`; Embree traces them as
    /// 16-ray packets (`rtcOccluded16`).
    fn occluded_batch(&self, rays: &[Ray], blocked: &mut [bool]) {
        rays.iter().zip(blocked).for_each(|(r, b)| *b = self.occluded(r));
    }
    /// Bounds of the whole scene.
    fn bounds(&self) -> Bounds3;
    /// Bytes the accelerator holds (BVH nodes and its own copies of the geometry).
    fn memory_bytes(&self) -> usize;
    /// Backend name, as on the command line.
    fn name(&self) -> &'static str;

    /// Appends every hit with t in (0, ray.t_max) to `hits`, in any order (BSSRDF probe rays).
    /// The default repeats [`Accel::intersect`] from just beyond each hit (two surfaces closer
    /// than ~2⁻¹⁶ of the distance travelled may merge into one hit); at most 256 hits.
    fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        let mut base = 0.0f32;
        for _ in 0..256 {
            let rest = Ray::segment(ray.at(base), ray.d, ray.t_max - base).at_time(ray.time);
            let Some(mut h) = self.intersect(&rest) else { return };
            h.t += base;
            if h.t.is_nan() || h.t >= ray.t_max {
                return;
            }
            hits.push(h);
            // Step past the hit by a relative margin larger than the hit point's rounding error.
            base = h.t + (h.t.abs() + ray.o.abs().max_element() / ray.d.length().max(f32::MIN_POSITIVE)) * 2e-6;
        }
    }
}

/// The backends, as named on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelKind {
    /// Intel Embree (feature `embree` or `embree4`) with its own triangle kernel: the fastest; lets about
    /// 1 in 4000 rays aimed exactly at a vertex through a closed mesh.
    Embree,
    /// Intel Embree's BVH with prism's watertight triangle test in user-geometry callbacks:
    /// no leaks, slower.
    EmbreeWatertight,
    /// The pure-Rust obvhs CWBVH (watertight).
    Obvhs,
}

crate::named::name_table!(AccelKind, "accelerator", {
    "embree" => AccelKind::Embree,
    "embree-watertight" => AccelKind::EmbreeWatertight,
    "obvhs" => AccelKind::Obvhs,
});

impl AccelKind {
    /// The default: Embree when compiled in, else obvhs.
    pub fn default_available() -> Self {
        if cfg!(embree) {
            AccelKind::Embree
        } else {
            AccelKind::Obvhs
        }
    }
}

/// Builds the chosen backend over `meshes` (geometry id = mesh index).
pub fn build(kind: AccelKind, meshes: &[Mesh]) -> Result<Box<dyn Accel>, AccelError> {
    match kind {
        #[cfg(embree)]
        AccelKind::Embree => Ok(Box::new(embree::EmbreeAccel::new(meshes)?)),
        #[cfg(embree)]
        AccelKind::EmbreeWatertight => Ok(Box::new(embree::EmbreeAccel::watertight(meshes)?)),
        #[cfg(not(embree))]
        AccelKind::Embree | AccelKind::EmbreeWatertight => Err(AccelError::NoEmbree),
        AccelKind::Obvhs => Ok(Box::new(obvhs::ObvhsAccel::new(meshes))),
    }
}

/// The geometry beside a scene's triangles, each paired with its geometry id (the id of a
/// primitive whose mesh is empty).
#[derive(Clone, Copy, Debug, Default)]
pub struct ExtraShapes<'a> {
    /// Curves (world space, or object space for a prototype's).
    pub curves: &'a [(u32, &'a Curves)],
    /// Quadrics with their placements.
    pub quadrics: &'a [(u32, &'a PlacedQuadric)],
}

impl ExtraShapes<'_> {
    /// True when there are neither curves nor quadrics.
    pub fn is_empty(&self) -> bool {
        self.curves.is_empty() && self.quadrics.is_empty()
    }

    /// `triangles` with these shapes beside it in BVHs of their own ([`WithExtra`]), or
    /// `triangles` itself when there are none.
    pub fn beside(&self, triangles: Box<dyn Accel>) -> Box<dyn Accel> {
        if self.is_empty() {
            return triangles;
        }
        let curves = (!self.curves.is_empty()).then(|| CurveBvh::new(self.curves));
        let quadrics = (!self.quadrics.is_empty()).then(|| QuadricBvh::new(self.quadrics));
        Box::new(WithExtra::new(triangles, curves, quadrics))
    }
}

/// The curves and the quadric of each primitive id, for splitting a scene's extra shapes
/// between the world and the prototypes.
pub(crate) struct ShapeTable<'a> {
    curves: Vec<Option<&'a Curves>>,
    quadrics: Vec<Option<&'a PlacedQuadric>>,
}

/// Curves and quadrics, each with the id its hits report.
pub(crate) type Picked<'a> = (Vec<(u32, &'a Curves)>, Vec<(u32, &'a PlacedQuadric)>);

impl<'a> ShapeTable<'a> {
    /// The table of `extra`.
    pub(crate) fn new(extra: ExtraShapes<'a>) -> Self {
        let ids = extra.curves.iter().map(|c| c.0).chain(extra.quadrics.iter().map(|q| q.0));
        let len = ids.max().map_or(0, |m| m as usize + 1);
        let (mut curves, mut quadrics) = (vec![None; len], vec![None; len]);
        for &(id, c) in extra.curves {
            curves[id as usize] = Some(c);
        }
        for &(id, q) in extra.quadrics {
            quadrics[id as usize] = Some(q);
        }
        Self { curves, quadrics }
    }

    /// The curves of primitive `id`, if it is a curve shape.
    pub(crate) fn curves(&self, id: u32) -> Option<&'a Curves> {
        self.curves.get(id as usize).copied().flatten()
    }

    /// The quadric of primitive `id`, if it is one.
    pub(crate) fn quadric(&self, id: u32) -> Option<&'a PlacedQuadric> {
        self.quadrics.get(id as usize).copied().flatten()
    }

    /// The curves and quadrics among primitives `ids`, each reported as `report(k, id)` of its
    /// index k in `ids`.
    pub(crate) fn pick(&self, ids: &[u32], report: impl Fn(u32, u32) -> u32) -> Picked<'a> {
        let mut picked: Picked<'a> = (Vec::new(), Vec::new());
        for (k, &id) in ids.iter().enumerate() {
            if let Some(c) = self.curves(id) {
                picked.0.push((report(k as u32, id), c));
            }
            if let Some(q) = self.quadric(id) {
                picked.1.push((report(k as u32, id), q));
            }
        }
        picked
    }
}

/// Builds the chosen backend over `meshes` and `curves` ((geometry id, its curves); the ids
/// are those of primitives whose meshes are empty): [`build_with_extra`] without quadrics.
pub fn build_with_curves(
    kind: AccelKind,
    meshes: &[Mesh],
    curves: &[(u32, &Curves)],
) -> Result<Box<dyn Accel>, AccelError> {
    build_with_extra(kind, meshes, ExtraShapes { curves, quadrics: &[] })
}

/// Builds the chosen backend over `meshes` and the curves and quadrics of `extra`, no
/// instances: [`build_scene`] with an empty [`InstanceSet`].
pub fn build_with_extra(kind: AccelKind, meshes: &[Mesh], extra: ExtraShapes) -> Result<Box<dyn Accel>, AccelError> {
    build_scene(kind, meshes, extra, &InstanceSet::default())
}

/// Builds the chosen backend over a scene with object instances of triangle meshes:
/// [`build_scene`] without curves and quadrics.
pub fn build_instanced(kind: AccelKind, meshes: &[Mesh], set: &InstanceSet) -> Result<Box<dyn Accel>, AccelError> {
    build_scene(kind, meshes, ExtraShapes::default(), set)
}

/// Builds the chosen backend over a whole scene — the one place accelerators are composed.
/// `meshes` are indexed by primitive id (empty for curves and quadrics), `extra` gives the
/// curves and quadrics by the same ids, and `set` the object instances: its world primitives
/// are traced as they are, each prototype (meshes, curves and static quadrics in object space)
/// is built once and traced through its instances' transforms. Hits report primitive ids
/// (`geom_id`) and the instance index (`inst_id`).
///
/// Embree holds everything in its scenes — curves as its curve geometry, static quadrics as user
/// geometry, prototypes as instanced scenes — except moving world quadrics (rays reach user
/// geometry without prism's time), which a [`QuadricBvh`] holds beside it. obvhs keeps the world's
/// curves and quadrics in BVHs beside its triangles, and each prototype's beside the prototype's
/// ([`WithExtra`]). A scene without curves, quadrics or instances gets the plain triangle
/// accelerator.
pub fn build_scene(
    kind: AccelKind,
    meshes: &[Mesh],
    extra: ExtraShapes,
    set: &InstanceSet,
) -> Result<Box<dyn Accel>, AccelError> {
    compose(kind, meshes, None, extra, set, None)
}

/// [`build_scene`] over meshes the accelerator may keep: Embree then reads their vertex and
/// index arrays in place (`rtcSetSharedGeometryBuffer`) instead of copying them, holding
/// `meshes` for as long as it lives. A mesh's positions need spare capacity for this (Embree
/// loads 16 bytes at each vertex); one without is copied. `rays`, the number of rays the render
/// expects to trace if known, lets Embree trade BVH quality for build time when they are few
/// (`embree::BuildChoice::for_triangles`).
pub fn build_scene_shared(
    kind: AccelKind,
    meshes: &Arc<[Mesh]>,
    extra: ExtraShapes,
    set: &InstanceSet,
    rays: Option<u64>,
) -> Result<Box<dyn Accel>, AccelError> {
    compose(kind, meshes, Some(meshes.clone()), extra, set, rays)
}

/// [`build_scene`], with Embree reading the arrays of `meshes` in place when `shared` holds them
/// and choosing its build for `rays`.
fn compose(
    kind: AccelKind,
    meshes: &[Mesh],
    shared: Option<Arc<[Mesh]>>,
    extra: ExtraShapes,
    set: &InstanceSet,
    rays: Option<u64>,
) -> Result<Box<dyn Accel>, AccelError> {
    // Only Embree's build depends on the number of rays; obvhs builds one way.
    #[cfg(not(embree))]
    let _ = rays;
    let instanced = !set.prototypes.is_empty();
    if extra.is_empty() && !instanced && (shared.is_none() || kind == AccelKind::Obvhs) {
        return build(kind, meshes);
    }
    let table = ShapeTable::new(extra);
    // The world's curves and quadrics, by their primitive ids.
    let (curves, quadrics) = if instanced {
        table.pick(&set.world_meshes, |_, id| id)
    } else {
        (extra.curves.to_vec(), extra.quadrics.to_vec())
    };
    match kind {
        #[cfg(embree)]
        AccelKind::Embree | AccelKind::EmbreeWatertight => {
            let test =
                if kind == AccelKind::Embree { embree::TriangleTest::Embree } else { embree::TriangleTest::Watertight };
            let (moving, fixed): (Vec<_>, Vec<_>) = quadrics.into_iter().partition(|(_, q)| q.moves());
            let scene = if instanced {
                embree::EmbreeAccel::instanced_with_shapes(meshes, &table, set, test, shared)
            } else {
                embree::EmbreeAccel::with_extra(meshes, &curves, &fixed, test, shared, rays)
            }?;
            Ok(ExtraShapes { curves: &[], quadrics: &moving }.beside(Box::new(scene)))
        }
        #[cfg(not(embree))]
        AccelKind::Embree | AccelKind::EmbreeWatertight => Err(AccelError::NoEmbree),
        AccelKind::Obvhs => {
            let triangles: Box<dyn Accel> = if instanced {
                Box::new(obvhs_instanced::ObvhsInstancedAccel::new(meshes, &table, set))
            } else {
                Box::new(obvhs::ObvhsAccel::new(meshes))
            };
            Ok(ExtraShapes { curves: &curves, quadrics: &quadrics }.beside(triangles))
        }
    }
}

/// Per-thread set-up a backend needs on every render thread (Embree: FTZ/DAZ).
pub fn init_render_thread() {
    #[cfg(embree)]
    embree::set_flush_denormals();
}

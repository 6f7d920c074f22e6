//! Ray intersection. One trait, two backends: Intel Embree (feature `embree` for Embree 3 or
//! `embree4` for Embree 4; either sets `cfg(embree)`) and the pure-Rust obvhs BVH. Nothing backend-specific leaves this module.

#[cfg(embree)]
pub mod embree;
mod extra;
pub mod huge_array;
pub mod obvhs;
pub mod obvhs_instanced;
pub mod watertight;

pub use self::extra::WithExtra;
pub use self::obvhs::curves::CurveBvh;
pub use self::obvhs::quadrics::QuadricBvh;
pub use self::obvhs::{BuildQuality, BuildStats, ObvhsAccel};
pub use self::obvhs_instanced::ObvhsInstancedAccel;

use crate::geometry::InstanceSet;
use crate::geometry::{Bounds3, Curves, Hit, Mesh, PlacedQuadric, Ray};

/// A ray-intersection accelerator over a set of triangle meshes.
pub trait Accel: Send + Sync {
    /// Closest hit with t in (0, ray.t_max], if any.
    fn intersect(&self, ray: &Ray) -> Option<Hit>;
    /// True when anything is hit with t in (0, ray.t_max) (shadow rays).
    fn occluded(&self, ray: &Ray) -> bool;
    /// Closest hits of eight rays traced together (`None` where `active` is false). The
    /// default traces them one by one; Embree traces them as one packet (`rtcIntersect8`).
    fn intersect8(&self, rays: &[Ray; 8], active: &[bool; 8]) -> [Option<Hit>; 8] {
        std::array::from_fn(|i| if active[i] { self.intersect(&rays[i]) } else { None })
    }
    /// Occlusion of eight shadow rays traced together (false where `active` is false).
    fn occluded8(&self, rays: &[Ray; 8], active: &[bool; 8]) -> [bool; 8] {
        std::array::from_fn(|i| active[i] && self.occluded(&rays[i]))
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

impl AccelKind {
    /// Parses "embree", "embree-watertight" or "obvhs".
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            "embree" => Ok(AccelKind::Embree),
            "embree-watertight" => Ok(AccelKind::EmbreeWatertight),
            "obvhs" => Ok(AccelKind::Obvhs),
            other => Err(format!("unknown accelerator '{other}' (valid: embree, embree-watertight, obvhs)")),
        }
    }

    /// The default: Embree when compiled in, else obvhs.
    pub fn default_available() -> Self {
        if cfg!(embree) {
            AccelKind::Embree
        } else {
            AccelKind::Obvhs
        }
    }

    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            AccelKind::Embree => "embree",
            AccelKind::EmbreeWatertight => "embree-watertight",
            AccelKind::Obvhs => "obvhs",
        }
    }
}

#[cfg(not(embree))]
const NO_EMBREE: &str = "this prism was built without Embree (feature `embree` or `embree4`); use --accel obvhs";

/// Builds the chosen backend over `meshes` (geometry id = mesh index).
pub fn build(kind: AccelKind, meshes: &[Mesh]) -> Result<Box<dyn Accel>, String> {
    match kind {
        #[cfg(embree)]
        AccelKind::Embree => Ok(Box::new(embree::EmbreeAccel::new(meshes).map_err(|e| e.to_string())?)),
        #[cfg(embree)]
        AccelKind::EmbreeWatertight => {
            Ok(Box::new(embree::EmbreeAccel::watertight(meshes).map_err(|e| e.to_string())?))
        }
        #[cfg(not(embree))]
        AccelKind::Embree | AccelKind::EmbreeWatertight => Err(NO_EMBREE.into()),
        AccelKind::Obvhs => Ok(Box::new(obvhs::ObvhsAccel::new(meshes))),
    }
}

/// The geometry beside a scene's triangles, each paired with its geometry id (the id of a
/// primitive whose mesh is empty).
#[derive(Clone, Copy, Debug, Default)]
pub struct ExtraShapes<'a> {
    /// Curves (world space).
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

/// Builds the chosen backend over `meshes` and `curves` ((geometry id, its curves); the ids
/// are those of primitives whose meshes are empty): [`build_with_extra`] without quadrics.
pub fn build_with_curves(
    kind: AccelKind,
    meshes: &[Mesh],
    curves: &[(u32, &Curves)],
) -> Result<Box<dyn Accel>, String> {
    build_with_extra(kind, meshes, ExtraShapes { curves, quadrics: &[] })
}

/// Builds the chosen backend over `meshes` and the curves and quadrics of `extra`. Embree
/// intersects curves as its own curve geometry and static quadrics as user geometry in the same
/// scene (moving quadrics in a [`QuadricBvh`] beside it); obvhs keeps both in BVHs beside the
/// triangles ([`WithExtra`]). Without either this is [`build`].
pub fn build_with_extra(kind: AccelKind, meshes: &[Mesh], extra: ExtraShapes) -> Result<Box<dyn Accel>, String> {
    if extra.is_empty() {
        return build(kind, meshes);
    }
    match kind {
        #[cfg(embree)]
        AccelKind::Embree | AccelKind::EmbreeWatertight => {
            let test =
                if kind == AccelKind::Embree { embree::TriangleTest::Embree } else { embree::TriangleTest::Watertight };
            let (moving, fixed): (Vec<_>, Vec<_>) = extra.quadrics.iter().partition(|(_, q)| q.moves());
            let scene =
                embree::EmbreeAccel::with_extra(meshes, extra.curves, &fixed, test).map_err(|e| e.to_string())?;
            Ok(ExtraShapes { curves: &[], quadrics: &moving }.beside(Box::new(scene)))
        }
        _ => Ok(extra.beside(build(kind, meshes)?)),
    }
}

/// Builds the chosen backend over a scene with object instances: `set.world_meshes` are traced
/// as they are, each prototype is built once and traced through its instances' transforms.
/// Hits report scene mesh ids (`geom_id`) and the instance index (`inst_id`).
pub fn build_instanced(kind: AccelKind, meshes: &[Mesh], set: &InstanceSet) -> Result<Box<dyn Accel>, String> {
    match kind {
        #[cfg(embree)]
        AccelKind::Embree => Ok(Box::new(embree::EmbreeAccel::instanced(meshes, set).map_err(|e| e.to_string())?)),
        #[cfg(embree)]
        AccelKind::EmbreeWatertight => Ok(Box::new(
            embree::EmbreeAccel::instanced_with_test(meshes, set, embree::TriangleTest::Watertight)
                .map_err(|e| e.to_string())?,
        )),
        #[cfg(not(embree))]
        AccelKind::Embree | AccelKind::EmbreeWatertight => Err(NO_EMBREE.into()),
        AccelKind::Obvhs => Ok(Box::new(obvhs_instanced::ObvhsInstancedAccel::new(meshes, set))),
    }
}

/// Per-thread set-up a backend needs on every render thread (Embree: FTZ/DAZ).
pub fn init_render_thread() {
    #[cfg(embree)]
    embree::set_flush_denormals();
}

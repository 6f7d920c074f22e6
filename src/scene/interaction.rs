//! The local geometry at a ray hit, recomputed from the mesh (not the backend) so that both
//! backends give identical shading and a bounded error for robust ray spawning; and what the hit
//! primitive binds to it (material, area light, media), which the integrator asks for here.

use super::{LightId, MediumInterface, Primitive, Scene};
use crate::bsdf::Bsdf;
use crate::geometry::{Hit, Ray};
use crate::light::Light;
use crate::material::{hit_key, Material, ShadingPoint};
use crate::math::{offset_ray_origin, triangle_point};
use crate::sampling::rng::hash64;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{TextureEvalContext, TextureFootprint};
use glam::{Vec2, Vec3};

/// A point on a surface where a ray hit, with the primitive it belongs to.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction<'s> {
    /// Hit point.
    pub p: Vec3,
    /// Per-axis bound on the absolute error of `p`.
    pub p_err: Vec3,
    /// Shading data for the material.
    pub shading: ShadingPoint,
    /// ∂p/∂v, with `shading.dpdu` the parameterisation that (u, v) footprints are found in.
    dpdv: Vec3,
    /// Unit direction back along the incoming ray.
    pub wo: Vec3,
    /// The primitive hit, with the scene's materials and lights (`None`: a virtual sensor).
    bound: Option<Bound<'s>>,
    /// Primitive index (the hit's `geom_id`).
    pub mesh: u32,
    /// Triangle index within the mesh.
    pub prim: u32,
    /// Instance index ([`Hit::NO_INSTANCE`] for world geometry).
    pub inst: u32,
}

/// What a hit on a primitive can ask of the scene.
#[derive(Clone, Copy, Debug)]
struct Bound<'s> {
    primitive: &'s Primitive,
    material: &'s Material,
    area_light: Option<(LightId, &'s Light)>,
}

impl<'s> SurfaceInteraction<'s> {
    /// Builds the interaction for `hit` of `ray` in `scene`.
    pub(super) fn new(scene: &'s Scene, ray: &Ray, hit: &Hit) -> Self {
        let primitive = &scene.primitives[hit.geom_id as usize];
        let area_light = primitive.area_light(hit.prim_id).map(|id| (id, &scene.lights[id as usize]));
        let bound = Bound { primitive, material: &scene.materials[primitive.material as usize], area_light };
        let mesh = &primitive.mesh;
        let tri = mesh.indices[hit.prim_id as usize];
        let p = mesh.triangle(hit.prim_id as usize);
        let b = [1.0 - hit.u - hit.v, hit.u, hit.v];
        let (point, p_err) = triangle_point(p, b);
        let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        // pbrt-v4's default (u, v) of a triangle's corners: (0, 0), (1, 0), (1, 1).
        let corner_uv = |k: usize| match &mesh.uvs {
            Some(uvs) => uvs[tri[k] as usize],
            None => [Vec2::ZERO, Vec2::X, Vec2::ONE][k],
        };
        let uv = corner_uv(0) * b[0] + corner_uv(1) * b[1] + corner_uv(2) * b[2];
        let interpolated = mesh.normals.as_ref().and_then(|normals| {
            let n = normals[tri[0] as usize] * b[0] + normals[tri[1] as usize] * b[1] + normals[tri[2] as usize] * b[2];
            (n.length_squared() > 0.0 && n.is_finite()).then_some(n)
        });
        // ∂p/∂u and ∂p/∂v from the corners' positions and (u, v) (pbrt-v4 §6.5.3); a degenerate
        // (u, v) layout falls back to edges of the triangle.
        let (duv02, duv12) = (corner_uv(0) - corner_uv(2), corner_uv(1) - corner_uv(2));
        let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        let (dpdu, dpdv) = if det.abs() > 1e-12 {
            ((dp02 * duv12.y - dp12 * duv02.y) / det, (dp12 * duv02.x - dp02 * duv12.x) / det)
        } else {
            (p[1] - p[0], ng.cross(p[1] - p[0]))
        };
        // An instance hit was computed in object space: carry the point with its error bound,
        // the normals and the tangent to world space (pbrt-v4 transforms interactions the same way).
        let (point, p_err, ng, interpolated, dpdu, dpdv) = match scene.instances.get(hit.inst_id as usize) {
            None => (point, p_err, ng, interpolated, dpdu, dpdv),
            Some(inst) => {
                let (wp, werr) = inst.point_to_world(point, p_err);
                (
                    wp,
                    werr,
                    inst.normal_to_world(ng),
                    interpolated.map(|n| inst.normal_to_world(n)),
                    inst.vector_to_world(dpdu),
                    inst.vector_to_world(dpdv),
                )
            }
        };
        let mut ns = ng;
        let mut ng_oriented = ng;
        if let Some(n) = interpolated {
            ns = n.normalize();
            // pbrt-v4: the geometric normal follows the side of the interpolated normal.
            if ng.dot(ns) < 0.0 {
                ng_oriented = -ng;
            }
        }
        Self {
            p: point,
            p_err,
            shading: ShadingPoint { ns, ng: ng_oriented, dpdu, tex: TextureEvalContext::at(point, ns, uv) },
            dpdv,
            wo: -ray.d.normalize(),
            bound: Some(bound),
            mesh: hit.geom_id,
            prim: hit.prim_id,
            inst: hit.inst_id,
        }
    }

    /// A virtual surface point (a sensor) at `p` facing `n`, not part of any mesh.
    pub fn sensor(p: Vec3, n: Vec3) -> Self {
        Self {
            p,
            p_err: p.abs() * crate::math::offset::gamma(4),
            shading: ShadingPoint { ns: n, ng: n, dpdu: Vec3::ZERO, tex: TextureEvalContext::at(p, n, Vec2::ZERO) },
            dpdv: Vec3::ZERO,
            wo: n,
            bound: None,
            mesh: u32::MAX,
            prim: u32::MAX,
            inst: Hit::NO_INSTANCE,
        }
    }

    /// The same point with the pixel footprint `footprint` estimates there, for filtered
    /// texture lookups (pbrt-v4 `SurfaceInteraction::ComputeDifferentials`); materials whose
    /// textures are all constants skip the estimate.
    pub fn with_texture_footprint(mut self, footprint: &TextureFootprint) -> Self {
        if !self.bound.is_some_and(|b| b.material.is_textured()) {
            return self;
        }
        let (dpdx, dpdy) = footprint.dp_dxy(self.p, self.shading.ns);
        self.shading.tex = self.shading.tex.with_footprint(dpdx, dpdy, self.shading.dpdu, self.dpdv);
        self
    }

    /// The material of the surface (`None` for a virtual sensor); a mix is resolved to the
    /// material it chooses for this point and direction.
    #[inline]
    pub fn material(&self) -> Option<&'s Material> {
        self.bound.map(|b| match b.material {
            Material::Mix(_) => b.material.resolve(hit_key(self.p, self.wo), &self.shading.tex),
            m => m,
        })
    }

    /// The BSDF at this point at the wavelengths `w`, which a dispersive material reduces to
    /// the hero wavelength (`None` for a virtual sensor or an interface).
    #[inline]
    pub fn bsdf(&self, w: &mut SampledWavelengths) -> Option<Bsdf> {
        self.material().and_then(|m| m.bsdf(&self.shading, w))
    }

    /// True when the primitive's alpha mask lets `ray` through here. Alpha a ≥ 1 keeps every
    /// hit, a ≤ 0 none; a fractional a keeps a hit with probability a, decided by a hash of the
    /// ray so that the decision is the same every time the same ray is traced (pbrt-v4's
    /// stochastic alpha).
    pub fn is_cut_out(&self, ray: &Ray) -> bool {
        let Some(alpha) = self.bound.and_then(|b| b.primitive.alpha.as_ref()) else { return false };
        let a = alpha.eval(&self.shading.tex);
        if a >= 1.0 {
            return false;
        }
        if a <= 0.0 {
            return true;
        }
        let bits = [ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z].map(|v| u64::from(v.to_bits()));
        let u = (hash64(&bits) >> 40) as f32 * (1.0 / (1u64 << 24) as f32);
        u > a
    }

    /// True when the surface is only a boundary between media (an interface material): a ray
    /// continues through it unchanged.
    #[inline]
    pub fn is_passthrough(&self) -> bool {
        self.material().is_some_and(Material::is_interface)
    }

    /// The area light of the triangle hit, if it emits: its index (for the light sampler's pmf,
    /// [`Scene::light_pdf`]) and the light.
    #[inline]
    pub fn area_light(&self) -> Option<(LightId, &'s Light)> {
        self.bound.and_then(|b| b.area_light)
    }

    /// Radiance L_e [W/(sr·m²·nm)] the surface emits toward `wo` (pbrt-v4 `SurfaceInteraction::Le`).
    #[inline]
    pub fn emitted(&self, w: &SampledWavelengths) -> SampledSpectrum {
        match self.area_light() {
            Some((_, light)) => light.surface_radiance(self.shading.ng, self.wo, w),
            None => SampledSpectrum::zero(),
        }
    }

    /// The largest bounding-sphere radius among the primitives of this point's material (0 for a
    /// virtual sensor): the size of the object a path entering it is inside.
    pub fn material_radius(&self, scene: &Scene) -> f32 {
        self.bound.map_or(0.0, |b| scene.material_radius(b.primitive.material))
    }

    /// The media on either side of the surface.
    #[inline]
    pub fn medium_interface(&self) -> MediumInterface {
        self.bound.map_or_else(MediumInterface::default, |b| b.primitive.medium_interface)
    }

    /// A ray leaving the surface along `d`, its origin offset past the error bound of `p`.
    #[inline]
    pub fn spawn_ray(&self, d: Vec3) -> Ray {
        Ray::new(offset_ray_origin(self.p, self.p_err, self.shading.ng, d), d)
    }

    /// A shadow ray from this point to `target` (a point on a light), stopping just short of it.
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        let o = offset_ray_origin(self.p, self.p_err, self.shading.ng, target - self.p);
        // pbrt-v4's ShadowEpsilon: stop at 1 − 1e-4 of the way to avoid hitting the light itself.
        Ray::segment(o, target - o, 1.0 - 1e-4)
    }

    /// The rest of a shadow ray whose end point `end` is already short of the light: from this
    /// point to exactly `end`.
    #[inline]
    pub fn spawn_ray_to_point(&self, end: Vec3) -> Ray {
        let o = offset_ray_origin(self.p, self.p_err, self.shading.ng, end - self.p);
        Ray::segment(o, end - o, 1.0)
    }
}

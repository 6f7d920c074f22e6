//! The local geometry at a ray hit, recomputed from the mesh (not the backend) so that both
//! backends give identical shading and a bounded error for robust ray spawning; and what the hit
//! primitive binds to it (material, area light, media), which the integrator asks for here.

use super::{LightId, MediumInterface, Primitive, Scene};
use crate::bsdf::Bsdf;
use crate::geometry::{Hit, Ray, Shape};
use crate::light::Light;
use crate::material::{hit_key, Material, ShadingDerivatives, ShadingPoint};
use crate::math::{offset_ray_origin, triangle_point};
use crate::sampling::rng::hash64;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{Footprint, TextureEvalContext};
use glam::{Vec2, Vec3};

/// A point on a surface where a ray hit, with the primitive it belongs to.
///
/// The path loop moves one of these per vertex, so it is kept small (at most 128 bytes, which
/// the compiler copies with a few vector moves rather than a `memcpy` call): what textures
/// need is assembled only when a BSDF is asked for ([`Self::shading_point`]).
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction<'s> {
    /// Hit point.
    pub p: Vec3,
    /// Per-axis bound on the absolute error of `p`.
    pub p_err: Vec3,
    /// The shading and geometric normals.
    pub shading: SurfaceNormals,
    /// ∂p/∂u: the tangent of anisotropic frames, and with `dpdv` the parameterisation that
    /// (u, v) footprints are found in.
    pub dpdu: Vec3,
    /// ∂p/∂v.
    dpdv: Vec3,
    /// Surface texture coordinates (u, v).
    pub uv: Vec2,
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
    /// The instant of the incoming ray, which every ray spawned here inherits.
    pub time: f32,
}

/// The two normals at a surface point (unit vectors).
#[derive(Clone, Copy, Debug)]
pub struct SurfaceNormals {
    /// Shading normal: interpolated, or the geometric one.
    pub ns: Vec3,
    /// Geometric normal, on the side of `ns`.
    pub ng: Vec3,
}

/// What a hit on a primitive can ask of the scene.
#[derive(Clone, Copy)]
struct Bound<'s> {
    scene: &'s Scene,
    primitive: &'s Primitive,
}

impl std::fmt::Debug for Bound<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bound").field("material", &self.primitive.material).finish_non_exhaustive()
    }
}

impl<'s> Bound<'s> {
    #[inline]
    fn material(&self) -> &'s Material {
        &self.scene.materials[self.primitive.material as usize]
    }
}

impl<'s> SurfaceInteraction<'s> {
    /// Builds the interaction for `hit` of `ray` in `scene`.
    pub(super) fn new(scene: &'s Scene, ray: &Ray, hit: &Hit) -> Self {
        let primitive = &scene.primitives[hit.geom_id as usize];
        let mesh = match &primitive.shape {
            Shape::Mesh(_) => scene.mesh(hit.geom_id),
            Shape::Curves(curves) => return Self::on_curve(scene, primitive, curves, ray, hit),
            Shape::Quadric(quadric) => return Self::on_quadric(scene, primitive, quadric, ray, hit),
        };
        let bound = Bound { scene, primitive };
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
        let interpolated = mesh.normals.as_ref().and_then(|normals| {
            let n = normals[tri[0] as usize] * b[0] + normals[tri[1] as usize] * b[1] + normals[tri[2] as usize] * b[2];
            (n.length_squared() > 0.0 && n.is_finite()).then_some(n)
        });
        // ∂p/∂u and ∂p/∂v from the corners' positions and (u, v) (pbrt-v4 §6.5.3); a degenerate
        // (u, v) layout falls back to edges of the triangle. A boundary between media that
        // nothing shades or textures needs neither, nor (u, v).
        let (uv, dpdu, dpdv) = if primitive.bare_boundary {
            (Vec2::ZERO, Vec3::ZERO, Vec3::ZERO)
        } else {
            let uv = corner_uv(0) * b[0] + corner_uv(1) * b[1] + corner_uv(2) * b[2];
            let (duv02, duv12) = (corner_uv(0) - corner_uv(2), corner_uv(1) - corner_uv(2));
            let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
            let det = duv02.x * duv12.y - duv02.y * duv12.x;
            if det.abs() > 1e-12 {
                (uv, (dp02 * duv12.y - dp12 * duv02.y) / det, (dp12 * duv02.x - dp02 * duv12.x) / det)
            } else {
                (uv, p[1] - p[0], ng.cross(p[1] - p[0]))
            }
        };
        // An instance hit was computed in object space: carry the point with its error bound,
        // the normals and the tangent to world space (pbrt-v4 transforms interactions the same way).
        // A moving instance is placed where it is at the ray's time.
        let (point, p_err, ng, interpolated, dpdu, dpdv) = match scene.instances.get(hit.inst_id as usize) {
            None => (point, p_err, ng, interpolated, dpdu, dpdv),
            Some(inst) => {
                let inst = inst.at(ray.time);
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
            shading: SurfaceNormals { ns, ng: ng_oriented },
            dpdu,
            dpdv,
            uv,
            wo: -ray.d.normalize(),
            bound: Some(bound),
            mesh: hit.geom_id,
            prim: hit.prim_id,
            inst: hit.inst_id,
            time: ray.time,
        }
    }

    /// A virtual surface point (a sensor) at `p` facing `n`, not part of any mesh.
    pub fn sensor(p: Vec3, n: Vec3) -> Self {
        Self {
            p,
            p_err: p.abs() * crate::math::offset::gamma(4),
            shading: SurfaceNormals { ns: n, ng: n },
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            uv: Vec2::ZERO,
            wo: n,
            bound: None,
            mesh: u32::MAX,
            prim: u32::MAX,
            inst: Hit::NO_INSTANCE,
            time: 0.0,
        }
    }

    /// What the material sees at this point: the normals, ∂p/∂u and the texture context,
    /// with the pixel footprint `footprint` estimates here for filtered texture lookups
    /// (pbrt-v4 `SurfaceInteraction::ComputeDifferentials`) when the material has textures
    /// that vary; `None` gives the finest texture detail.
    pub fn shading_point(&self, footprint: Option<Footprint>) -> ShadingPoint {
        self.shading_point_for(self.bound.map(|b| b.material()), footprint)
    }

    fn shading_point_for(&self, material: Option<&Material>, footprint: Option<Footprint>) -> ShadingPoint {
        let mut tex = self.texture_point();
        if let Some(f) = footprint.filter(|_| material.is_some_and(Material::is_textured)) {
            let (dpdx, dpdy) = f.dp_dxy(self.p, self.shading.ns, self.time);
            tex = tex.with_footprint(dpdx, dpdy, self.dpdu, self.dpdv);
        }
        ShadingPoint { ns: self.shading.ns, ng: self.shading.ng, dpdu: self.dpdu, tex }
    }

    /// The shading frame's derivatives as pbrt-v4's triangles set them (§6.5.3): without
    /// vertex normals, ∂p/∂u, ∂p/∂v and a constant normal; with them, ∂p/∂u made
    /// perpendicular to the shading normal n, ∂p/∂v = n × ∂p/∂u, and ∂n/∂u, ∂n/∂v from the
    /// corners' normals and (u, v) as ∂p/∂u and ∂p/∂v are found from their positions.
    fn shading_derivatives(&self, b: Bound<'s>) -> ShadingDerivatives {
        let flat = ShadingDerivatives { dpdu: self.dpdu, dpdv: self.dpdv, ..Default::default() };
        let mesh = match &b.primitive.shape {
            Shape::Mesh(_) => b.scene.mesh(self.mesh),
            Shape::Quadric(q) => return self.quadric_derivatives(b.scene, q),
            Shape::Curves(_) => return flat,
        };
        // Triangles without vertex normals are flat.
        let Some(normals) = &mesh.normals else { return flat };
        let ns = self.shading.ns;
        let ts = ns.cross(self.dpdu);
        let (ss, ts) = if ts.length_squared() > 0.0 { (ts.cross(ns), ts) } else { ns.any_orthonormal_pair() };
        let tri = mesh.indices[self.prim as usize];
        let instance = b.scene.instances.get(self.inst as usize).map(|i| i.at(self.time));
        let n = |k: usize| {
            let n = normals[tri[k] as usize];
            instance.as_ref().map_or(n, |inst| inst.normal_to_world(n))
        };
        let uv = |k: usize| match &mesh.uvs {
            Some(uvs) => uvs[tri[k] as usize],
            None => [Vec2::ZERO, Vec2::X, Vec2::ONE][k],
        };
        let (duv02, duv12) = (uv(0) - uv(2), uv(1) - uv(2));
        let (dn02, dn12) = (n(0) - n(2), n(1) - n(2));
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        let (dndu, dndv) = if det.abs() > 1e-12 {
            ((dn02 * duv12.y - dn12 * duv02.y) / det, (dn12 * duv02.x - dn02 * duv12.x) / det)
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        ShadingDerivatives { dpdu: ss, dpdv: ts, dndu, dndv }
    }

    /// Where textures are evaluated here, without a footprint.
    #[inline]
    fn texture_point(&self) -> TextureEvalContext {
        TextureEvalContext::at(self.p, self.shading.ns, self.uv)
    }

    /// The material of the surface (`None` for a virtual sensor); a mix is resolved to the
    /// material it chooses for this point and direction.
    #[inline]
    pub fn material(&self) -> Option<&'s Material> {
        self.bound.map(|b| self.resolve(b.material(), &self.texture_point()))
    }

    /// `material` itself, or for a mix the material it chooses at `tex` for this point and
    /// direction.
    #[inline]
    fn resolve(&self, material: &'s Material, tex: &TextureEvalContext) -> &'s Material {
        match material {
            Material::Mix(_) => self.resolve_mix(material, tex),
            m => m,
        }
    }

    /// [`Self::resolve`] for a mix, kept out of line so that the hash of the hit is not
    /// computed speculatively for every other material.
    #[inline(never)]
    fn resolve_mix(&self, mix: &'s Material, tex: &TextureEvalContext) -> &'s Material {
        mix.resolve(hit_key(self.p, self.wo), tex)
    }

    /// The BSDF at this point at the wavelengths `w`, which a dispersive material reduces to
    /// the hero wavelength (`None` for a virtual sensor or an interface); textures are
    /// filtered over `footprint`'s estimate of the pixel footprint.
    #[inline]
    pub fn bsdf(&self, w: &mut SampledWavelengths, footprint: Option<Footprint>) -> Option<Bsdf> {
        let b = self.bound?;
        let material = self.resolve(b.material(), &self.texture_point());
        let sp = self.shading_point_for(Some(material), footprint);
        match material {
            Material::Bumped(bumped) => {
                let sp = bumped.perturbation.apply(&sp, &self.shading_derivatives(b));
                bumped.base.bsdf(&sp, w)
            }
            m => m.bsdf(&sp, w),
        }
    }

    /// True when the primitive's alpha mask lets `ray` through here. Alpha a ≥ 1 keeps every
    /// hit, a ≤ 0 none; a fractional a keeps a hit with probability a, decided by a hash of the
    /// ray so that the decision is the same every time the same ray is traced (pbrt-v4's
    /// stochastic alpha).
    pub fn is_cut_out(&self, ray: &Ray) -> bool {
        let Some(alpha) = self.bound.and_then(|b| b.primitive.alpha.as_ref()) else { return false };
        let a = alpha.eval(&self.texture_point());
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
        match self.bound.map(|b| b.material()) {
            Some(Material::Interface) => true,
            Some(m @ Material::Mix(_)) if m.may_be_interface() => self.material().is_some_and(Material::is_interface),
            _ => false,
        }
    }

    /// The area light of the triangle hit, if it emits: its index (for the light sampler's pmf,
    /// [`Scene::light_pdf`]) and the light.
    #[inline]
    pub fn area_light(&self) -> Option<(LightId, &'s Light)> {
        let b = self.bound?;
        let id = b.primitive.area_light(self.prim)?;
        Some((id, &b.scene.lights[id as usize]))
    }

    /// Radiance L_e [W/(sr·m²·nm)] the surface emits toward `wo` (pbrt-v4 `SurfaceInteraction::Le`).
    #[inline]
    pub fn emitted(&self, w: &SampledWavelengths) -> SampledSpectrum {
        match self.area_light() {
            Some((_, light)) => light.surface_radiance(self.shading.ng, self.wo, self.uv, w),
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
        Ray::new(offset_ray_origin(self.p, self.p_err, self.shading.ng, d), d).at_time(self.time)
    }

    /// `ray` continued through this surface, which only bounds media (see
    /// [`Self::is_passthrough`]): the same direction from here, and the medium on the side it
    /// enters, given `medium`, the one it arrived in.
    #[inline]
    pub fn pass_through(&self, ray: &Ray, medium: Option<u32>) -> (Ray, Option<u32>) {
        (self.spawn_ray(ray.d), self.medium_interface().medium_toward(ray.d, self.shading.ng, medium))
    }

    /// A shadow ray from this point to `target` (a point on a light), stopping just short of it.
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        let o = offset_ray_origin(self.p, self.p_err, self.shading.ng, target - self.p);
        // pbrt-v4's ShadowEpsilon: stop at 1 − 1e-4 of the way to avoid hitting the light itself.
        Ray::segment(o, target - o, 1.0 - 1e-4).at_time(self.time)
    }

    /// The rest of a shadow ray whose end point `end` is already short of the light: from this
    /// point to exactly `end`.
    #[inline]
    pub fn spawn_ray_to_point(&self, end: Vec3) -> Ray {
        let o = offset_ray_origin(self.p, self.p_err, self.shading.ng, end - self.p);
        Ray::segment(o, end - o, 1.0).at_time(self.time)
    }
}

#[path = "curve_interaction.rs"]
mod curve_interaction;
#[path = "quadric_interaction.rs"]
mod quadric_interaction;

#[cfg(test)]
mod tests {
    #[test]
    fn the_per_hit_structures_stay_small_enough_to_move_without_memcpy() {
        // The path loop moves one interaction and one BSDF per vertex; beyond 128 bytes the
        // compiler calls `memcpy` for each move (measured: 5% of the Cornell box's time).
        assert!(std::mem::size_of::<super::SurfaceInteraction>() <= 128);
        assert!(std::mem::size_of::<crate::bsdf::Bsdf>() <= 128);
    }
}

//! The two ways to continue a path that refracts into a subsurface material.
//!
//! - [`SubsurfaceMethod::Diffusion`]: the separable PBD BSSRDF. An entry point p_i is found by a
//!   probe ray ([`crate::bssrdf::TabulatedBssrdf`]) among all surfaces of the same mesh on the
//!   probe segment (one chosen uniformly), the throughput is multiplied by
//!   S_p(p_i) / (pdf(p_i) / n_hits), and the path continues from p_i with the S_ω lobe
//!   (L_o = ∫_A ∫_{H²} S L_i cos θ_i dω_i dA, Jensen et al., "A Practical Model for Subsurface
//!   Light Transport", SIGGRAPH 2001; estimated with one area sample).
//! - [`SubsurfaceMethod::RandomWalk`]: the reference. Volumetric path tracing inside the object:
//!   free-flight sampling with spectral MIS ([`crate::media::HomogeneousMedium`]),
//!   Henyey–Greenstein scattering, and the dielectric boundary sampled at every surface hit
//!   (reflection stays inside, refraction leaves). Unbiased up to [`MAX_WALK_EVENTS`].
//!
//! With `Diffusion`, media whose longest mean free path exceeds the object's bounding radius
//! (optically thin objects, where PBD's semi-infinite assumption loses most of the light) are
//! walked instead.
//!
//! Both assume the subsurface object does not intersect other geometry: a hit inside the medium
//! is treated as its boundary.

use super::Stats;
use crate::bsdf::{Bsdf, BsdfSample, TransportMode};
use crate::bssrdf::TabulatedBssrdf;
use crate::geometry::{Hit, Ray};
use crate::light::LightSampleContext;
use crate::material::{Material, SubsurfaceMaterial};
use crate::math::Frame;
use crate::media::{FreeFlight, HomogeneousMedium};
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// Scattering events after which a random walk is abandoned (a bias only for media so thick
/// and white that a walk this long has non-negligible probability).
pub const MAX_WALK_EVENTS: u32 = 100_000;
/// Events after which Russian roulette may end a walk.
const WALK_RR_EVENTS: u32 = 8;

/// How paths entering a subsurface material are continued (`prism render --sss`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SubsurfaceMethod {
    /// Photon beam diffusion BSSRDF with probe-ray sampling (fast, biased by the model).
    #[default]
    Diffusion,
    /// Brute-force volumetric random walk (slow, unbiased reference).
    RandomWalk,
}

crate::named::name_table!(SubsurfaceMethod, "subsurface method", {
    "diffusion" => SubsurfaceMethod::Diffusion,
    "randomwalk" => SubsurfaceMethod::RandomWalk,
    "random-walk" => SubsurfaceMethod::RandomWalk,
});

/// Where the path goes on after the subsurface event. Returned by value once per event and
/// taken apart at once, so the size gap between the variants costs a copy, not memory held.
#[allow(clippy::large_enum_variant)]
pub(super) enum Exit<'s> {
    /// A new vertex at p_i with its BSDF (diffusion): light sampling and BSDF sampling go on
    /// from there.
    Vertex(SurfaceInteraction<'s>, Bsdf),
    /// A ray leaving the object from the exit point (random walk; with its shading normal),
    /// sampled from the boundary's lobe with this solid-angle density (`None`: a delta lobe), for
    /// MIS with the light sampling done there.
    Ray(Ray, LightSampleContext, Option<f32>),
}

/// The subsurface material a path enters when its sample `bs` at `si` (with BSDF shading normal
/// `ns`) refracts into the surface; `None` for any other sample or material. The material is
/// resolved only for inward transmissions, so other bounces pay nothing.
pub(super) fn entered<'s>(si: &SurfaceInteraction<'s>, bs: &BsdfSample, ns: Vec3) -> Option<&'s SubsurfaceMaterial> {
    if !bs.is_transmission() || bs.wi.dot(ns) >= 0.0 {
        return None;
    }
    si.material().and_then(Material::subsurface)
}

/// Next-event estimation at a boundary vertex of a random walk: the light sampled from the
/// vertex through its BSDF, MIS-weighted the way the calling integrator weights the emission
/// its BSDF-sampled rays find (per unit throughput).
pub(super) type BoundaryNee<'n> =
    &'n mut dyn FnMut(&SurfaceInteraction, &Bsdf, &mut Sampler, &mut Stats) -> SampledSpectrum;

/// Continues a path that refracted at `si` into the material along `wi`, multiplying `beta`
/// by the transport inside, by `method`. `nee` (none: no light sampling) estimates direct light
/// at the walk's boundary vertices. `None`: the path ends (absorbed, or no entry point found).
#[allow(clippy::too_many_arguments)]
pub(super) fn enter<'s>(
    method: SubsurfaceMethod,
    nee: Option<BoundaryNee>,
    scene: &'s Scene,
    material: &SubsurfaceMaterial,
    si: &SurfaceInteraction<'s>,
    wi: Vec3,
    (beta, l): (&mut SampledSpectrum, &mut SampledSpectrum),
    w: &SampledWavelengths,
    sampler: &mut Sampler,
    stats: &mut Stats,
) -> Option<Exit<'s>> {
    let medium = material.medium(&si.shading_point(None), w);
    // Diffusion assumes an optically thick object; where the longest mean free path exceeds the
    // object's bounding radius, the medium is nearly clear, PBD would lose most of the light,
    // and a walk needs only a few events: take the walk.
    let thin = || {
        let mfp = medium.sigma_t().min_value().recip();
        mfp > material.object_radius(|| si.material_radius(scene))
    };
    match method {
        SubsurfaceMethod::Diffusion if !thin() => diffusion(scene, material, &medium, si, beta, sampler, stats),
        _ => {
            let walk = Walk { scene, material, medium: &medium };
            walk.run(si, wi, (beta, l), nee, sampler, stats)
        }
    }
}

fn diffusion<'s>(
    scene: &'s Scene,
    material: &SubsurfaceMaterial,
    medium: &HomogeneousMedium,
    si: &SurfaceInteraction<'s>,
    beta: &mut SampledSpectrum,
    sampler: &mut Sampler,
    stats: &mut Stats,
) -> Option<Exit<'s>> {
    let frame = Frame::from_normal_tangent(si.shading.ns, si.dpdu);
    let bssrdf = TabulatedBssrdf::new(material.table(), si.p, frame, medium.sigma_t(), medium.albedo());
    let u1 = sampler.get_1d();
    let u2 = sampler.get_2d();
    let uh = sampler.get_1d();
    let seg = bssrdf.sample(u1, u2)?;
    let probe = Ray::segment(seg.p0, seg.p1 - seg.p0, 1.0).at_time(si.time);
    let mut hits: Vec<Hit> = Vec::with_capacity(8);
    stats.rays += 1;
    scene.all_hits(&probe, &mut hits);
    hits.retain(|h| h.geom_id == si.mesh);
    if hits.is_empty() {
        return None;
    }
    // Deterministic order, so the choice does not depend on the backend's traversal order.
    hits.sort_by(|a, b| a.t.total_cmp(&b.t));
    let k = ((uh * hits.len() as f32) as usize).min(hits.len() - 1);
    let mut pi = scene.interaction(&probe, &hits[k]);
    let pdf = bssrdf.pdf_sp(pi.p, pi.shading.ng) / hits.len() as f32;
    if pdf.is_nan() || pdf <= 0.0 {
        return None;
    }
    *beta *= bssrdf.sp(pi.p) / pdf;
    if beta.is_black() || !beta.is_finite() {
        return None;
    }
    // S_ω ignores ωo except for its side: pbrt sets it to the normal.
    pi.wo = pi.shading.ns;
    let bsdf = material.entry_bsdf(&pi.shading_point(None));
    Some(Exit::Vertex(pi, bsdf))
}

/// What a random walk needs besides the path state.
struct Walk<'a> {
    scene: &'a Scene,
    material: &'a SubsurfaceMaterial,
    medium: &'a HomogeneousMedium,
}

impl Walk<'_> {
    /// Walks from `si` along `wi` (into the medium) until the path refracts out. At every
    /// boundary hit with a non-delta lobe, light is sampled through the boundary (next-event
    /// estimation, MIS against the lobe) and added to `l`.
    fn run<'s>(
        &self,
        si: &SurfaceInteraction<'_>,
        wi: Vec3,
        (beta, l): (&mut SampledSpectrum, &mut SampledSpectrum),
        mut nee: Option<BoundaryNee>,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> Option<Exit<'s>> {
        let scene = self.scene;
        let phase = self.material.phase();
        let mut ray = si.spawn_ray(wi.normalize());
        let mut scatterings = 0u32;
        for _ in 0..MAX_WALK_EVENTS {
            stats.rays += 1;
            let hit = scene.closest_hit(&ray);
            let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
            let (uc, ud) = (sampler.get_1d(), sampler.get_1d());
            match self.medium.sample_free_flight(t_hit, uc, ud) {
                FreeFlight::Scatter { t, weight } => {
                    *beta *= weight;
                    scatterings += 1;
                    let p = ray.at(t);
                    ray = Ray::new(p, phase.sample(ray.d, sampler.get_2d())).at_time(ray.time);
                }
                FreeFlight::Pass { weight } => {
                    *beta *= weight;
                    let h = hit?;
                    let b = scene.interaction(&ray, &h);
                    let bsdf = self.material.boundary_bsdf(&b.shading_point(None));
                    if let Some(nee) = nee.as_mut().filter(|_| bsdf.flags().is_non_specular()) {
                        *l += *beta * nee(&b, &bsdf, sampler, stats);
                    }
                    let bs = bsdf.sample_f(b.wo, sampler.get_1d(), sampler.get_2d(), TransportMode::Radiance)?;
                    *beta *= bs.f * (bs.wi.dot(b.shading.ns).abs() / bs.pdf);
                    let next = b.spawn_ray(bs.wi);
                    if bs.wi.dot(b.shading.ns) > 0.0 {
                        let pdf = if bs.is_specular() { None } else { Some(bs.pdf) };
                        return (!beta.is_black()).then_some(Exit::Ray(
                            next,
                            LightSampleContext::surface(b.p, bsdf.ns()),
                            pdf,
                        ));
                    }
                    ray = next;
                }
            }
            if beta.is_black() {
                return None;
            }
            // Russian roulette once the walk is long and dim (pbrt-v4 volpath's rule).
            if scatterings >= WALK_RR_EVENTS && beta.max_value() < 1.0 {
                let q = (1.0 - beta.max_value()).max(0.0);
                if sampler.get_1d() < q {
                    return None;
                }
                *beta /= 1.0 - q;
            }
        }
        None
    }
}

#[cfg(test)]
#[path = "subsurface_tests.rs"]
mod tests;

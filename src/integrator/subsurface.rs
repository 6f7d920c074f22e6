//! The two ways to continue a path that refracts into a subsurface material.
//!
//! - [`SubsurfaceMethod::Diffusion`]: the separable PBD BSSRDF. An entry point p_i is found by a
//!   probe ray ([`crate::bssrdf::TabulatedBssrdf`]) among all surfaces of the same mesh on the
//!   probe segment (one chosen uniformly), the throughput is multiplied by
//!   S_p(p_i) / (pdf(p_i) / n_hits), and the path continues from p_i with the S_ω lobe
//!   (L_o = ∫_A ∫_{H²} S L_i cos θ_i dω_i dA, Jensen et al., "A Practical Model for Subsurface
//!   Light Transport", SIGGRAPH 2001; estimated with one area sample).
//! - [`SubsurfaceMethod::RandomWalk`]: the reference. The volumetric loop goes on inside the
//!   object with the material's homogeneous interior ([`Interior`]) as its medium: delta
//!   tracking ([`crate::media::sample_t_maj_homogeneous`], the collisions of
//!   [`super::collision`]) with the path's spectral MIS, Henyey–Greenstein scattering, and the
//!   dielectric boundary sampled at every surface hit, light sampled through it (reflection
//!   stays inside, refraction leaves). Unbiased up to [`MAX_WALK_EVENTS`].
//!
//! With `Diffusion`, media whose longest mean free path exceeds the object's bounding radius
//! (optically thin objects, where PBD's semi-infinite assumption loses most of the light) are
//! walked instead.
//!
//! Both assume the subsurface object does not intersect other geometry: a hit inside the medium
//! is treated as its boundary.

use super::Stats;
use crate::bsdf::{Bsdf, BsdfSample};
use crate::bssrdf::TabulatedBssrdf;
use crate::geometry::{Hit, Ray};
use crate::material::{Material, SubsurfaceMaterial};
use crate::math::Frame;
use crate::media::MediumPoint;
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// Scattering events after which a random walk is abandoned (a bias only for media so thick
/// and white that a walk this long has non-negligible probability).
pub const MAX_WALK_EVENTS: u32 = 100_000;
/// Scatterings after which Russian roulette may end a walk (the walk's events are not path
/// vertices: a walk of any length is one subsurface event of the path).
pub(super) const WALK_RR_EVENTS: u32 = 8;

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

/// The subsurface material a path enters when its sample `bs` at `si` (with BSDF shading normal
/// `ns`) refracts into the surface; `None` for any other sample or material. The material is
/// resolved only for inward transmissions, so other bounces pay nothing.
pub(super) fn entered<'s>(si: &SurfaceInteraction<'s>, bs: &BsdfSample, ns: Vec3) -> Option<&'s SubsurfaceMaterial> {
    if !bs.is_transmission() || bs.wi.dot(ns) >= 0.0 {
        return None;
    }
    si.material().and_then(Material::subsurface)
}

/// The homogeneous interior of a subsurface object a random walk is in: the volumetric loop's
/// medium while the path is inside ([`crate::integrator::Integrator`]'s walk step).
#[derive(Clone, Copy, Debug)]
pub(super) struct Interior<'s> {
    /// The coefficients at the path's wavelengths, as at the entry point.
    pub medium: MediumPoint,
    /// The material, whose boundary BSDF every surface hit inside samples.
    pub material: &'s SubsurfaceMaterial,
    /// The scene medium outside, where the path goes on when it leaves.
    pub outside: Option<u32>,
    /// Real scatterings so far.
    pub scatterings: u32,
    /// Events (scatterings and boundary hits) so far.
    pub events: u32,
}

/// How a path that refracted at `si` into `material` goes on: its interior at the path's
/// wavelengths, and whether the path walks through it (`true`) or takes the diffusion BSSRDF.
/// Diffusion assumes an optically thick object; where the longest mean free path exceeds the
/// object's bounding radius, the medium is nearly clear, PBD would lose most of the light, and
/// a walk needs only a few events: `Diffusion` walks there too.
pub(super) fn interior(
    method: SubsurfaceMethod,
    scene: &Scene,
    material: &SubsurfaceMaterial,
    si: &SurfaceInteraction,
    w: &SampledWavelengths,
) -> (MediumPoint, bool) {
    let medium = material.medium(&si.shading_point(None), w);
    let walks = match method {
        SubsurfaceMethod::RandomWalk => true,
        SubsurfaceMethod::Diffusion => medium.sigma_t().min_value().recip() > si.material_radius(scene),
    };
    (medium, walks)
}

/// The diffusion BSSRDF: the throughput `beta` is multiplied by S_p(p_i) / pdf(p_i), and the
/// path goes on from the entry point p_i with its S_ω lobe. `None`: no entry point was found.
pub(super) fn diffusion<'s>(
    scene: &'s Scene,
    material: &SubsurfaceMaterial,
    medium: &MediumPoint,
    si: &SurfaceInteraction<'s>,
    beta: &mut SampledSpectrum,
    sampler: &mut Sampler,
    stats: &mut Stats,
) -> Option<(SurfaceInteraction<'s>, Bsdf)> {
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
    Some((pi, bsdf))
}

#[cfg(test)]
#[path = "subsurface_tests.rs"]
mod tests;

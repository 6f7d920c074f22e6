//! Coated diffuse: a dielectric coat (smooth or GGX-rough, IOR η) over a Lambertian base of
//! albedo ρ, with no absorption in the coat. Analytic model of Kelemen & Szirmay-Kalos 2001 /
//! Weidlich & Wilkie 2007 (Mitsuba's `plastic`/`roughplastic`):
//!
//! f = f_coat(ωo, ωi) + (1 − F(θi)) (1 − F(θo)) ρ / (π η² (1 − ρ F̄_int)),
//!
//! f_coat the microfacet (or mirror) reflection of the coat, F the smooth-interface Fresnel
//! reflectance, F̄_int = 1 − (1 − F̄_ext)/η² the cosine-averaged internal reflectance, and the
//! 1/(1 − ρ F̄_int) factor the geometric series of base ↔ coat interreflections.
//!
//! With a smooth coat this is exact (the Lambertian base re-randomises every internal bounce;
//! albedo F(θo) + (1 − F(θo)) ρ(1 − F̄_int)/(1 − ρF̄_int), = 1 for ρ = 1). With a rough coat the
//! transmission through it is approximated by the smooth Fresnel factors; its albedo error
//! against a random walk through the rough layer is measured in the tests (docs/bsdf.md).
//! Two-sided: directions below the surface are mirrored above.

use super::fresnel::{fr_dielectric, fr_dielectric_average};
use super::local::{abs_cos_theta, reflect, same_hemisphere};
use super::{BsdfSample, BxdfFlags, TransportMode, TrowbridgeReitz};
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;

/// Dielectric-coated Lambertian surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatedDiffuse {
    /// Albedo of the base.
    pub reflectance: SampledSpectrum,
    /// IOR of the coat relative to the outside.
    pub eta: f32,
    /// Roughness of the coat's outer interface.
    pub distrib: TrowbridgeReitz,
    /// ρ / (π η² (1 − ρ F̄_int)), precomputed per hit.
    diffuse_scale: SampledSpectrum,
    /// Average base weight used to choose between coat and base sampling.
    base_weight: f32,
}

impl CoatedDiffuse {
    /// Base albedo `reflectance`, coat IOR `eta` (invalid values become 1), coat roughness.
    pub fn new(reflectance: SampledSpectrum, eta: f32, distrib: TrowbridgeReitz) -> Self {
        let eta = if eta.is_finite() && eta > 0.0 { eta } else { 1.0 };
        let reflectance = reflectance.map(|r| r.clamp(0.0, 1.0));
        let f_int = 1.0 - (1.0 - fr_dielectric_average(eta)) / (eta * eta);
        let diffuse_scale = reflectance.map(|r| r * INV_PI / (eta * eta * (1.0 - r * f_int)));
        let base_weight = (diffuse_scale * (eta * eta * std::f32::consts::PI)).average();
        Self { reflectance, eta, distrib, diffuse_scale, base_weight }
    }

    fn is_smooth(&self) -> bool {
        self.distrib.effectively_smooth()
    }

    /// Probability of sampling the coat lobe rather than the base, for cos θo.
    fn coat_probability(&self, cos_o: f32) -> f32 {
        let fo = fr_dielectric(cos_o, self.eta);
        let base = (1.0 - fo) * self.base_weight;
        if fo + base > 0.0 {
            fo / (fo + base)
        } else {
            1.0
        }
    }

    /// Base term (1 − F(θi)) (1 − F(θo)) ρ / (π η² (1 − ρ F̄_int)); directions in +z.
    fn f_base(&self, cos_o: f32, cos_i: f32) -> SampledSpectrum {
        let t = (1.0 - fr_dielectric(cos_i, self.eta)) * (1.0 - fr_dielectric(cos_o, self.eta));
        self.diffuse_scale * t
    }

    /// Coat microfacet reflection, directions in +z.
    fn f_coat(&self, wo: Vec3, wi: Vec3) -> f32 {
        let wm = wo + wi;
        if self.is_smooth() || wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        let fr = fr_dielectric(wo.dot(wm), self.eta);
        self.distrib.d(wm) * self.distrib.g(wo, wi) * fr / (4.0 * wo.z * wi.z)
    }

    fn pdf_coat(&self, wo: Vec3, wi: Vec3) -> f32 {
        let wm = wo + wi;
        if self.is_smooth() || wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm).abs())
    }

    /// Both terms (the smooth coat's mirror is a delta and not included).
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) || wo.z == 0.0 {
            return SampledSpectrum::zero();
        }
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        self.f_base(wo.z, wi.z) + SampledSpectrum::splat(self.f_coat(wo, wi))
    }

    /// Chooses the coat with probability F(θo)/(F(θo) + (1 − F(θo)) ρ̄′), else the base.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo_up = if flip { -wo } else { wo };
        let pc = self.coat_probability(wo_up.z);
        let unflip = |w: Vec3| if flip { -w } else { w };
        if uc < pc {
            if self.is_smooth() {
                let wi = Vec3::new(-wo_up.x, -wo_up.y, wo_up.z);
                let f = fr_dielectric(wo_up.z, self.eta) / wo_up.z;
                return Some(BsdfSample::new(
                    SampledSpectrum::splat(f),
                    unflip(wi),
                    pc,
                    BxdfFlags::SPECULAR_REFLECTION,
                ));
            }
            let wm = self.distrib.sample_wm(wo_up, u);
            let wi = reflect(wo_up, wm);
            if wi.z <= 0.0 {
                return None;
            }
            let (wo_w, wi_w) = (unflip(wo_up), unflip(wi));
            let pdf = self.pdf(wo_w, wi_w, mode);
            if pdf.is_nan() || pdf <= 0.0 {
                return None;
            }
            return Some(BsdfSample::new(self.f(wo_w, wi_w, mode), wi_w, pdf, BxdfFlags::GLOSSY_REFLECTION));
        }
        let wi = sample_cosine_hemisphere(u);
        if wi.z <= 0.0 {
            return None;
        }
        let (wo_w, wi_w) = (unflip(wo_up), unflip(wi));
        let pdf = self.pdf(wo_w, wi_w, mode);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample::new(self.f(wo_w, wi_w, mode), wi_w, pdf, BxdfFlags::DIFFUSE_REFLECTION))
    }

    /// Mixture density of the non-delta lobes.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        if !same_hemisphere(wo, wi) || wo.z == 0.0 {
            return 0.0;
        }
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let pc = self.coat_probability(wo.z);
        pc * self.pdf_coat(wo, wi) + (1.0 - pc) * cosine_hemisphere_pdf(abs_cos_theta(wi))
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        let coat = if self.is_smooth() { BxdfFlags::SPECULAR_REFLECTION } else { BxdfFlags::GLOSSY_REFLECTION };
        coat | BxdfFlags::DIFFUSE_REFLECTION
    }
}

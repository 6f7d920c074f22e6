//! Dielectric interfaces (glass, water): Fresnel-weighted specular reflection and refraction
//! when smooth, the Walter et al. 2007 rough microfacet BSDF otherwise ("Microfacet Models for
//! Refraction through Rough Surfaces", eqs. 20–21; pbrt-v4 `DielectricBxDF`).
//!
//! Radiance is scaled by 1/η² on refraction in [`TransportMode::Radiance`] (radiance
//! compresses into the narrower cone of the denser medium, Veach 1997 §5.2).
//! `eta` is a single relative IOR for the hero wavelength: when η varies with λ the caller
//! terminates the secondary wavelengths (see [`super::ior`]).

use super::fresnel::fr_dielectric;
use super::local::{abs_cos_theta, cos_theta, face_forward, reflect, refract, same_hemisphere};
use super::{BsdfSample, BxdfFlags, Lobes, TransportMode, TrowbridgeReitz};
use crate::math::{Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// A dielectric boundary with relative IOR `eta` = η_inside/η_outside (inside: −z side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Relative IOR.
    pub eta: f32,
    /// Microfacet distribution of the boundary.
    pub distrib: TrowbridgeReitz,
}

impl Dielectric {
    /// An interface with relative IOR `eta` (non-positive or non-finite values become 1).
    pub fn new(eta: f32, distrib: TrowbridgeReitz) -> Self {
        let eta = if eta.is_finite() && eta > 0.0 { eta } else { 1.0 };
        Self { eta, distrib }
    }

    fn is_smooth(&self) -> bool {
        self.eta == 1.0 || self.distrib.effectively_smooth()
    }

    /// Generalized half vector ωm = normalize(η′ωi + ωo) facing +z, with η′ the relative IOR
    /// along the path, or `None` for degenerate or back-facing configurations.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32, bool)> {
        let (cos_o, cos_i) = (cos_theta(wo), cos_theta(wi));
        let is_reflect = cos_i * cos_o > 0.0;
        let etap = if is_reflect {
            1.0
        } else if cos_o > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let wm = wi * etap + wo;
        if cos_i == 0.0 || cos_o == 0.0 || wm.length_squared() == 0.0 {
            return None;
        }
        let wm = face_forward(wm.normalize(), Vec3::Z);
        // Microfacets seen from behind by either direction contribute nothing.
        if wm.dot(wi) * cos_i < 0.0 || wm.dot(wo) * cos_o < 0.0 {
            return None;
        }
        Some((wm, etap, is_reflect))
    }

    /// Rough BSDF value (0 when smooth: delta lobes have no finite density).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if self.is_smooth() {
            return SampledSpectrum::zero();
        }
        let Some((wm, etap, is_reflect)) = self.half_vector(wo, wi) else {
            return SampledSpectrum::zero();
        };
        let fr = fr_dielectric(wo.dot(wm), self.eta);
        let d = self.distrib.d(wm);
        let g = self.distrib.g(wo, wi);
        let (cos_o, cos_i) = (cos_theta(wo), cos_theta(wi));
        if is_reflect {
            return SampledSpectrum::splat(d * g * fr / (4.0 * cos_i * cos_o).abs());
        }
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2) * cos_i * cos_o;
        let mut ft = d * (1.0 - fr) * g * (wi.dot(wm) * wo.dot(wm) / denom).abs();
        if mode == TransportMode::Radiance {
            ft /= etap * etap;
        }
        SampledSpectrum::splat(ft)
    }

    /// Chooses reflection with probability F, refraction with 1 − F.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        self.sample_lobes(wo, uc, u, mode, Lobes::All)
    }

    /// [`Self::sample_f`] restricted to `lobes`: the excluded lobe's probability is 0 and the
    /// chosen one's pdf is relative to what remains (pbrt-v4 `BxDFReflTransFlags`).
    pub fn sample_lobes(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode, lobes: Lobes) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        if self.is_smooth() {
            let (r, t) = lobes.weights(fr_dielectric(cos_theta(wo), self.eta))?;
            if uc < r / (r + t) {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let f = SampledSpectrum::splat(r / abs_cos_theta(wi));
                return Some(BsdfSample::new(f, wi, r / (r + t), BxdfFlags::SPECULAR_REFLECTION));
            }
            let (wi, etap) = refract(wo, Vec3::Z, self.eta)?;
            let mut ft = t / abs_cos_theta(wi);
            if mode == TransportMode::Radiance {
                ft /= etap * etap;
            }
            let mut s = BsdfSample::new(SampledSpectrum::splat(ft), wi, t / (r + t), BxdfFlags::SPECULAR_TRANSMISSION);
            s.eta = etap;
            return Some(s);
        }
        let wm = self.distrib.sample_wm(wo, u);
        let (r, t) = lobes.weights(fr_dielectric(wo.dot(wm), self.eta))?;
        if uc < r / (r + t) {
            let wi = reflect(wo, wm);
            if !same_hemisphere(wo, wi) {
                return None;
            }
            let (d, lambda_o) = (self.distrib.d(wm), self.distrib.lambda(wo));
            let pdf = self.distrib.visible_pdf(wo, wm, d, lambda_o) / (4.0 * wo.dot(wm).abs()) * r / (r + t);
            let g = 1.0 / (1.0 + lambda_o + self.distrib.lambda(wi));
            let f = d * g * r / (4.0 * cos_theta(wi) * cos_theta(wo)).abs();
            if pdf.is_nan() || pdf <= 0.0 {
                return None;
            }
            return Some(BsdfSample::new(SampledSpectrum::splat(f), wi, pdf, BxdfFlags::GLOSSY_REFLECTION));
        }
        let (wi, etap) = refract(wo, wm, self.eta)?;
        if same_hemisphere(wo, wi) || wi.z == 0.0 {
            return None;
        }
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
        let dwm_dwi = wi.dot(wm).abs() / denom;
        let (d, lambda_o) = (self.distrib.d(wm), self.distrib.lambda(wo));
        let pdf = self.distrib.visible_pdf(wo, wm, d, lambda_o) * dwm_dwi * t / (r + t);
        let g = 1.0 / (1.0 + lambda_o + self.distrib.lambda(wi));
        let mut ft = t * d * g * (wi.dot(wm) * wo.dot(wm) / (cos_theta(wi) * cos_theta(wo) * denom)).abs();
        if mode == TransportMode::Radiance {
            ft /= etap * etap;
        }
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let mut s = BsdfSample::new(SampledSpectrum::splat(ft), wi, pdf, BxdfFlags::GLOSSY_TRANSMISSION);
        s.eta = etap;
        Some(s)
    }

    /// Density of [`Self::sample_f`]; refraction uses the Jacobian
    /// dωm/dωi = |ωi·ωm| / (ωi·ωm + ωo·ωm/η′)² (Walter et al. 2007 eq. 17).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        self.pdf_lobes(wo, wi, mode, Lobes::All)
    }

    /// Density of [`Self::sample_lobes`] with the same `lobes`.
    pub fn pdf_lobes(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, lobes: Lobes) -> f32 {
        if self.is_smooth() {
            return 0.0;
        }
        let Some((wm, etap, is_reflect)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let Some((r, t)) = lobes.weights(fr_dielectric(wo.dot(wm), self.eta)) else {
            return 0.0;
        };
        if is_reflect {
            self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm).abs()) * r / (r + t)
        } else {
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            let dwm_dwi = wi.dot(wm).abs() / denom;
            self.distrib.pdf(wo, wm) * dwm_dwi * t / (r + t)
        }
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        let kind = if self.is_smooth() { BxdfFlags::SPECULAR } else { BxdfFlags::GLOSSY };
        if self.eta == 1.0 {
            BxdfFlags::TRANSMISSION | kind
        } else {
            BxdfFlags::REFLECTION | BxdfFlags::TRANSMISSION | kind
        }
    }
}

//! Conductors: a Trowbridge–Reitz microfacet BRDF with the exact complex Fresnel term
//! (Cook & Torrance 1982; Walter et al. 2007), f = D(ωm) F(ωo·ωm) G(ωo, ωi) / (4 cos θo cos θi),
//! sampled with visible normals (pbrt-v4 `ConductorBxDF`); a perfect mirror when α → 0.

use super::fresnel::fr_complex_spectrum;
use super::local::{abs_cos_theta, face_forward, reflect, same_hemisphere};
use super::{BsdfSample, BxdfFlags, TransportMode, TrowbridgeReitz};
use crate::math::{Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// A metal with complex IOR η + ik at the four wavelengths (relative to the outside medium).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Microfacet distribution.
    pub distrib: TrowbridgeReitz,
    /// Real part of the IOR.
    pub eta: SampledSpectrum,
    /// Extinction coefficient.
    pub k: SampledSpectrum,
}

impl Conductor {
    /// A conductor with distribution `distrib` and complex IOR `eta` + i`k`.
    pub fn new(distrib: TrowbridgeReitz, eta: SampledSpectrum, k: SampledSpectrum) -> Self {
        Self { distrib, eta, k }
    }

    /// Microfacet BRDF; 0 for the smooth (delta) case.
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) || self.distrib.effectively_smooth() {
            return SampledSpectrum::zero();
        }
        let (cos_o, cos_i) = (abs_cos_theta(wo), abs_cos_theta(wi));
        if cos_i == 0.0 || cos_o == 0.0 {
            return SampledSpectrum::zero();
        }
        let wm = wi + wo;
        if wm.length_squared() == 0.0 {
            return SampledSpectrum::zero();
        }
        let wm = wm.normalize();
        let fr = fr_complex_spectrum(wo.dot(wm).abs(), self.eta, self.k);
        fr * (self.distrib.d(wm) * self.distrib.g(wo, wi) / (4.0 * cos_i * cos_o))
    }

    /// Mirror direction when smooth; otherwise a visible normal reflected about.
    pub fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if self.distrib.effectively_smooth() {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let cos_i = abs_cos_theta(wi);
            if cos_i == 0.0 {
                return None;
            }
            let f = fr_complex_spectrum(cos_i, self.eta, self.k) / cos_i;
            return Some(BsdfSample::new(f, wi, 1.0, BxdfFlags::SPECULAR_REFLECTION));
        }
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distrib.sample_wm(wo, u);
        let wi = reflect(wo, wm);
        if !same_hemisphere(wo, wi) {
            return None;
        }
        let (d, lambda_o) = (self.distrib.d(wm), self.distrib.lambda(wo));
        let pdf = self.distrib.visible_pdf(wo, wm, d, lambda_o) / (4.0 * wo.dot(wm).abs());
        let (cos_o, cos_i) = (abs_cos_theta(wo), abs_cos_theta(wi));
        if cos_i == 0.0 || cos_o == 0.0 || pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let fr = fr_complex_spectrum(wo.dot(wm).abs(), self.eta, self.k);
        let g = 1.0 / (1.0 + lambda_o + self.distrib.lambda(wi));
        let f = fr * (d * g / (4.0 * cos_i * cos_o));
        Some(BsdfSample::new(f, wi, pdf, BxdfFlags::GLOSSY_REFLECTION))
    }

    /// Density of [`Self::sample_f`]: D_ωo(ωm) / (4 |ωo·ωm|) (the reflection Jacobian).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        if !same_hemisphere(wo, wi) || self.distrib.effectively_smooth() {
            return 0.0;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = face_forward(wm.normalize(), Vec3::Z);
        let d = wo.dot(wm).abs();
        if d == 0.0 {
            return 0.0;
        }
        self.distrib.pdf(wo, wm) / (4.0 * d)
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        if self.distrib.effectively_smooth() {
            BxdfFlags::SPECULAR_REFLECTION
        } else {
            BxdfFlags::GLOSSY_REFLECTION
        }
    }
}

//! Lambertian reflection: f = ρ/π (Lambert 1760), sampled by the cosine-weighted hemisphere.

use super::local::{abs_cos_theta, same_hemisphere};
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;

/// Lambertian BRDF with reflectance `r` ∈ [0, 1] per wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    /// Hemispherical reflectance ρ (albedo).
    pub r: SampledSpectrum,
}

impl Diffuse {
    /// A Lambertian surface of albedo `r`.
    pub fn new(r: SampledSpectrum) -> Self {
        Self { r }
    }

    /// f(wo, wi) = ρ/π on the same side, 0 otherwise.
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) {
            return SampledSpectrum::zero();
        }
        self.r * INV_PI
    }

    /// Cosine-weighted sample on the side of `wo`.
    pub fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if self.r.is_black() {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi));
        Some(BsdfSample::new(self.r * INV_PI, wi, pdf, BxdfFlags::DIFFUSE_REFLECTION))
    }

    /// Density of [`Self::sample_f`].
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        if self.r.is_black() || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        cosine_hemisphere_pdf(abs_cos_theta(wi))
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        if self.r.is_black() {
            BxdfFlags::UNSET
        } else {
            BxdfFlags::DIFFUSE_REFLECTION
        }
    }
}

//! Diffuse reflection plus diffuse transmission: f = r/π on the side of wo, t/π on the other
//! (pbrt-v4 `DiffuseTransmissionBxDF`; thin translucent sheets such as paper or leaves).

use super::local::{abs_cos_theta, same_hemisphere};
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;

/// Lambertian reflection `r` and Lambertian transmission `t` (r + t ≤ 1 per wavelength).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmission {
    /// Hemispherical reflectance.
    pub r: SampledSpectrum,
    /// Hemispherical transmittance.
    pub t: SampledSpectrum,
}

impl DiffuseTransmission {
    /// Reflectance `r`, transmittance `t`.
    pub fn new(r: SampledSpectrum, t: SampledSpectrum) -> Self {
        Self { r, t }
    }

    /// Probability of sampling the reflection lobe: max ρ / (max ρ + max τ).
    fn reflect_probability(&self) -> Option<f32> {
        let (pr, pt) = (self.r.max_value().max(0.0), self.t.max_value().max(0.0));
        if pr + pt == 0.0 {
            None
        } else {
            Some(pr / (pr + pt))
        }
    }

    /// r/π or t/π by the side of `wi`.
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if same_hemisphere(wo, wi) {
            self.r * INV_PI
        } else {
            self.t * INV_PI
        }
    }

    /// Picks a lobe by `uc`, then a cosine-weighted direction on its side.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let pr = self.reflect_probability()?;
        let mut wi = sample_cosine_hemisphere(u);
        let reflect = uc < pr;
        // Reflection stays on the side of wo, transmission goes to the other.
        if (wo.z < 0.0) == reflect {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi));
        Some(if reflect {
            BsdfSample::new(self.r * INV_PI, wi, pdf * pr, BxdfFlags::DIFFUSE_REFLECTION)
        } else {
            BsdfSample::new(self.t * INV_PI, wi, pdf * (1.0 - pr), BxdfFlags::DIFFUSE_TRANSMISSION)
        })
    }

    /// Density of [`Self::sample_f`].
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        let Some(pr) = self.reflect_probability() else {
            return 0.0;
        };
        let p = cosine_hemisphere_pdf(abs_cos_theta(wi));
        if same_hemisphere(wo, wi) {
            pr * p
        } else if wo.z * wi.z < 0.0 {
            (1.0 - pr) * p
        } else {
            0.0
        }
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        let mut f = BxdfFlags::UNSET;
        if !self.r.is_black() {
            f = f | BxdfFlags::DIFFUSE_REFLECTION;
        }
        if !self.t.is_black() {
            f = f | BxdfFlags::DIFFUSE_TRANSMISSION;
        }
        f
    }
}

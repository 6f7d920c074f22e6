//! A thin dielectric slab (window pane, bubble): both interfaces smooth and parallel, so light
//! leaves undeviated; internal reflections summed as a geometric series:
//! R′ = R + T²R/(1 − R²), T′ = 1 − R′ (pbrt-v4 `ThinDielectricBxDF`).

use super::fresnel::fr_dielectric;
use super::local::abs_cos_theta;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Thin slab of relative IOR `eta`; purely specular.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric {
    /// Relative IOR of the slab material.
    pub eta: f32,
}

impl ThinDielectric {
    /// A slab of IOR `eta` (invalid values become 1).
    pub fn new(eta: f32) -> Self {
        Self { eta: if eta.is_finite() && eta > 0.0 { eta } else { 1.0 } }
    }

    /// Delta lobes only: 0.
    pub fn f(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    /// Mirror with probability R′, straight through otherwise.
    pub fn sample_f(&self, wo: Vec3, uc: f32, _u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let cos = abs_cos_theta(wo);
        if cos == 0.0 {
            return None;
        }
        let mut r = fr_dielectric(cos, self.eta);
        let mut t = 1.0 - r;
        if r < 1.0 {
            r += t * t * r / (1.0 - r * r);
            t = 1.0 - r;
        }
        if uc < r / (r + t) {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            Some(BsdfSample::new(SampledSpectrum::splat(r / cos), wi, r / (r + t), BxdfFlags::SPECULAR_REFLECTION))
        } else {
            Some(BsdfSample::new(SampledSpectrum::splat(t / cos), -wo, t / (r + t), BxdfFlags::SPECULAR_TRANSMISSION))
        }
    }

    /// Delta lobes only: 0.
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> f32 {
        0.0
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::SPECULAR_REFLECTION | BxdfFlags::TRANSMISSION
    }
}

//! The directional factor S_ω of a separable BSSRDF at the entry point p_i, as a BxDF:
//! f(ω_i) = (1 − F_r(cos θ_i, η)) / (c π) with c = 1 − 2 ∫₀¹ F_r(μ, η) μ dμ, so that
//! ∫ f cos θ dω = 1 (pbrt-v4 `NormalizedFresnelBxDF`). The 1/η² that the dielectric boundary
//! applied to radiance on the way in is undone here (η² in radiance mode), as pbrt does.

use super::fresnel::fr_dielectric;
use super::local::{abs_cos_theta, cos_theta, same_hemisphere};
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;

/// S_ω of a subsurface boundary of relative index `eta`, on the +z side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalizedFresnel {
    /// Relative IOR of the boundary (inside over outside).
    pub eta: f32,
    /// Normalisation c = 1 − 2 ∫ F_r μ dμ (see [`NormalizedFresnel::normalization`]).
    pub c: f32,
}

impl NormalizedFresnel {
    /// The lobe for `eta` with a precomputed normalisation `c`.
    pub fn new(eta: f32, c: f32) -> Self {
        Self { eta, c }
    }

    /// c(η) = 1 − 2 ∫₀¹ F_r(μ, η) μ dμ by 256-point midpoint quadrature (computed once per
    /// material; exact normalisation rather than a polynomial fit).
    pub fn normalization(eta: f32) -> f32 {
        let n = 256;
        let m1: f32 =
            (0..n).map(|i| (i as f32 + 0.5) / n as f32).map(|mu| fr_dielectric(mu, eta) * mu).sum::<f32>() / n as f32;
        1.0 - 2.0 * m1
    }

    /// f(ωo, ωi): ωo only selects the side (+z).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) || cos_theta(wi) <= 0.0 || self.c.is_nan() || self.c <= 0.0 {
            return SampledSpectrum::zero();
        }
        let mut f = (1.0 - fr_dielectric(cos_theta(wi), self.eta)) / self.c * INV_PI;
        if mode == TransportMode::Radiance {
            f *= self.eta * self.eta;
        }
        SampledSpectrum::splat(f)
    }

    /// Cosine-weighted sample on the +z side.
    pub fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = sample_cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi));
        Some(BsdfSample::new(self.f(wo, wi, mode), wi, pdf, BxdfFlags::DIFFUSE_REFLECTION))
    }

    /// Density of [`Self::sample_f`].
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        cosine_hemisphere_pdf(abs_cos_theta(wi))
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::DIFFUSE_REFLECTION
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn normalized_fresnel_integrates_to_one_in_importance_mode() {
        for eta in [1.0f32, 1.33, 1.5] {
            let b = NormalizedFresnel::new(eta, NormalizedFresnel::normalization(eta));
            let mut rng = Rng::new(3, 1);
            let n = 200_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let u = Vec2::new(rng.uniform(), rng.uniform());
                let bs = b.sample_f(Vec3::Z, 0.5, u, TransportMode::Importance).unwrap();
                let x = (bs.f[0] * bs.wi.z / bs.pdf) as f64;
                s += x;
                s2 += x * x;
            }
            let mean = s / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            // Midpoint quadrature of c is accurate to ~1e-5.
            assert!((mean - 1.0).abs() < 4.0 * se + 1e-4, "η={eta}: ∫f cos = {mean} ± {se}");
        }
    }
}

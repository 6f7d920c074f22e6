//! How a metal's complex index of refraction is given: measured η and k, or an artist's
//! normal-incidence reflectance r turned into the index that reflects it (pbrt-v4
//! `ConductorMaterial`): η = 1, k = 2√r / √(1 − r), for which F(0°) = ((η−1)² + k²)/((η+1)² + k²) = r.

use super::{SpectrumTexture, TextureEvalContext};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// Largest reflectance mapped to an index: r = 1 would need k = ∞.
const MAX_REFLECTANCE: f32 = 0.9999;

/// A conductor's complex index η + ik.
#[derive(Clone, Debug)]
pub enum ConductorIor {
    /// Measured spectra of η and k.
    EtaK {
        /// Real part.
        eta: Spectrum,
        /// Imaginary part (absorption).
        k: Spectrum,
    },
    /// Normal-incidence reflectance r ∈ [0, 1].
    Reflectance(SpectrumTexture),
}

impl ConductorIor {
    /// (η, k) at the path's wavelengths and the shading point `ctx`.
    pub fn eval(&self, ctx: &TextureEvalContext, w: &SampledWavelengths) -> (SampledSpectrum, SampledSpectrum) {
        match self {
            ConductorIor::EtaK { eta, k } => (eta.sample(w), k.sample(w)),
            ConductorIor::Reflectance(r) => {
                let r = r.eval(ctx, w).map(|r| if r.is_finite() { r.clamp(0.0, MAX_REFLECTANCE) } else { 0.0 });
                (SampledSpectrum::one(), r.map(|r| 2.0 * r.sqrt() / (1.0 - r).sqrt()))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::fr_complex;

    #[test]
    fn reflectance_is_what_the_metal_reflects_at_normal_incidence() {
        let w = SampledWavelengths::sample_uniform(0.3);
        for r in [0.0f32, 0.04, 0.35, 0.6, 0.95, 0.9999] {
            let ior = ConductorIor::Reflectance(SpectrumTexture::Constant(Spectrum::constant(r)));
            let (eta, k) = ior.eval(&TextureEvalContext::uv(glam::Vec2::ZERO), &w);
            for i in 0..4 {
                // The exact complex Fresnel reflectance at normal incidence gives back r.
                let f = fr_complex(1.0, eta[i], k[i]);
                assert!((f - r).abs() < 2e-4 * r.max(1e-2), "r = {r}: F(0°) = {f}");
            }
        }
        // Out-of-range requests stay finite: r ≥ 1 is clamped, r < 0 is black.
        for r in [1.0f32, 7.0, -0.5] {
            let ior = ConductorIor::Reflectance(SpectrumTexture::Constant(Spectrum::constant(r)));
            let (_, k) = ior.eval(&TextureEvalContext::uv(glam::Vec2::ZERO), &w);
            assert!(k.is_finite() && k.min_value() >= 0.0, "r = {r}: k = {k:?}");
        }
    }
}

//! The fluxes by which the light samplers choose lights, as pbrt-v4 defines them, so that a
//! light is chosen with pbrt-v4's probability. Both estimators are unbiased whatever the
//! probabilities, but a per-sample nonlinearity (the film's `maxcomponentvalue` clamp) sees the
//! distribution of the samples, not only their mean.
//!
//! - The power sampler (pbrt-v4 `PowerLightSampler`) weighs a light by the mean of Φ(λ)/p(λ)
//!   over the four wavelengths `SampledWavelengths::SampleVisible(0.5)`, Φ(λ) being the light's
//!   `Phi` (its spectral flux): [`visible_flux`] of its spectrum times its geometric factor.
//! - The BVH sampler weighs a light by the `phi` of its `LightBounds` (pbrt-v4 `Light::Bounds`):
//!   the `MaxValue` of its spectrum — every pbrt-v4 light keeps its spectrum as a
//!   `DenselySampledSpectrum`, whose `MaxValue` is the largest of its values at each whole nm of
//!   360–830 nm ([`Spectrum::max_value`] of prism's spectrum, tabulated the same way; so a
//!   blackbody's is its largest value inside that band, not the 1 of its Wien peak, and an RGB
//!   illuminant's the largest value of the product, not the product of the factors' maxima) —
//!   times the light's scale and: π A for an area light (for one side even when it emits from
//!   both: the importance counts both sides), whose image, if any, stands in for the spectrum by
//!   the mean of its texels' channels; 4π for point and spot lights (whatever the spot's cone:
//!   the importance accounts for it) and goniometric lights (times the image's mean); for a
//!   projection light the mean over its pixels of their largest channel (no solid angle).
//!
//! Units: prism normalises a light's spectrum S to unit luminance Y = ∫ S ȳ dλ / ∫ ȳ dλ where
//! pbrt-v4 divides it by ∫ S ȳ dλ, and an image's RGB (1, 1, 1) is its colour space's white of
//! unit Y where pbrt-v4's is the illuminant divided by ∫ ȳ·illuminant dλ = ∫ ȳ dλ: every flux
//! here is pbrt-v4's times the one constant ∫ ȳ dλ, and only ratios matter.

use crate::spectrum::{sample_visible_wavelength, visible_wavelength_pdf, Spectrum};

/// pbrt-v4's estimate of ∫ S(λ) dλ for choosing lights by power: the mean of S(λᵢ)/p(λᵢ) over
/// the wavelengths of `SampledWavelengths::SampleVisible(0.5)` (uᵢ = 0.5 + i/4, less 1 above 1:
/// 0.5, 0.75, 1, 0.25), S looked up at the nearest whole nm as in a `DenselySampledSpectrum`.
pub(crate) fn visible_flux(s: &Spectrum) -> f32 {
    let sum: f64 = (0..4)
        .map(|i| {
            let u = 0.5 + i as f32 / 4.0;
            let lambda = sample_visible_wavelength(if u > 1.0 { u - 1.0 } else { u });
            let pdf = visible_wavelength_pdf(lambda);
            if pdf > 0.0 {
                s.eval_f64(lambda.round() as f64) / pdf as f64
            } else {
                0.0
            }
        })
        .sum();
    (sum / 4.0) as f32
}

/// pbrt-v4's `MaxValue` of a light's spectrum: its largest value over 360–830 nm.
pub(crate) fn max_value(s: &Spectrum) -> f32 {
    (s.max_value().max(0.0) as f32).min(f32::MAX)
}

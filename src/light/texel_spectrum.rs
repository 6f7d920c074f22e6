//! One environment-map texel's radiance spectrum: its linear RGB upsampled once, at load, to
//! the shape of pbrt-v4's `RGBIlluminantSpectrum` (Jakob & Hanika 2019, "A Low-Dimensional
//! Function Space for Efficient Spectral Upsampling"): `s(λ) = scale · σ(c₀x² + c₁x + c₂)`, to be
//! multiplied by the colour space's white illuminant W(λ) (Y = 1). A lookup then evaluates one
//! sigmoid per wavelength and never runs the RGB→spectrum fit.

use crate::spectrum::{
    fit_albedo_fast, normalised_wavelengths, ColorSpace, SampledSpectrum, SampledWavelengths, ScaledSigmoid,
};
use rayon::prelude::*;
use std::collections::HashMap;

/// One texel's spectrum shape: `scale · σ(poly(x))`, x = (λ − 360 nm)/470 nm (times the white).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct TexelSpectrum(ScaledSigmoid);

impl TexelSpectrum {
    /// The unbounded form of `Spectrum::from_rgb` (m = max(rgb), 2m · σ(fit of rgb/2m)), with the
    /// coefficients from the colour space's table refined on the fitter's 5 nm product rule
    /// (`fit_albedo_fast`: a 2k × 1k map has two million texels, too many for the full fit; the
    /// table alone loses ~0.4 % of a sky's luminance).
    pub(super) fn from_rgb(rgb: [f32; 3], space: &ColorSpace) -> Self {
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        if !(m > 0.0 && m.is_finite()) {
            return Self::default();
        }
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            // σ(0) = ½, so a constant m is scale 2m with a zero polynomial.
            return Self(ScaledSigmoid { c: [0.0; 3], scale: 2.0 * m });
        }
        let scaled = rgb.map(|v| (v / (2.0 * m)) as f64);
        let poly = fit_albedo_fast(scaled, space);
        Self(ScaledSigmoid { c: poly.c.map(|c| c as f32), scale: 2.0 * m })
    }

    /// [`TexelSpectrum::from_rgb`] of every colour of `rgbs`, each distinct colour fitted once
    /// (images repeat colours: a slide or a sky's flat regions), in parallel.
    pub(super) fn from_rgbs(rgbs: &[[f32; 3]], space: &ColorSpace) -> Vec<Self> {
        // Build (or fetch) the lazily made table before going parallel: its construction runs
        // rayon jobs inside a OnceLock, and a worker stealing one of ours in the middle of it
        // would re-enter the OnceLock and deadlock.
        let _ = space.rgb_to_spectrum_table();
        let key = |rgb: &[f32; 3]| rgb.map(f32::to_bits);
        let mut distinct: Vec<[u32; 3]> = rgbs.iter().map(key).collect();
        distinct.sort_unstable();
        distinct.dedup();
        let fits: HashMap<[u32; 3], Self> =
            distinct.into_par_iter().map(|k| (k, Self::from_rgb(k.map(f32::from_bits), space))).collect();
        rgbs.iter().map(|rgb| fits[&key(rgb)]).collect()
    }

    #[inline]
    pub(super) fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum(self.0.sample(normalised_wavelengths(w.lambda)))
    }
}

//! One environment-map texel's radiance spectrum: its linear RGB upsampled once, at load, to
//! the shape of pbrt-v4's `RGBIlluminantSpectrum` (Jakob & Hanika 2019, "A Low-Dimensional
//! Function Space for Efficient Spectral Upsampling"): `s(λ) = scale · σ(c₀x² + c₁x + c₂)`, to be
//! multiplied by the colour space's white illuminant W(λ) (Y = 1). A lookup then evaluates one
//! sigmoid per wavelength and never runs the RGB→spectrum fit.

use crate::spectrum::{fit_albedo_fast, ColorSpace, SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};

/// One texel's spectrum shape: `scale · σ(poly(x))`, x = (λ − 360 nm)/470 nm (times the white).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct TexelSpectrum {
    c: [f32; 3],
    scale: f32,
}

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
            return Self { c: [0.0; 3], scale: 2.0 * m };
        }
        let scaled = rgb.map(|v| (v / (2.0 * m)) as f64);
        let poly = fit_albedo_fast(scaled, space);
        Self { c: poly.c.map(|c| c as f32), scale: 2.0 * m }
    }

    #[inline]
    pub(super) fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        if self.scale == 0.0 {
            return SampledSpectrum::zero();
        }
        let span = LAMBDA_MAX - LAMBDA_MIN;
        SampledSpectrum::new(w.lambda.map(|l| {
            let x = (l - LAMBDA_MIN) / span;
            let t = (self.c[0] * x + self.c[1]) * x + self.c[2];
            let s = if t.is_infinite() { (t > 0.0) as u8 as f32 } else { 0.5 + t / (2.0 * (1.0 + t * t).sqrt()) };
            self.scale * s
        }))
    }
}

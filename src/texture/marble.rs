//! Marble (pbrt-v4 §10.6.5): bands t = ½ + ½ sin(y + variation · fBm(p)) across the texture's
//! y axis, perturbed by fractal noise, coloured by a fixed spline of stone colours.

use super::context::TextureEvalContext;
use super::fractal::fbm;
use super::mapping::Mapping3D;
use crate::spectrum::{fit_albedo, ColorSpace, SampledSpectrum, SampledWavelengths, SigmoidPolynomial};
use std::sync::Arc;

/// The spline's control colours (pbrt-v4's), sRGB: greys with one dark blue-grey vein.
const COLORS: [[f32; 3]; 9] = [
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.5, 0.5, 0.5],
    [0.6, 0.59, 0.58],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.2, 0.2, 0.33],
    [0.58, 0.58, 0.6],
];

/// Cubic Bézier segments: segment i has control points COLORS[i..i + 4].
const SEGMENTS: usize = COLORS.len() - 3;

/// Brightness factor of the spline colours.
const GAIN: f32 = 1.5;

/// Samples of the spectrum per segment (both ends included).
const SAMPLES: usize = 65;

/// The colour of `segment` at its parameter `local` ∈ [0, 1], by de Casteljau's
/// construction, times [`GAIN`].
fn bezier(segment: usize, local: f32) -> [f32; 3] {
    let mut p: Vec<[f32; 3]> = COLORS[segment..segment + 4].to_vec();
    for n in (1..4).rev() {
        for i in 0..n {
            p[i] = std::array::from_fn(|c| p[i][c] + local * (p[i + 1][c] - p[i][c]));
        }
    }
    p[0].map(|v| GAIN * v)
}

/// The segment of `t` ∈ [0, 1], ⌊6t⌋ (the last one includes t = 1), and the parameter within
/// it. Segments meet with jumps, as in pbrt-v4.
fn segment_of(t: f32) -> (usize, f32) {
    let x = t.clamp(0.0, 1.0) * SEGMENTS as f32;
    let segment = (x.floor() as usize).min(SEGMENTS - 1);
    (segment, x - segment as f32)
}

/// The marble texture.
#[derive(Clone, Debug)]
pub struct Marble {
    mapping: Mapping3D,
    octaves: u32,
    omega: f32,
    scale: f32,
    variation: f32,
    /// The spline's spectra, [`SAMPLES`] per segment, fitted at construction.
    spectra: Arc<Vec<SigmoidPolynomial>>,
}

impl Marble {
    /// Marble with fBm of `octaves` octaves and roughness `omega`, texture space scaled by
    /// `scale`, the bands displaced by `variation` times the noise.
    pub fn new(mapping: Mapping3D, octaves: u32, omega: f32, scale: f32, variation: f32) -> Self {
        let space = ColorSpace::srgb();
        let spectra = (0..SEGMENTS)
            .flat_map(|s| (0..SAMPLES).map(move |i| (s, i as f32 / (SAMPLES - 1) as f32)))
            // Each segment is sampled on its own, so the jumps between segments stay sharp.
            .map(|(s, local)| fit_albedo(bezier(s, local).map(|v| v as f64), space).poly)
            .collect();
        Self { mapping, octaves, omega, scale, variation, spectra: Arc::new(spectra) }
    }

    /// The band parameter t ∈ [0, 1] at `ctx`.
    fn band(&self, ctx: &TextureEvalContext) -> f32 {
        let c = self.mapping.map(ctx);
        let p = self.scale * c.p;
        let noise = fbm(p, self.scale * c.dpdx, self.scale * c.dpdy, self.omega, self.octaves);
        0.5 + 0.5 * (p.y + self.variation * noise).sin()
    }

    /// The reflectance at `ctx`.
    pub fn eval(&self, ctx: &TextureEvalContext, w: &SampledWavelengths) -> SampledSpectrum {
        let (segment, local) = segment_of(self.band(ctx));
        let x = local * (SAMPLES - 1) as f32;
        let i = (x.floor() as usize).min(SAMPLES - 2);
        let f = x - i as f32;
        let at = |k: usize| {
            let p = &self.spectra[segment * SAMPLES + k];
            SampledSpectrum::new(std::array::from_fn(|j| p.eval_f64(w.lambda[j] as f64) as f32))
        };
        at(i) * (1.0 - f) + at(i + 1) * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{RgbKind, Spectrum};
    use glam::{Mat4, Vec2, Vec3};

    fn marble(scale: f32) -> Marble {
        Marble::new(Mapping3D { texture_from_world: Mat4::IDENTITY }, 8, 0.5, scale, 0.0)
    }

    fn at(y: f32) -> TextureEvalContext {
        TextureEvalContext::at(Vec3::new(0.3, y, 0.2), Vec3::Z, Vec2::ZERO)
    }

    #[test]
    fn the_spline_at_chosen_band_positions() {
        let w = SampledWavelengths { lambda: [420.0, 510.0, 580.0, 690.0], pdf: [1.0; 4] };
        let m = marble(2.0);
        // Without variation t = ½ + ½ sin(2y). y = 0: t = ½, the start of segment 3, whose
        // first control point is the grey 0.5: a flat 0.75.
        let s = m.eval(&at(0.0), &w);
        assert!((0..4).all(|k| (s[k] - 0.75).abs() < 2e-3), "{s:?}");
        // t = 1/12 is the middle of segment 0: Bernstein weights (1, 3, 3, 1)/8 on
        // (0.58, 0.58, 0.6) × 3 and 0.5: RGB = 1.5 (7 · 0.58 + 0.5, …, 7 · 0.6 + 0.5)/8.
        let y = (2.0 * (1.0 / 12.0) - 1.0f32).asin() / 2.0;
        let expect = [1.5 * (7.0 * 0.58 + 0.5) / 8.0, 1.5 * (7.0 * 0.58 + 0.5) / 8.0, 1.5 * (7.0 * 0.6 + 0.5) / 8.0];
        let want = Spectrum::from_rgb(expect, RgbKind::Albedo, ColorSpace::srgb()).sample(&w);
        let got = m.eval(&at(y), &w);
        for k in 0..4 {
            assert!((got[k] - want[k]).abs() < 2e-3, "{got:?} vs {want:?}");
        }
    }

    #[test]
    fn de_casteljau_matches_the_bernstein_form() {
        for &t in &[0.03f32, 0.2, 0.45, 0.61, 0.9, 0.999] {
            let (s, u) = segment_of(t);
            let b = [(1.0 - u).powi(3), 3.0 * u * (1.0 - u).powi(2), 3.0 * u * u * (1.0 - u), u.powi(3)];
            let c = bezier(s, u);
            for ch in 0..3 {
                let want: f32 = (0..4).map(|i| b[i] * COLORS[s + i][ch]).sum::<f32>() * GAIN;
                assert!((c[ch] - want).abs() < 1e-5, "t = {t}");
            }
        }
    }
}

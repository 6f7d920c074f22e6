//! An area light's emission image (pbrt-v4 `DiffuseAreaLight` with "filename"): the radiance at
//! a surface point is the image at the point's (u, v), row 0 at v = 1, bilinear between texel
//! centres with the border clamped, each texel's linear RGB an illuminant spectrum of the colour
//! space (PBR 4th ed. §12.5.1). The texels' spectra are fitted once, at load, and a lookup blends
//! the four nearest; pbrt-v4 blends their RGB and fits the blend, which has the same luminance
//! (both are linear in the texels) and differs only in the spectral shape between texels.

use super::texel_spectrum::TexelSpectrum;
use crate::image::Image;
use crate::spectrum::{ColorSpace, SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// The texels of an emission image as spectra, with their mean luminance.
#[derive(Debug)]
pub struct EmissionImage {
    width: usize,
    height: usize,
    texels: Vec<TexelSpectrum>,
    /// The colour space's white illuminant the texels' shapes multiply.
    white: Arc<Spectrum>,
    /// Mean over texels of the luminance Y of their RGB (pbrt-v4's k_e factor for `power`).
    mean_luminance: f32,
    /// Mean over texels and their three channels (pbrt-v4's `DiffuseAreaLight::Bounds` flux).
    mean_channel: f32,
}

/// An emitting triangle's image and the (u, v) of its corners.
#[derive(Clone, Debug)]
pub struct ImageEmission {
    /// The image, shared by the mesh's triangles.
    pub image: Arc<EmissionImage>,
    /// (u, v) of the triangle's corners, in the order of its vertices.
    pub uv: [Vec2; 3],
}

impl EmissionImage {
    /// The image's first three channels (a grey image's one channel repeated) as linear RGB of
    /// `space`; negative and non-finite values emit nothing.
    pub fn new(image: &Image, space: &'static ColorSpace) -> Self {
        let (width, height) = (image.width.max(1) as usize, image.height.max(1) as usize);
        let c = image.channels.max(1) as usize;
        let mut rgbs = Vec::with_capacity(width * height);
        let (mut sum, mut channels) = (0.0f64, 0.0f64);
        for p in image.data.chunks_exact(c) {
            let px = |k: usize| p.get(k.min(c - 1)).copied().filter(|v| v.is_finite()).unwrap_or(0.0).max(0.0);
            let rgb = [px(0), px(1), px(2)];
            rgbs.push(rgb);
            sum += f64::from(space.rgb_to_xyz(Vec3::from_array(rgb)).y);
            channels += rgb.iter().map(|&v| f64::from(v)).sum::<f64>() / 3.0;
        }
        let mut texels = TexelSpectrum::from_rgbs(&rgbs, space);
        texels.resize(width * height, TexelSpectrum::default());
        let mean_luminance = (sum / (width * height) as f64) as f32;
        let mean_channel = (channels / (width * height) as f64) as f32;
        Self { width, height, texels, white: Arc::new(space.illuminant.clone()), mean_luminance, mean_channel }
    }

    /// Mean luminance of the texels (unitless; 1 for a white image).
    pub fn mean_luminance(&self) -> f32 {
        self.mean_luminance
    }

    /// Mean of the texels' R, G and B (unitless; 1 for a white image).
    pub fn mean_channel(&self) -> f32 {
        self.mean_channel
    }

    /// The image's spectrum at `uv` before the light's scale.
    pub fn radiance(&self, uv: Vec2, w: &SampledWavelengths) -> SampledSpectrum {
        // Texel centres at ((i + ½)/width, (j + ½)/height) with j counted from the top (v = 1).
        let x = uv.x * self.width as f32 - 0.5;
        let y = (1.0 - uv.y) * self.height as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return SampledSpectrum::zero();
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let clamp = |i: f32, n: usize| (i.max(0.0) as usize).min(n - 1);
        let (xa, xb) = (clamp(x0, self.width), clamp(x0 + 1.0, self.width));
        let (ya, yb) = (clamp(y0, self.height), clamp(y0 + 1.0, self.height));
        let t = |x: usize, y: usize| self.texels[y * self.width + x].sample(w);
        let s = t(xa, ya) * ((1.0 - fx) * (1.0 - fy))
            + t(xb, ya) * (fx * (1.0 - fy))
            + t(xa, yb) * ((1.0 - fx) * fy)
            + t(xb, yb) * (fx * fy);
        s * self.white.sample(w)
    }
}

impl ImageEmission {
    /// The image's spectrum at barycentric coordinates `b` of the triangle.
    #[inline]
    pub fn radiance_at(&self, b: [f32; 3], w: &SampledWavelengths) -> SampledSpectrum {
        self.image.radiance(self.uv[0] * b[0] + self.uv[1] * b[1] + self.uv[2] * b[2], w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn luminance(s: SampledSpectrum, w: &SampledWavelengths) -> f32 {
        s.y(w)
    }

    #[test]
    fn texels_are_read_from_the_top_row_at_v_one_and_blend_between_centres() {
        // 1 × 2 image: the top row white (1), the bottom row black.
        let image = Image { width: 1, height: 2, channels: 3, data: vec![1.0, 1.0, 1.0, 0.0, 0.0, 0.0] };
        let e = EmissionImage::new(&image, ColorSpace::srgb());
        assert!((e.mean_luminance() - 0.5).abs() < 1e-5);
        let w = SampledWavelengths::sample_visible(0.3);
        let white = luminance(e.radiance(Vec2::new(0.5, 0.9), &w), &w);
        assert!(white > 0.0);
        // The top texel's centre is v = 0.75: above it (clamped) the same value, the bottom
        // texel's centre v = 0.25 black, and halfway between them half.
        assert!((luminance(e.radiance(Vec2::new(0.5, 0.75), &w), &w) - white).abs() < 1e-5 * white);
        assert_eq!(luminance(e.radiance(Vec2::new(0.5, 0.1), &w), &w), 0.0);
        let mid = luminance(e.radiance(Vec2::new(0.2, 0.5), &w), &w);
        assert!((mid - 0.5 * white).abs() < 1e-5 * white, "{mid} vs {white}");
    }
}

//! Textures for material parameters: constant, checkerboard and image lookups by (u, v).

use crate::image::Image;
use crate::spectrum::{fit_albedo, ColorSpace, SampledSpectrum, SampledWavelengths, SigmoidPolynomial, Spectrum};
use glam::Vec2;
use rayon::prelude::*;
use std::sync::Arc;

/// An image used as a texture: linear RGB, bilinear lookup, repeat wrapping, v up (pbrt).
#[derive(Clone, Debug)]
pub struct ImageTexture {
    /// The pixels (linear).
    pub image: Arc<Image>,
    /// Multiplier.
    pub scale: f32,
}

impl ImageTexture {
    /// The four texels around (u, v) and their bilinear weights, with repeat wrapping and v up.
    fn footprint(&self, uv: Vec2) -> Option<[(usize, f32); 4]> {
        let img = &*self.image;
        let (w, h) = (img.width as i64, img.height as i64);
        if w == 0 || h == 0 {
            return None;
        }
        let x = uv.x * w as f32 - 0.5;
        let y = (1.0 - uv.y) * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let texel = |dx: i64, dy: i64| ((y0 + dy).rem_euclid(h) * w + (x0 + dx).rem_euclid(w)) as usize;
        Some([
            (texel(0, 0), (1.0 - fx) * (1.0 - fy)),
            (texel(1, 0), fx * (1.0 - fy)),
            (texel(0, 1), (1.0 - fx) * fy),
            (texel(1, 1), fx * fy),
        ])
    }

    /// RGB of texel `i` (grey images repeat their one channel), times `scale`.
    fn texel_rgb(&self, i: usize) -> [f32; 3] {
        let c = self.image.channels as usize;
        let px = &self.image.data[i * c..i * c + c];
        let rgb = if c >= 3 { [px[0], px[1], px[2]] } else { [px[0]; 3] };
        rgb.map(|v| v * self.scale)
    }

    /// Bilinear RGB at (u, v) with repeat wrapping.
    pub fn rgb(&self, uv: Vec2) -> [f32; 3] {
        let mut out = [0.0; 3];
        for (i, wgt) in self.footprint(uv).into_iter().flatten() {
            let t = self.texel_rgb(i);
            for k in 0..3 {
                out[k] += wgt * t[k];
            }
        }
        out
    }
}

/// An RGB image used as a reflectance: each texel's RGB (clamped to [0, 1]) is fitted once, at
/// load, by Jakob–Hanika (table start + Newton, the same accuracy as `Spectrum::from_rgb`), and
/// a lookup blends the four texels' spectra bilinearly. A blend of spectra projects to the same
/// blend of their RGB, so this is RGB-bilinear filtering without a fit per shading point.
#[derive(Clone, Debug)]
pub struct ReflectanceImage {
    texture: ImageTexture,
    /// One sigmoid polynomial per texel, row-major like the image.
    texels: Arc<Vec<SigmoidPolynomial>>,
}

impl ReflectanceImage {
    /// Fits every texel of `texture` in the sRGB space (in parallel).
    pub fn new(texture: ImageTexture) -> Self {
        let n = texture.image.width as usize * texture.image.height as usize;
        let space = ColorSpace::srgb();
        let texels =
            (0..n).into_par_iter().map(|i| fit_albedo(texture.texel_rgb(i).map(|v| v as f64), space).poly).collect();
        Self { texture, texels: Arc::new(texels) }
    }

    /// The reflectance at (u, v) for the path's wavelengths.
    pub fn eval(&self, uv: Vec2, w: &SampledWavelengths) -> SampledSpectrum {
        let mut out = SampledSpectrum::splat(0.0);
        for (i, wgt) in self.texture.footprint(uv).into_iter().flatten() {
            let poly = &self.texels[i];
            out += SampledSpectrum::new(std::array::from_fn(|k| poly.eval_f64(w.lambda[k] as f64) as f32)) * wgt;
        }
        out
    }
}

/// A spectrally varying texture (reflectance, transmittance).
#[derive(Clone, Debug)]
pub enum SpectrumTexture {
    /// The same spectrum everywhere.
    Constant(Spectrum),
    /// Alternating `even`/`odd` squares of size 1/`scale` in (u, v).
    Checkerboard {
        /// Value on squares where ⌊u s⌋ + ⌊v s⌋ is even.
        even: Box<SpectrumTexture>,
        /// Value on the others.
        odd: Box<SpectrumTexture>,
        /// Squares per unit of (u, v).
        scale: Vec2,
    },
    /// An RGB image as bounded reflectance spectra (Jakob–Hanika, fitted per texel at load).
    Image(ReflectanceImage),
}

impl SpectrumTexture {
    /// Value at texture coordinates `uv` and the path's wavelengths.
    pub fn eval(&self, uv: Vec2, w: &SampledWavelengths) -> SampledSpectrum {
        match self {
            SpectrumTexture::Constant(s) => s.sample(w),
            SpectrumTexture::Checkerboard { even, odd, scale } => {
                if checker_parity(uv, *scale) {
                    even.eval(uv, w)
                } else {
                    odd.eval(uv, w)
                }
            }
            SpectrumTexture::Image(t) => t.eval(uv, w),
        }
    }
}

/// A scalar texture (roughness, …).
#[derive(Clone, Debug)]
pub enum FloatTexture {
    /// The same value everywhere.
    Constant(f32),
    /// Alternating values.
    Checkerboard {
        /// Value on even squares.
        even: f32,
        /// Value on odd squares.
        odd: f32,
        /// Squares per unit of (u, v).
        scale: Vec2,
    },
    /// First channel of an image.
    Image(ImageTexture),
}

impl FloatTexture {
    /// Value at `uv`.
    pub fn eval(&self, uv: Vec2) -> f32 {
        match self {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Checkerboard { even, odd, scale } => {
                if checker_parity(uv, *scale) {
                    *even
                } else {
                    *odd
                }
            }
            FloatTexture::Image(t) => t.rgb(uv)[0],
        }
    }
}

fn checker_parity(uv: Vec2, scale: Vec2) -> bool {
    let s = (uv * scale).floor();
    (s.x as i64 + s.y as i64) & 1 == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tex() -> ImageTexture {
        // 2×2 RGB: red, green (top row), blue, white (bottom row).
        let data = vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        ImageTexture { image: Arc::new(Image { width: 2, height: 2, channels: 3, data }), scale: 1.0 }
    }

    #[test]
    fn image_lookup_is_bilinear_with_v_up_and_repeat() {
        let t = tex();
        // Texel centres: (u, v) = (0.25, 0.75) is the top-left texel (v points up).
        assert_eq!(t.rgb(Vec2::new(0.25, 0.75)), [1.0, 0.0, 0.0]);
        assert_eq!(t.rgb(Vec2::new(0.75, 0.25)), [1.0, 1.0, 1.0]);
        // Halfway between the two top texels: the average.
        let m = t.rgb(Vec2::new(0.5, 0.75));
        assert!((m[0] - 0.5).abs() < 1e-6 && (m[1] - 0.5).abs() < 1e-6 && m[2].abs() < 1e-6);
        // Repeat wrapping: u + 1 is the same place.
        assert_eq!(t.rgb(Vec2::new(1.25, 0.75)), t.rgb(Vec2::new(0.25, 0.75)));
    }

    #[test]
    fn image_texture_gives_the_texel_reflectance_spectrum() {
        let t = SpectrumTexture::Image(ReflectanceImage::new(tex()));
        let w = SampledWavelengths::sample_uniform(0.3);
        let white = t.eval(Vec2::new(0.75, 0.25), &w);
        for i in 0..4 {
            assert!((white[i] - 1.0).abs() < 1e-3, "white texel is not a flat 1: {white:?}");
        }
        // A red texel reflects long wavelengths more than short ones.
        let red =
            t.eval(Vec2::new(0.25, 0.75), &SampledWavelengths { lambda: [450.0, 650.0, 500.0, 600.0], pdf: [1.0; 4] });
        assert!(red[1] > 0.8 && red[0] < 0.2, "{red:?}");
    }

    #[test]
    fn reflectance_image_matches_per_texel_fits_and_blends_them() {
        let t = ReflectanceImage::new(tex());
        let w = SampledWavelengths { lambda: [420.0, 510.0, 580.0, 690.0], pdf: [1.0; 4] };
        let fit =
            |rgb: [f32; 3]| Spectrum::from_rgb(rgb, crate::spectrum::RgbKind::Albedo, ColorSpace::srgb()).sample(&w);
        let (red, green) = (fit([1.0, 0.0, 0.0]), fit([0.0, 1.0, 0.0]));
        let at_red = t.eval(Vec2::new(0.25, 0.75), &w);
        let halfway = t.eval(Vec2::new(0.5, 0.75), &w);
        for k in 0..4 {
            assert!((at_red[k] - red[k]).abs() < 1e-5, "{at_red:?} vs {red:?}");
            assert!((halfway[k] - 0.5 * (red[k] + green[k])).abs() < 1e-5, "{halfway:?}");
        }
    }

    #[test]
    fn checkerboard_alternates() {
        let c = FloatTexture::Checkerboard { even: 1.0, odd: 0.0, scale: Vec2::splat(2.0) };
        assert_eq!(c.eval(Vec2::new(0.1, 0.1)), 1.0);
        assert_eq!(c.eval(Vec2::new(0.6, 0.1)), 0.0);
        assert_eq!(c.eval(Vec2::new(0.6, 0.6)), 1.0);
    }
}

//! Textures for material parameters: constant, checkerboard and image lookups by (u, v).

use crate::image::Image;
use crate::spectrum::{ColorSpace, RgbKind, SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec2;
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
    /// Bilinear RGB at (u, v) with repeat wrapping.
    pub fn rgb(&self, uv: Vec2) -> [f32; 3] {
        let img = &*self.image;
        let (w, h) = (img.width as i64, img.height as i64);
        if w == 0 || h == 0 {
            return [0.0; 3];
        }
        let x = uv.x * w as f32 - 0.5;
        let y = (1.0 - uv.y) * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |xi: i64, yi: i64| -> [f32; 3] {
            let xi = xi.rem_euclid(w) as usize;
            let yi = yi.rem_euclid(h) as usize;
            let c = img.channels as usize;
            let o = (yi * w as usize + xi) * c;
            let px = &img.data[o..o + c];
            if c >= 3 {
                [px[0], px[1], px[2]]
            } else {
                [px[0]; 3]
            }
        };
        let (x0, y0) = (x0 as i64, y0 as i64);
        let mut out = [0.0; 3];
        for (dx, dy, wgt) in
            [(0, 0, (1.0 - fx) * (1.0 - fy)), (1, 0, fx * (1.0 - fy)), (0, 1, (1.0 - fx) * fy), (1, 1, fx * fy)]
        {
            let t = texel(x0 + dx, y0 + dy);
            for i in 0..3 {
                out[i] += wgt * t[i] * self.scale;
            }
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
    /// An RGB image upsampled per lookup to a bounded reflectance spectrum (Jakob–Hanika).
    Image(ImageTexture),
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
            SpectrumTexture::Image(t) => {
                let rgb = t.rgb(uv).map(|c| c.clamp(0.0, 1.0));
                Spectrum::from_rgb(rgb, RgbKind::Albedo, ColorSpace::srgb()).sample(w)
            }
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
        let t = SpectrumTexture::Image(tex());
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
    fn checkerboard_alternates() {
        let c = FloatTexture::Checkerboard { even: 1.0, odd: 0.0, scale: Vec2::splat(2.0) };
        assert_eq!(c.eval(Vec2::new(0.1, 0.1)), 1.0);
        assert_eq!(c.eval(Vec2::new(0.6, 0.1)), 0.0);
        assert_eq!(c.eval(Vec2::new(0.6, 0.6)), 1.0);
    }
}

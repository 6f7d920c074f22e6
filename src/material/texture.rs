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

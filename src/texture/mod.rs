//! Textures: values of material parameters that vary over surfaces (pbrt-v4 chapter 10), as
//! floats (roughness, amounts, …) or spectra (reflectances). Every pbrt-v4 texture type is a
//! variant of [`Texture`]: constants, patterns evaluated through a [`mapping`] of the shading
//! point (bilerp, checkerboard, dots, fractal noise, marble, images), and combinations of
//! other textures (mix, directionmix, scale). Image and pattern lookups are filtered over the
//! footprint of a pixel at the shading point (its [`TextureEvalContext`] derivatives,
//! estimated by [`footprint`]), so distant textures do not alias.

mod checkerboard;
mod context;
mod dots;
mod encoding;
mod float;
pub mod footprint;
mod fractal;
mod image;
pub mod mapping;
mod marble;
pub mod mipmap;
pub mod noise;
mod spectrum;
mod wrap;

pub use checkerboard::Checkerboard;
pub use context::TextureEvalContext;
pub use dots::inside_polka_dot;
pub use encoding::ColorEncoding;
pub use float::FloatSource;
pub use footprint::{Footprint, RayDifferentials, TextureFootprint};
pub use fractal::{fbm, turbulence, windy};
pub use image::{rgb_texels, FloatImage, SpectrumImage};
pub use mapping::{Mapping2D, Mapping3D};
pub use marble::Marble;
pub use mipmap::{FilterFunction, MipMap, MipOptions};
pub use spectrum::SpectrumSource;
pub use wrap::WrapMode;

use crate::spectrum::{SampledSpectrum, Spectrum};
use glam::Vec3;
use std::fmt::Debug;
use std::ops::{Add, Mul};
use std::sync::Arc;

/// A texture value at one shading point that filters and blends linearly: `f32`, or a
/// spectrum at the path's wavelengths.
pub trait Sample: Copy + Add<Output = Self> + Mul<f32, Output = Self> {
    /// The additive identity.
    fn zero() -> Self;
}

impl Sample for f32 {
    fn zero() -> Self {
        0.0
    }
}

impl Sample for SampledSpectrum {
    fn zero() -> Self {
        SampledSpectrum::zero()
    }
}

impl Sample for Vec3 {
    fn zero() -> Self {
        Vec3::ZERO
    }
}

/// What a texture yields: floats (`f32`) or spectra ([`Spectrum`]).
pub trait TextureValue: Clone + Debug + Send + Sync + 'static {
    /// The value at a shading point: `f32`, or a [`SampledSpectrum`].
    type Sampled: Sample;
    /// What a value depends on besides the point: nothing for floats, the path's wavelengths
    /// for spectra.
    type Lambda: ?Sized;
    /// Texture types only this kind has (images and noise patterns).
    type Source: Clone + Debug + Send + Sync;
    /// A constant at `lambda`.
    fn at(&self, lambda: &Self::Lambda) -> Self::Sampled;
    /// A source texture at `ctx` and `lambda`.
    fn source(source: &Self::Source, ctx: &TextureEvalContext, lambda: &Self::Lambda) -> Self::Sampled;
}

/// A texture of floats or of spectra.
#[derive(Clone, Debug)]
pub enum Texture<V: TextureValue> {
    /// "constant": the same value everywhere.
    Constant(V),
    /// "bilerp": bilinear interpolation of four corner values over (s, t) ∈ [0, 1]².
    Bilerp {
        /// The mapping to (s, t).
        mapping: Mapping2D,
        /// Values at (s, t) = (0, 0), (1, 0), (0, 1), (1, 1) ("v00", "v10", "v01", "v11").
        corners: Box<[V; 4]>,
    },
    /// "checkerboard": the first texture on even checks, the second on odd ones, blended
    /// where the footprint covers both.
    Checkerboard {
        /// The layout of the checks.
        pattern: Checkerboard,
        /// The two textures ("tex1", "tex2").
        tex: [Arc<Texture<V>>; 2],
    },
    /// "dots": polka dots in (s, t).
    Dots {
        /// The mapping to (s, t).
        mapping: Mapping2D,
        /// The texture inside the dots.
        dots: Arc<Texture<V>>,
        /// The texture around them.
        background: Arc<Texture<V>>,
    },
    /// "mix": (1 − a)·tex1 + a·tex2 for the float texture a.
    Mix {
        /// tex1, tex2.
        tex: [Arc<Texture<V>>; 2],
        /// a ("amount").
        amount: Arc<FloatTexture>,
    },
    /// "directionmix": a·tex1 + (1 − a)·tex2 with a = |n · dir|.
    DirectionMix {
        /// tex1, tex2.
        tex: [Arc<Texture<V>>; 2],
        /// Unit direction [world space].
        dir: Vec3,
    },
    /// "scale": tex · scale.
    Scale {
        /// The texture scaled.
        tex: Arc<Texture<V>>,
        /// The float factor.
        scale: Arc<FloatTexture>,
    },
    /// Images and the patterns only this kind has.
    Source(V::Source),
}

/// A texture of floats.
pub type FloatTexture = Texture<f32>;

/// A texture of spectra.
pub type SpectrumTexture = Texture<Spectrum>;

impl<V: TextureValue> Texture<V> {
    /// The value at `ctx` (and wavelengths `lambda`).
    pub fn evaluate(&self, ctx: &TextureEvalContext, lambda: &V::Lambda) -> V::Sampled {
        match self {
            Texture::Constant(v) => v.at(lambda),
            Texture::Bilerp { mapping, corners } => {
                let st = mapping.map(ctx).st;
                let [v00, v10, v01, v11] = &**corners;
                v00.at(lambda) * ((1.0 - st.x) * (1.0 - st.y))
                    + v10.at(lambda) * (st.x * (1.0 - st.y))
                    + v01.at(lambda) * ((1.0 - st.x) * st.y)
                    + v11.at(lambda) * (st.x * st.y)
            }
            Texture::Checkerboard { pattern, tex } => blend(tex, pattern.weight(ctx), ctx, lambda),
            Texture::Dots { mapping, dots, background } => {
                if inside_polka_dot(mapping.map(ctx).st) {
                    dots.evaluate(ctx, lambda)
                } else {
                    background.evaluate(ctx, lambda)
                }
            }
            Texture::Mix { tex, amount } => blend(tex, amount.eval(ctx), ctx, lambda),
            Texture::DirectionMix { tex, dir } => blend(tex, 1.0 - ctx.n.dot(*dir).abs(), ctx, lambda),
            Texture::Scale { tex, scale } => {
                let s = scale.eval(ctx);
                if s == 0.0 {
                    V::Sampled::zero()
                } else {
                    tex.evaluate(ctx, lambda) * s
                }
            }
            Texture::Source(s) => V::source(s, ctx, lambda),
        }
    }

    /// True unless the texture is a constant: its value then depends on the point and the
    /// footprint it is evaluated at.
    pub fn varies(&self) -> bool {
        !matches!(self, Texture::Constant(_))
    }
}

/// (1 − w)·tex[0] + w·tex[1], evaluating only the textures with nonzero weight.
fn blend<V: TextureValue>(
    tex: &[Arc<Texture<V>>; 2],
    w: f32,
    ctx: &TextureEvalContext,
    lambda: &V::Lambda,
) -> V::Sampled {
    let first = if w != 1.0 { tex[0].evaluate(ctx, lambda) * (1.0 - w) } else { V::Sampled::zero() };
    let second = if w != 0.0 { tex[1].evaluate(ctx, lambda) * w } else { V::Sampled::zero() };
    first + second
}

impl FloatTexture {
    /// The value at `ctx` (a constant without the call into the general evaluation).
    #[inline]
    pub fn eval(&self, ctx: &TextureEvalContext) -> f32 {
        match self {
            Texture::Constant(v) => *v,
            t => t.evaluate(ctx, &()),
        }
    }
}

impl SpectrumTexture {
    /// The value at `ctx` for the path's wavelengths `w`.
    /// A constant is sampled without the call into the general evaluation.
    #[inline]
    pub fn eval(&self, ctx: &TextureEvalContext, w: &crate::spectrum::SampledWavelengths) -> SampledSpectrum {
        match self {
            Texture::Constant(s) => s.sample(w),
            t => t.evaluate(ctx, w),
        }
    }
}

#[cfg(test)]
mod tests;

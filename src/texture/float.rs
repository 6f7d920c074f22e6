//! Float textures: the [`TextureValue`] of `f32`, and the float-only texture types.

use super::context::TextureEvalContext;
use super::fractal::{fbm, turbulence, windy};
use super::image::FloatImage;
use super::mapping::Mapping3D;
use super::TextureValue;

/// Float-only textures.
#[derive(Clone, Debug)]
pub enum FloatSource {
    /// "fbm": fractional Brownian motion.
    Fbm {
        /// Texture space.
        mapping: Mapping3D,
        /// Amplitude ratio ω of successive octaves ("roughness").
        omega: f32,
        /// Most octaves ("octaves").
        octaves: u32,
    },
    /// "wrinkled": turbulence, Σ ωⁱ |noise|.
    Wrinkled {
        /// Texture space.
        mapping: Mapping3D,
        /// Amplitude ratio ω ("roughness").
        omega: f32,
        /// Most octaves ("octaves").
        octaves: u32,
    },
    /// "windy": waves scaled by wind strength.
    Windy {
        /// Texture space.
        mapping: Mapping3D,
    },
    /// "imagemap".
    Image(FloatImage),
}

impl TextureValue for f32 {
    type Sampled = f32;
    type Lambda = ();
    type Source = FloatSource;

    fn at(&self, _: &()) -> f32 {
        *self
    }

    fn source(source: &FloatSource, ctx: &TextureEvalContext, _: &()) -> f32 {
        match source {
            FloatSource::Fbm { mapping, omega, octaves } => {
                let c = mapping.map(ctx);
                fbm(c.p, c.dpdx, c.dpdy, *omega, *octaves)
            }
            FloatSource::Wrinkled { mapping, omega, octaves } => {
                let c = mapping.map(ctx);
                turbulence(c.p, c.dpdx, c.dpdy, *omega, *octaves)
            }
            FloatSource::Windy { mapping } => {
                let c = mapping.map(ctx);
                windy(c.p, c.dpdx, c.dpdy)
            }
            FloatSource::Image(image) => image.eval(ctx),
        }
    }
}

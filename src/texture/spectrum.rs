//! Spectrum textures: the [`TextureValue`] of [`Spectrum`], and the spectrum-only texture
//! types.

use super::context::TextureEvalContext;
use super::image::SpectrumImage;
use super::marble::Marble;
use super::TextureValue;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// Spectrum-only textures.
#[derive(Clone, Debug)]
pub enum SpectrumSource {
    /// "marble".
    Marble(Marble),
    /// "imagemap": reflectance from RGB.
    Image(SpectrumImage),
}

impl TextureValue for Spectrum {
    type Sampled = SampledSpectrum;
    type Lambda = SampledWavelengths;
    type Source = SpectrumSource;

    fn at(&self, w: &SampledWavelengths) -> SampledSpectrum {
        self.sample(w)
    }

    fn source(source: &SpectrumSource, ctx: &TextureEvalContext, w: &SampledWavelengths) -> SampledSpectrum {
        match source {
            SpectrumSource::Marble(m) => m.eval(ctx, w),
            SpectrumSource::Image(i) => i.eval(ctx, w),
        }
    }
}

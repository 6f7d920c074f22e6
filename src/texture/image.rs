//! Image textures (pbrt-v4 "imagemap", §10.4): a MIP-mapped image looked up through a 2D
//! mapping and filtered over the footprint. Image row 0 is the top of the picture, t = 1, so
//! t is flipped. Float textures read the first channel; spectrum textures turn RGB into
//! reflectance spectra.

use super::context::TextureEvalContext;
use super::encoding::ColorEncoding;
use super::mapping::Mapping2D;
use super::mipmap::MipMap;
use crate::image::Image;
use crate::spectrum::{
    fit_albedo, normalised_wavelengths, srgb_encode, ColorSpace, SampledSpectrum, SampledWavelengths, SigmoidPolynomial,
};
use glam::Vec2;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// The RGB texels of `img` (grey for one or two channels; alpha dropped), row 0 at the top.
/// `recode`: for images stored as integer codes, which prism's reader decodes with the sRGB
/// curve, the encoding the file is to be read with instead (pbrt-v4's "encoding").
pub fn rgb_texels(img: &Image, recode: Option<ColorEncoding>) -> Vec<[f32; 3]> {
    let c = img.channels as usize;
    let convert = |v: f32| match recode {
        None | Some(ColorEncoding::Srgb) => v,
        // Back to the code (exact on a 1/65535 grid, which holds 8- and 16-bit codes alike).
        Some(e) => e.to_linear((srgb_encode(v) * 65535.0).round() / 65535.0),
    };
    img.data
        .chunks_exact(c.max(1))
        .map(|px| if c >= 3 { [px[0], px[1], px[2]] } else { [px[0]; 3] }.map(convert))
        .collect()
}

/// (s, t) of the image and the footprint axes, with t flipped to the image's top-down rows.
fn image_coords(mapping: &Mapping2D, ctx: &TextureEvalContext) -> (Vec2, Vec2, Vec2) {
    let c = mapping.map(ctx);
    let flip = |v: Vec2| Vec2::new(v.x, -v.y);
    (Vec2::new(c.st.x, 1.0 - c.st.y), flip(c.dst_dx), flip(c.dst_dy))
}

/// A float image texture: `scale` times the filtered first channel, then 1 − v (at least 0)
/// when `invert`.
#[derive(Clone, Debug)]
pub struct FloatImage {
    mapping: Mapping2D,
    mip: Arc<MipMap<f32>>,
    scale: f32,
    invert: bool,
}

impl FloatImage {
    /// The first channel of the pyramid `rgb`.
    pub fn new(mapping: Mapping2D, rgb: &MipMap<[f32; 3]>, scale: f32, invert: bool) -> Self {
        Self { mapping, mip: Arc::new(rgb.map(|t| t[0])), scale, invert }
    }

    /// The value at `ctx`.
    pub fn eval(&self, ctx: &TextureEvalContext) -> f32 {
        let (st, d0, d1) = image_coords(&self.mapping, ctx);
        let v = self.scale * self.mip.filter(st, d0, d1, |&t| t);
        if self.invert {
            (1.0 - v).max(0.0)
        } else {
            v
        }
    }
}

/// An RGB image as reflectance: each texel's RGB (times `scale`, inverted to 1 − RGB if asked,
/// clamped to [0, 1]) is fitted once, at load, by Jakob–Hanika, and a lookup filters the
/// texels' spectra. A weighted sum of spectra projects to the same weighted sum of their RGB,
/// so this is RGB filtering without a fit per shading point (pbrt-v4 fits the filtered RGB; the
/// two agree except where the clamp to [0, 1] acts between texels).
#[derive(Clone, Debug)]
pub struct SpectrumImage {
    mapping: Mapping2D,
    mip: Arc<MipMap<SigmoidPolynomial>>,
}

impl SpectrumImage {
    /// Fits every distinct texel value of every level of `rgb` in `space` (in parallel; an
    /// image of few colours, as most 8-bit ones, needs few fits).
    pub fn new(mapping: Mapping2D, rgb: &MipMap<[f32; 3]>, scale: f32, invert: bool, space: &ColorSpace) -> Self {
        // The fit's starting table is built in parallel on first use: build it here, before
        // the parallel fits, so that no fit waits inside the thread pool for the table.
        let _ = space.rgb_to_spectrum_table();
        let reflectance = |t: &[f32; 3]| {
            t.map(|x| {
                let x = x * scale;
                let x = if invert { 1.0 - x } else { x };
                (x.clamp(0.0, 1.0) as f64).to_bits()
            })
        };
        let mut distinct: Vec<[u64; 3]> = rgb.texels().map(reflectance).collect();
        distinct.sort_unstable();
        distinct.dedup();
        let fits: HashMap<[u64; 3], SigmoidPolynomial> =
            distinct.into_par_iter().map(|v| (v, fit_albedo(v.map(f64::from_bits), space).poly)).collect();
        let mip = rgb.map(|t| fits[&reflectance(t)]);
        Self { mapping, mip: Arc::new(mip) }
    }

    /// The reflectance at `ctx` for the path's wavelengths.
    pub fn eval(&self, ctx: &TextureEvalContext, w: &SampledWavelengths) -> SampledSpectrum {
        let (st, d0, d1) = image_coords(&self.mapping, ctx);
        let x = normalised_wavelengths(w.lambda);
        self.mip.filter(st, d0, d1, |p| SampledSpectrum(p.sample(x)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{RgbKind, Spectrum};
    use crate::texture::mipmap::MipOptions;

    /// 2 × 2 RGB: red, green (top row), blue, white (bottom row).
    fn image() -> Image {
        let data = vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        Image { width: 2, height: 2, channels: 3, data }
    }

    fn pyramid() -> MipMap<[f32; 3]> {
        MipMap::build(2, 2, rgb_texels(&image(), None), MipOptions::default())
    }

    #[test]
    fn row_zero_is_the_top_of_the_texture() {
        let t = FloatImage::new(Mapping2D::UV, &pyramid(), 1.0, false);
        // Texel centres: (u, v) = (0.25, 0.75) is the top-left texel (red: channel 0 is 1);
        // (0.75, 0.75) top-right (green: 0); (0.25, 0.25) bottom-left (blue: 0).
        let at = |u: f32, v: f32| t.eval(&TextureEvalContext::uv(Vec2::new(u, v)));
        assert_eq!(at(0.25, 0.75), 1.0);
        assert_eq!(at(0.75, 0.75), 0.0);
        assert_eq!(at(0.25, 0.25), 0.0);
        assert_eq!(at(0.75, 0.25), 1.0);
        // Halfway between the two top texels, bilinear: ½; one period on, the same (repeat).
        assert!((at(0.5, 0.75) - 0.5).abs() < 1e-6);
        assert_eq!(at(1.25, 0.75), at(0.25, 0.75));
    }

    #[test]
    fn scale_and_invert() {
        let t = FloatImage::new(Mapping2D::UV, &pyramid(), 0.5, true);
        // Red texel: 1 · 0.5 inverted = 0.5; green: 0 inverted = 1.
        assert!((t.eval(&TextureEvalContext::uv(Vec2::new(0.25, 0.75))) - 0.5).abs() < 1e-6);
        assert_eq!(t.eval(&TextureEvalContext::uv(Vec2::new(0.75, 0.75))), 1.0);
        // Over-range values invert to 0, not below.
        let bright = FloatImage::new(Mapping2D::UV, &pyramid(), 3.0, true);
        assert_eq!(bright.eval(&TextureEvalContext::uv(Vec2::new(0.25, 0.75))), 0.0);
    }

    #[test]
    fn spectra_are_the_texel_fits_blended() {
        let t = SpectrumImage::new(Mapping2D::UV, &pyramid(), 1.0, false, ColorSpace::srgb());
        let w = SampledWavelengths { lambda: [420.0, 510.0, 580.0, 690.0], pdf: [1.0; 4] };
        let fit = |rgb: [f32; 3]| Spectrum::from_rgb(rgb, RgbKind::Albedo, ColorSpace::srgb()).sample(&w);
        let (red, green) = (fit([1.0, 0.0, 0.0]), fit([0.0, 1.0, 0.0]));
        let at_red = t.eval(&TextureEvalContext::uv(Vec2::new(0.25, 0.75)), &w);
        let halfway = t.eval(&TextureEvalContext::uv(Vec2::new(0.5, 0.75)), &w);
        for k in 0..4 {
            assert!((at_red[k] - red[k]).abs() < 1e-5, "{at_red:?} vs {red:?}");
            assert!((halfway[k] - 0.5 * (red[k] + green[k])).abs() < 1e-5, "{halfway:?}");
        }
        // The white texel is a flat 1; inverted it is a flat 0.
        let white = t.eval(&TextureEvalContext::uv(Vec2::new(0.75, 0.25)), &w);
        assert!((0..4).all(|k| (white[k] - 1.0).abs() < 1e-3), "{white:?}");
        let inv = SpectrumImage::new(Mapping2D::UV, &pyramid(), 1.0, true, ColorSpace::srgb());
        let black = inv.eval(&TextureEvalContext::uv(Vec2::new(0.75, 0.25)), &w);
        assert!((0..4).all(|k| black[k] < 1e-3), "{black:?}");
    }

    #[test]
    fn recoding_reads_the_stored_codes_with_another_curve() {
        // A pixel stored as code 128/255 was decoded with sRGB by the reader.
        let code = 128.0 / 255.0;
        let img = Image { width: 1, height: 1, channels: 1, data: vec![crate::spectrum::srgb_decode(code)] };
        let lin = rgb_texels(&img, Some(ColorEncoding::Linear))[0][0];
        assert!((lin - code).abs() < 1e-7, "{lin}");
        let g = rgb_texels(&img, Some(ColorEncoding::Gamma(2.2)))[0][0];
        assert!((g - code.powf(2.2)).abs() < 1e-6, "{g}");
        assert_eq!(rgb_texels(&img, Some(ColorEncoding::Srgb))[0][0], img.data[0]);
    }
}

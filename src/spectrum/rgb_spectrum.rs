//! `Spectrum::from_rgb`: RGB → spectrum with Jakob–Hanika (the default) for the three kinds
//! pbrt-v4 has (`RGBAlbedoSpectrum`, `RGBUnboundedSpectrum`, `RGBIlluminantSpectrum`).

use super::albedo_fit::fit_albedo;
use super::color_space::ColorSpace;
use super::spd::{RgbKind, Spectrum};

impl Spectrum {
    /// The Jakob–Hanika spectrum for linear `rgb` in `space`.
    ///
    /// * `Albedo`: components clamped to [0, 1]; a grey r = g = b is the constant r exactly.
    /// * `Unbounded`: components clamped to ≥ 0; m = max(rgb), 2m · σ(fit of rgb / 2m).
    /// * `Illuminant`: the unbounded spectrum times the space's white illuminant (Y = 1), so
    ///   RGB (1,1,1) is the space's white at luminance 1.
    ///
    /// Non-finite components count as 0.
    pub fn from_rgb(rgb: [f32; 3], kind: RgbKind, space: &ColorSpace) -> Spectrum {
        let rgb = rgb.map(|v| if v.is_finite() { v.max(0.0) as f64 } else { 0.0 });
        match kind {
            RgbKind::Albedo => {
                let rgb = rgb.map(|v| v.min(1.0));
                if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
                    return Spectrum::constant(rgb[0] as f32);
                }
                let fit = fit_albedo(rgb, space);
                Spectrum::Sigmoid { poly: fit.poly, scale: 1.0 }
            }
            RgbKind::Unbounded => unbounded(rgb, space),
            RgbKind::Illuminant => unbounded(rgb, space).product(space.illuminant.clone()),
        }
    }
}

fn unbounded(rgb: [f64; 3], space: &ColorSpace) -> Spectrum {
    let m = rgb[0].max(rgb[1]).max(rgb[2]);
    if m == 0.0 {
        return Spectrum::constant(0.0);
    }
    if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
        return Spectrum::constant(m as f32);
    }
    let scale = 2.0 * m;
    let fit = fit_albedo(rgb.map(|v| v / scale), space);
    Spectrum::Sigmoid { poly: fit.poly, scale: scale as f32 }
}

//! pbrt-v4's "hair" material: a fibre's absorption from σa, a colour, or melanin
//! concentrations, and the [`Hair`] BSDF at the hit's offset across the fibre.

use super::{FloatTexture, SpectrumTexture, TextureEvalContext};
use crate::bsdf::hair::{sigma_a_from_reflectance, Hair};
use crate::bsdf::Bxdf;
use crate::spectrum::{ColorSpace, RgbKind, SampledWavelengths, Spectrum};

/// Where a fibre's interior absorption comes from (pbrt-v4 checks them in this order).
#[derive(Clone, Debug)]
pub enum HairAbsorption {
    /// "sigma_a" [1 / fibre radius], or melanin concentrations that are constant (turned into
    /// σa once).
    SigmaA(Spectrum),
    /// "reflectance": the fibre's colour, inverted to σa through Chiang et al.'s fit.
    Reflectance(SpectrumTexture),
    /// "eumelanin" and "pheomelanin" concentrations that vary over the surface.
    Melanin {
        /// Eumelanin concentration (brown to black).
        eumelanin: FloatTexture,
        /// Pheomelanin concentration (red).
        pheomelanin: FloatTexture,
    },
}

/// The hair material.
#[derive(Clone, Debug)]
pub struct HairMaterial {
    /// Interior absorption.
    pub absorption: HairAbsorption,
    /// Index of refraction of the fibre (1.55).
    pub eta: FloatTexture,
    /// Longitudinal roughness β_m ∈ [0, 1] (0.3).
    pub beta_m: FloatTexture,
    /// Azimuthal roughness β_n ∈ [0, 1] (0.3).
    pub beta_n: FloatTexture,
    /// Cuticle scale tilt α [degrees] (2).
    pub alpha: FloatTexture,
}

impl HairMaterial {
    /// The fibre's BxDF at `tex`, whose v across the curve's width gives the offset
    /// h = 2v − 1 (pbrt-v4's convention).
    pub fn bxdf(&self, tex: &TextureEvalContext, w: &SampledWavelengths) -> Bxdf {
        let beta_n = self.beta_n.eval(tex);
        let sigma_a = match &self.absorption {
            HairAbsorption::SigmaA(s) => s.sample(w),
            HairAbsorption::Reflectance(c) => {
                c.eval(tex, w).map(|c| sigma_a_from_reflectance(c.clamp(0.0, 1.0), beta_n))
            }
            HairAbsorption::Melanin { eumelanin, pheomelanin } => {
                melanin_sigma_a(eumelanin.eval(tex), pheomelanin.eval(tex)).sample(w)
            }
        };
        let h = -1.0 + 2.0 * tex.uv.y;
        Hair::new(h, self.eta.eval(tex), sigma_a, self.beta_m.eval(tex), beta_n, self.alpha.eval(tex)).into()
    }
}

/// σa of melanin concentrations as a spectrum (from its linear-sRGB values).
pub fn melanin_sigma_a(eumelanin: f32, pheomelanin: f32) -> Spectrum {
    let rgb = crate::bsdf::hair::sigma_a_from_melanin(eumelanin, pheomelanin);
    Spectrum::from_rgb(rgb, RgbKind::Unbounded, ColorSpace::srgb())
}

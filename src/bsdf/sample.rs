//! The result of sampling a BxDF.

use super::BxdfFlags;
use crate::math::Vec3;
use crate::spectrum::SampledSpectrum;

/// A sampled incident direction with its BxDF value and density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// f(wo, wi) at the four wavelengths (cosine not included) [1/sr].
    pub f: SampledSpectrum,
    /// Sampled incident direction (local frame from a [`super::Bxdf`], world from a
    /// [`super::Bsdf`]).
    pub wi: Vec3,
    /// Density of `wi` [1/sr]; for a delta lobe the discrete probability of choosing it.
    pub pdf: f32,
    /// Kind of lobe sampled.
    pub flags: BxdfFlags,
    /// Relative IOR η_t/η_i along the sampled transmission (1 for reflection): the integrator
    /// tracks η² for Russian roulette.
    pub eta: f32,
    /// True when `pdf` is only proportional to the density (stochastic layered models).
    pub pdf_is_proportional: bool,
}

impl BsdfSample {
    /// A sample with `eta` = 1 and an exact pdf.
    pub fn new(f: SampledSpectrum, wi: Vec3, pdf: f32, flags: BxdfFlags) -> Self {
        Self { f, wi, pdf, flags, eta: 1.0, pdf_is_proportional: false }
    }
    /// Sampled a reflection lobe.
    pub fn is_reflection(&self) -> bool {
        self.flags.is_reflective()
    }
    /// Sampled a transmission lobe.
    pub fn is_transmission(&self) -> bool {
        self.flags.is_transmissive()
    }
    /// Sampled a delta lobe (no MIS with light sampling).
    pub fn is_specular(&self) -> bool {
        self.flags.is_specular()
    }
}

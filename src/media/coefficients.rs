//! A medium's coefficients: at one point of the path's four wavelengths, and the same
//! everywhere (a homogeneous medium, and the constant part of a grid medium).

use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// A medium's coefficients at one point, at the path's four wavelengths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumPoint {
    /// Absorption coefficient σ_a [1/scene unit].
    pub sigma_a: SampledSpectrum,
    /// Scattering coefficient σ_s [1/scene unit].
    pub sigma_s: SampledSpectrum,
    /// Emitted radiance L_e [W/(sr·m²·nm)]; the source term of the transport equation is σ_a L_e.
    pub le: SampledSpectrum,
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
}

impl MediumPoint {
    /// Extinction σ_t = σ_a + σ_s.
    #[inline]
    pub fn sigma_t(&self) -> SampledSpectrum {
        self.sigma_a + self.sigma_s
    }

    /// Single-scattering albedo σ_s/σ_t (0 where σ_t = 0).
    pub fn albedo(&self) -> SampledSpectrum {
        self.sigma_s.safe_div(self.sigma_t())
    }
}

/// A medium with the same coefficients everywhere (pbrt-v4 `HomogeneousMedium`).
#[derive(Clone, Debug)]
pub struct Homogeneous {
    /// σ_a before `scale` [1/scene unit].
    pub sigma_a: Spectrum,
    /// σ_s before `scale` [1/scene unit].
    pub sigma_s: Spectrum,
    /// Multiplier of both coefficients.
    pub scale: f32,
    /// Emitted radiance, already multiplied by its scale (zero: no emission).
    pub le: Spectrum,
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
}

impl Homogeneous {
    /// True when the medium emits (L_e above zero at some visible wavelength).
    pub fn emits(&self) -> bool {
        self.le.max_value() > 0.0
    }

    /// The coefficients at the wavelengths `w`.
    pub fn point(&self, w: &SampledWavelengths) -> MediumPoint {
        MediumPoint {
            sigma_a: self.sigma_a.sample(w) * self.scale,
            sigma_s: self.sigma_s.sample(w) * self.scale,
            le: self.le.sample(w),
            g: self.g,
        }
    }
}

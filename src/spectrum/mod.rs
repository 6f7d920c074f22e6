//! Spectral and colorimetric core: sampled spectra, spectral representations, CIE colour
//! matching, colour spaces and RGB→spectrum upsampling.

mod albedo_fit;
mod blackbody;
pub mod cie;
mod color_space;
mod data;
pub mod display;
mod illuminant;
mod jakob_hanika;
mod lanes;
mod named;
mod pbrt_spectra;
pub mod projection;
mod rgb_spectrum;
pub mod roundtrip;
mod sampled;
mod sigmoid;
pub mod smits;
mod spd;
mod spd_file;
mod transfer;

pub use albedo_fit::{fit_albedo, fit_albedo_fast};
pub use blackbody::{blackbody_peak_radiance, blackbody_radiance};
pub use cie::{xyz_bar, CIE_Y_INTEGRAL, K_M};
pub use color_space::{rgb_to_xyz_from_chromaticities, ColorSpace};
pub use illuminant::{daylight, normalise_luminance, NAMED_ILLUMINANTS};
pub use jakob_hanika::{Fit, RgbToSpectrumTable};
pub use lanes::S4;
pub use named::NAMED_SPECTRA;
pub use pbrt_spectra::{
    camera_names, camera_rgb_bar, camera_sensitivities, colorchecker_reflectances, is_named_spectrum, CameraCurves,
    CAMERA_LAMBDA_START, CAMERA_LAMBDA_STEP,
};
pub use sampled::{
    sample_visible_wavelength, uniform_wavelength_pdf, visible_wavelength_pdf, SampledSpectrum, SampledWavelengths,
    LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES,
};
pub use sigmoid::{normalised_wavelengths, ScaledSigmoid, SigmoidPolynomial};
pub use spd::{PiecewiseConstant, PiecewiseLinear, RgbKind, Spectrum};
pub use spd_file::{parse_spd, SpdError};
pub use transfer::{srgb_decode, srgb_encode, srgb_to_u8};
#[cfg(test)]
mod metamer_tests;
#[cfg(test)]
mod truth_tests;

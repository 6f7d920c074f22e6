//! Spectral and colorimetric core: sampled spectra, spectral representations, CIE colour
//! matching, colour spaces and RGB→spectrum upsampling (lecture: "Color").

mod sampled;

pub use sampled::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES};

//! Participating media: a homogeneous medium given by its absorption and scattering
//! coefficients, free-flight distance sampling with spectral MIS over the path's four
//! wavelengths, and the Henyey–Greenstein phase function. Used by the random-walk subsurface
//! reference (`integrator::subsurface`).

mod homogeneous;
mod phase;

pub use homogeneous::{FreeFlight, HomogeneousMedium};
pub use phase::{hg_density, HenyeyGreenstein};

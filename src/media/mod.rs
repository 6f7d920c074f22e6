//! Participating media: homogeneous media, density and RGB grids, pbrt-v4's procedural
//! cloud and NanoVDB grids ([`Medium`]), majorants and
//! free-flight sampling against them ([`sample_t_maj`]), the measured media table, and the
//! Henyey–Greenstein phase function. The volumetric path tracer (`integrator::volpath`) samples
//! free flights in a scene's [`Medium`], the random-walk subsurface method in a subsurface
//! material's homogeneous interior ([`sample_t_maj_homogeneous`]): one free-flight sampler.

mod cloud;
mod coefficients;
mod delta_tracking;
pub mod grid;
pub mod majorant;
mod medium;
pub mod nanovdb;
mod nanovdb_medium;
mod phase;
pub mod presets;
mod rgb_grid;

pub use cloud::{CloudMedium, CloudShape};
pub use coefficients::{Homogeneous, MediumPoint};
pub use delta_tracking::{sample_t_maj, sample_t_maj_homogeneous, Collision};
pub use grid::{DensityGrid, EmissionSource, GridEmission, GridMedium};
pub use majorant::MajorantSegment;
pub use medium::Medium;
pub use nanovdb_medium::{NanoVdbMedium, TemperatureEmission, NANOVDB_MAJORANT_RES};
pub use phase::{hg_density, HenyeyGreenstein};
pub use rgb_grid::{RgbGridMedium, SpectrumGrid};

//! Participating media: homogeneous media, density and RGB grids, pbrt-v4's procedural
//! cloud and NanoVDB grids ([`Medium`]), majorants and
//! free-flight sampling against them ([`sample_t_maj`]), the measured media table, and the
//! Henyey–Greenstein phase function. The volumetric path tracer (`integrator::volpath`) samples
//! free flights in a scene's [`Medium`], the random-walk subsurface method in a subsurface
//! material's homogeneous interior ([`sample_t_maj_homogeneous`]): one free-flight sampler.
//!
//! A medium answers two questions of the volumetric path tracer (pbrt-v4 `Medium`, Pharr, Jakob
//! & Humphreys, *Physically Based Rendering*, 4th ed., §11.4): the coefficients at a point (σ_a,
//! σ_s, the emitted radiance L_e and the phase function's g), and the majorant σ_maj ≥ σ_t along
//! a ray, piecewise constant over segments, that free-flight sampling draws distances from. A new
//! medium is its own file, its variant, arms and name here, and its parameters in the reader.

mod cloud;
mod coefficients;
mod delta_tracking;
pub mod grid;
pub mod majorant;
pub mod nanovdb;
mod nanovdb_medium;
pub mod presets;
mod rgb_grid;

pub use crate::bsdf::{hg_density, HenyeyGreenstein};
pub use cloud::{CloudMedium, CloudShape};
pub use coefficients::{Homogeneous, MediumPoint};
pub use delta_tracking::{sample_t_maj, sample_t_maj_homogeneous, take_cut_off_walks, Collision, MAX_COLLISIONS};
pub use grid::{DensityGrid, EmissionSource, GridEmission, GridMedium};
pub use majorant::MajorantSegment;
pub use nanovdb_medium::{NanoVdbMedium, TemperatureEmission, NANOVDB_MAJORANT_RES};
pub use rgb_grid::{RgbGridMedium, SpectrumGrid};

use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use majorant::MajorantSegments;

/// The pbrt-v4 medium types, by the names `MakeNamedMedium` gives them.
pub const PBRT_NAMES: &[&str] = &["homogeneous", "uniformgrid", "rgbgrid", "cloud", "nanovdb"];

/// A participating medium.
#[derive(Clone, Debug)]
pub enum Medium {
    /// Constant coefficients.
    Homogeneous(Homogeneous),
    /// Coefficients scaled by a density grid over a box (pbrt-v4 `GridMedium`).
    Grid(Box<GridMedium>),
    /// RGB coefficients on a grid over a box (pbrt-v4 `RGBGridMedium`).
    RgbGrid(Box<RgbGridMedium>),
    /// pbrt-v4's procedural cloud.
    Cloud(Box<CloudMedium>),
    /// A NanoVDB density grid (pbrt-v4 `NanoVDBMedium`).
    NanoVdb(Box<NanoVdbMedium>),
}

impl Medium {
    /// True when the medium emits light somewhere.
    pub fn emits(&self) -> bool {
        match self {
            Medium::Homogeneous(h) => h.emits(),
            Medium::Grid(g) => g.emission.is_some() || g.coefficients.emits(),
            Medium::RgbGrid(g) => g.emits(),
            Medium::Cloud(_) => false,
            Medium::NanoVdb(v) => v.emission.is_some(),
        }
    }

    /// The coefficients at world-space point `p`; `uniform` is the homogeneous medium's
    /// (evaluated once per ray, since it does not vary).
    #[inline]
    pub fn point_at(&self, p: Vec3, uniform: &MediumPoint, w: &SampledWavelengths) -> MediumPoint {
        match self {
            Medium::Homogeneous(_) => *uniform,
            Medium::Grid(g) => g.point_given(p, uniform, w),
            Medium::RgbGrid(g) => g.point(p, w),
            Medium::Cloud(c) => c.point(p, uniform),
            Medium::NanoVdb(v) => v.point(p, uniform, w),
        }
    }

    /// The spatially constant part of the medium at `w`: all of a homogeneous medium, the
    /// coefficients at unit density of a density grid, a cloud or a NanoVDB grid (the RGB grid has none).
    pub fn uniform_point(&self, w: &SampledWavelengths) -> MediumPoint {
        match self {
            Medium::Homogeneous(h) => h.point(w),
            Medium::Grid(g) => g.unit_point(w),
            Medium::RgbGrid(_) => MediumPoint {
                sigma_a: SampledSpectrum::zero(),
                sigma_s: SampledSpectrum::zero(),
                le: SampledSpectrum::zero(),
                g: 0.0,
            },
            Medium::Cloud(c) => c.coefficients.point(w),
            Medium::NanoVdb(v) => v.coefficients.point(w),
        }
    }

    /// The majorant's segments along the ray `o + t d` (`d` unit, world space) for t in
    /// [0, t_max] at the path's wavelengths `w`.
    pub fn majorant_segments(
        &self,
        o: Vec3,
        d: Vec3,
        t_max: f32,
        uniform: &MediumPoint,
        w: &SampledWavelengths,
    ) -> MajorantSegments<'_> {
        let sigma_t = uniform.sigma_a + uniform.sigma_s;
        match self {
            Medium::Homogeneous(_) => MajorantSegments::single(0.0, t_max, sigma_t),
            Medium::Grid(g) => g.majorant_segments(o, d, t_max, sigma_t),
            Medium::RgbGrid(g) => g.majorant_segments(o, d, t_max, w),
            Medium::Cloud(c) => c.majorant_segments(o, d, t_max, sigma_t),
            Medium::NanoVdb(v) => v.majorant_segments(o, d, t_max, sigma_t),
        }
    }
}

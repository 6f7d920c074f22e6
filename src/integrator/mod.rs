//! Integrators: estimators of the radiance arriving at the camera, behind one interface
//! ([`Integrator`]).

mod ambient_occlusion;
mod bdpt;
mod bdpt_weights;
mod camera_sample;
mod collision;
mod free_flight;
mod function;
#[cfg(test)]
mod function_tests;
mod interface;
mod lightpath;
mod mlt;
#[cfg(test)]
mod nanovdb_tests;
mod options;
mod path;
mod random_walk;
mod simple_path;
mod simple_volpath;
mod sppm;
pub mod sppm_grid;
mod state;
pub mod subsurface;
mod transmittance;
mod visible_surface;
mod volpath;
#[cfg(test)]
mod volpath_tests;
pub mod wavefront;

pub use camera_sample::{camera_sample, CameraSample};
pub use function::{function_image, FunctionTest, FunctionTestError, MseCurve};
pub use interface::{DirectStrategy, Integrator, IntegratorKind, UNBOUNDED_DEPTH};
pub use mlt::MltFilm;
pub use options::{AmbientOcclusion, FunctionOptions, Mlt, SimplePath, Sppm, StrategyImageKind};
pub use sppm::VisiblePoint;
pub use subsurface::SubsurfaceMethod;

use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Light a sample brings to a film position of its own (light tracing's camera connections):
/// the render loop turns it into the sensor's response at those wavelengths and splats it.
#[derive(Clone, Copy, Debug)]
pub struct SplatSample {
    /// Position in the full image [pixels]; `None`: the camera sample's own.
    pub p_raster: Option<glam::Vec2>,
    /// The contribution [the camera's measurement per path].
    pub l: SampledSpectrum,
    /// The wavelengths it was carried at (a dispersive interface may have ended all but one).
    pub lambdas: SampledWavelengths,
    /// The bidirectional strategy (s, t) whose image alone it belongs to
    /// ([`crate::film::StrategyImages`]); `None`: the main image.
    pub strategy: Option<(usize, usize)>,
}

/// Counters gathered while rendering (summed over threads).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Rays traced (camera, continuation and shadow).
    pub rays: u64,
    /// Camera samples taken.
    pub samples: u64,
    /// Samples whose estimate was NaN or infinite and was discarded.
    pub nonfinite: u64,
    /// Where the first few non-finite samples happened: (x, y, sample index, path depth).
    pub nonfinite_at: Vec<(u32, u32, u64, u32)>,
    /// Depth reached by the last traced path (for locating non-finite samples).
    pub last_depth: u32,
    /// Time the wavefront loop spent in each of its stages [ns], summed over threads (zero for
    /// the scalar loop).
    pub stage_ns: [u64; wavefront::STAGES],
}

impl Stats {
    /// Adds another thread's counters.
    pub fn merge(&mut self, o: &Stats) {
        self.rays += o.rays;
        self.samples += o.samples;
        self.nonfinite += o.nonfinite;
        for (a, b) in self.stage_ns.iter_mut().zip(o.stage_ns) {
            *a += b;
        }
        for &p in &o.nonfinite_at {
            if self.nonfinite_at.len() < 16 {
                self.nonfinite_at.push(p);
            }
        }
    }
}

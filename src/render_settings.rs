//! The settings of a render that are not the scene: resolution and film, samples, seed,
//! sampler, filter, integrator, time limit.

use crate::film::FilmSettings;
use crate::filter::Filter;
use crate::integrator::Integrator;
use crate::sampling::SamplerKind;
use std::time::Duration;

/// Everything about a render that is not the scene.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Size of the full image [pixels].
    pub resolution: (u32, u32),
    /// The part of the image rendered and the sensor it is seen through.
    pub film: FilmSettings,
    /// Samples per pixel.
    pub spp: u64,
    /// Seed of all random decisions.
    pub seed: u64,
    /// Sampler.
    pub sampler: SamplerKind,
    /// Pixel filter.
    pub filter: Filter,
    /// The integrator and its settings.
    pub integrator: Integrator,
    /// Stop after the pass during which this much time has passed.
    pub time_limit: Option<Duration>,
    /// Render with the wavefront prototype ([`crate::integrator::wavefront`]; the caller checks
    /// the scene with [`crate::integrator::wavefront::check`]). Ignored with geometry buffers,
    /// spectral buckets, adaptive sampling or a splatting estimator.
    pub wavefront: bool,
}

impl Default for RenderSettings {
    /// prism's defaults, which a scene file and then the command line override: 256×256 pixels,
    /// 16 samples per pixel, seed 0, Sobol, Gaussian filter, the path tracer's defaults (depth
    /// 8, diffusion subsurface), the whole image, the default sensor, no time limit.
    fn default() -> Self {
        Self {
            resolution: (256, 256),
            film: FilmSettings::default(),
            spp: 16,
            seed: 0,
            sampler: SamplerKind::Sobol,
            filter: Filter::by_name("gaussian").expect("built in"),
            integrator: Integrator::default(),
            time_limit: None,
            wavefront: false,
        }
    }
}

impl RenderSettings {
    /// Size of the film: the crop, or the whole image [pixels].
    pub fn film_size(&self) -> (u32, u32) {
        match self.film.crop {
            Some(b) => (b.x1 - b.x0, b.y1 - b.y0),
            None => self.resolution,
        }
    }

    /// The full-image pixel of the film's pixel (0, 0).
    pub(crate) fn film_origin(&self) -> (u32, u32) {
        self.film.crop.map_or((0, 0), |b| (b.x0, b.y0))
    }
}

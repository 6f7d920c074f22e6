//! The paths of a batch: what each carries between stages, indexed by its place in the batch
//! (pixel-major, then sample index, as the scalar loop visits them).

use super::super::state::PathState;
use crate::geometry::Ray;
use crate::sampling::Sampler;
use crate::spectrum::SampledWavelengths;
use crate::texture::RayDifferentials;

/// One batch of camera paths.
#[derive(Default)]
pub(super) struct Paths {
    /// The pixel's index in its band and its sample index.
    pub pixel: Vec<(u32, u64)>,
    /// Each path's sampler, positioned at its pixel sample.
    pub sampler: Vec<Sampler>,
    pub lambdas: Vec<SampledWavelengths>,
    /// Pixel filter weight and camera-ray weight.
    pub filter_weight: Vec<f32>,
    pub camera_weight: Vec<f32>,
    /// The camera ray's differentials (textures filter over them at the first vertex).
    pub differentials: Vec<Option<RayDifferentials>>,
    pub state: Vec<PathState>,
    /// The ray each active path traces next.
    pub ray: Vec<Ray>,
}

impl Paths {
    pub fn clear(&mut self) {
        self.pixel.clear();
        self.lambdas.clear();
        self.filter_weight.clear();
        self.camera_weight.clear();
        self.differentials.clear();
        self.state.clear();
        self.ray.clear();
        // Samplers are kept: each is repositioned for its next pixel sample.
    }
}

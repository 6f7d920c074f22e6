//! The parameters of pbrt-v4's estimators beyond the shared ones (`ambientocclusion`,
//! `simplepath`, `mlt`, `sppm`, `function`) and `bdpt`'s debugging images, which the one
//! [`super::Integrator`] carries beside the settings every
//! estimator shares.

use crate::spectrum::ColorSpace;

/// pbrt-v4's `ambientocclusion` parameters, and the white it is shown in.
#[derive(Clone, Copy)]
pub struct AmbientOcclusion {
    /// `cossample`: directions sampled ∝ cos θ (true, pbrt-v4's default) or uniformly over the
    /// hemisphere; both estimate the same A.
    pub cos_sample: bool,
    /// `maxdistance` [scene units]: occluders farther than this do not count (default ∞).
    pub max_distance: f32,
    /// The output colour space, whose illuminant (normalised to luminance 1) is the white.
    pub space: &'static ColorSpace,
}

impl Default for AmbientOcclusion {
    fn default() -> Self {
        Self { cos_sample: true, max_distance: f32::INFINITY, space: ColorSpace::srgb() }
    }
}

/// Without the space: it is the output space, which settings name on their own (render
/// fingerprints compare it there).
impl std::fmt::Debug for AmbientOcclusion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (c, d) = (self.cos_sample, self.max_distance);
        write!(f, "AmbientOcclusion {{ cos_sample: {c}, max_distance: {d} }}")
    }
}

/// pbrt-v4's `simplepath` parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SimplePath {
    /// `samplelights` (default true): next-event estimation at every vertex.
    pub sample_lights: bool,
    /// `samplebsdf` (default true): continue by BSDF sampling, else uniformly over the sphere.
    pub sample_bsdf: bool,
}

impl Default for SimplePath {
    fn default() -> Self {
        Self { sample_lights: true, sample_bsdf: true }
    }
}

/// pbrt-v4's `mlt` parameters (its `maxdepth` and `regularize` are the shared ones; its
/// `mutationsperpixel` is the render's samples per pixel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mlt {
    /// `bootstrapsamples` (100 000): paths per depth whose luminance estimates the
    /// normalisation b and from which the chains start.
    pub bootstrap_samples: u32,
    /// `chains` (1000): independent Markov chains.
    pub chains: u32,
    /// `mutationsperpixel` (100), the render's samples per pixel unless the command line
    /// gives them.
    pub mutations_per_pixel: u64,
    /// `largestepprobability` (0.3): the chance that a proposal is an independent path.
    pub large_step_probability: f32,
    /// `sigma` (0.01): standard deviation of a small step's perturbation of each primary
    /// sample.
    pub sigma: f32,
}

impl Default for Mlt {
    fn default() -> Self {
        Self {
            bootstrap_samples: 100_000,
            chains: 1000,
            mutations_per_pixel: 100,
            large_step_probability: 0.3,
            sigma: 0.01,
        }
    }
}

/// pbrt-v4 `bdpt`'s per-strategy images ([`crate::film::StrategyImages`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StrategyImageKind {
    /// None (the default).
    #[default]
    Off,
    /// `visualizestrategies`: each strategy's contribution without its MIS weight (each image
    /// alone estimates all the light of its depth that the strategy can sample).
    Unweighted,
    /// `visualizeweights` (taking precedence, as in pbrt-v4): the weighted contributions, which
    /// sum to the image.
    Weighted,
}
/// pbrt-v4's `sppm` parameters (stochastic progressive photon mapping).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sppm {
    /// `photonsperiteration`: photon paths per pass (`None`, pbrt-v4's −1: one per film pixel).
    pub photons_per_iteration: Option<u64>,
    /// `radius`: every pixel's initial search radius [scene units] (pbrt-v4's default 1).
    pub radius: f32,
    /// `seed`: seeds the photon paths (pbrt-v4's default 6502), with the render's seed.
    pub seed: u64,
}

impl Default for Sppm {
    fn default() -> Self {
        Self { photons_per_iteration: None, radius: 1.0, seed: 6502 }
    }
}

/// pbrt-v4's `function` parameters (its output files are the command line's business).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FunctionOptions {
    /// `function` (default `step`): the integrand.
    pub function: crate::sampling::TestFunction,
    /// `skipbad` (default true): report only the sample counts the sampler's patterns are made
    /// for ([`super::FunctionTest::natural_count`]).
    pub skip_bad: bool,
}

impl Default for FunctionOptions {
    fn default() -> Self {
        Self { function: crate::sampling::TestFunction::Step, skip_bad: true }
    }
}

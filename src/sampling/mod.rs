//! Sampling: random numbers, warps, distributions, MIS weights, samplers, the chi² harness.

pub mod alias;
pub mod chi2;
pub mod distribution;
mod kind;
pub mod mis;
pub mod pattern;
pub mod piecewise_linear;
pub mod pss;
pub mod rng;
pub mod sampler;
mod sobol;
pub mod spherical_rectangle;
mod test_function;
pub mod warp;
pub mod windowed;

pub use alias::AliasTable;
pub use distribution::{Distribution1D, Distribution2D, Sample1D};
pub use kind::SamplerKind;
pub use pattern::Randomize;
pub use piecewise_linear::PiecewiseLinear2D;
pub use pss::{PssSampler, PssStream};
pub use rng::Rng;
pub use sampler::Sampler;
pub use spherical_rectangle::SphericalRectangle;
pub use test_function::TestFunction;
pub use windowed::{Window, WindowedDistribution2D};

/// The radical inverse of `i` in prime base `b` (the Halton sequence's coordinates).
pub fn radical_inverse(b: u32, mut i: u32) -> f64 {
    let (mut inv, mut f) = (0.0, 1.0 / f64::from(b));
    while i > 0 {
        inv += f64::from(i % b) * f;
        i /= b;
        f /= f64::from(b);
    }
    inv
}

//! Sampling: random numbers, warps, distributions, MIS weights, samplers, the chi² harness.

pub mod alias;
pub mod distribution;
pub mod rng;
pub mod sampler;

pub use alias::AliasTable;
pub use distribution::{Distribution1D, Distribution2D, Sample1D};
pub use rng::Rng;
pub use sampler::Sampler;

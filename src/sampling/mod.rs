//! Sampling: random numbers, warps, distributions, MIS weights, samplers, the chi² harness.

pub mod chi2;
pub mod mis;
pub mod rng;
pub mod warp;

pub use rng::Rng;

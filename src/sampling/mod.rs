//! Sampling: random numbers, warps, distributions, MIS weights, samplers, the chi² harness.

pub mod rng;

pub use rng::Rng;

//! prism: a spectral, physically based offline renderer.

pub mod accel;
pub mod cli;
pub mod geometry;
pub mod math;
pub mod sampling;
pub mod spectrum;

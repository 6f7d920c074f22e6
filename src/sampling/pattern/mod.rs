//! pbrt-v4's sample patterns (`Sampler "zsobol" | "sobol" | "paddedsobol" | "halton" |
//! "pmj02bn" | "stratified"`), each a pure function of (pixel, sample index, dimension, seed)
//! and of the render's samples per pixel and image size, drawn in the order pbrt-v4's
//! integrators draw.

mod blue_noise;
mod global_sobol;
mod halton;
mod padded_sobol;
mod pmj02;
mod pmj02bn;
pub mod scramble;
mod sobol2d;
mod sobol_matrices;
mod stratified;
mod torus_grid;
mod zsobol;

pub use global_sobol::GlobalSobol;
pub use halton::Halton;
pub use padded_sobol::PaddedSobol;
pub use pmj02bn::Pmj02bn;
pub use scramble::Randomize;
pub use stratified::Stratified;
pub use zsobol::ZSobol;

use glam::Vec2;

/// One of pbrt-v4's samplers, positioned at a pixel sample.
#[derive(Clone, Debug)]
pub enum Pattern {
    ZSobol(ZSobol),
    GlobalSobol(GlobalSobol),
    PaddedSobol(PaddedSobol),
    Halton(Halton),
    Pmj02bn(Pmj02bn),
    Stratified(Stratified),
}

// Kept out of line: the caller's match over the sampler kinds stays small enough to inline,
// so prism's own Sobol path costs the same with these samplers compiled in.
impl Pattern {
    /// Positions the pattern at sample `index` of `pixel`; dimensions restart.
    #[inline(never)]
    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        match self {
            Self::ZSobol(s) => s.start(pixel, index),
            Self::GlobalSobol(s) => s.start(pixel, index),
            Self::PaddedSobol(s) => s.start(pixel, index),
            Self::Halton(s) => s.start(pixel, index),
            Self::Pmj02bn(s) => s.start(pixel, index),
            Self::Stratified(s) => s.start(pixel, index),
        }
    }

    #[inline(never)]
    pub fn get_1d(&mut self) -> f32 {
        match self {
            Self::ZSobol(s) => s.get_1d(),
            Self::GlobalSobol(s) => s.get_1d(),
            Self::PaddedSobol(s) => s.get_1d(),
            Self::Halton(s) => s.get_1d(),
            Self::Pmj02bn(s) => s.get_1d(),
            Self::Stratified(s) => s.get_1d(),
        }
    }

    #[inline(never)]
    pub fn get_2d(&mut self) -> Vec2 {
        match self {
            Self::ZSobol(s) => s.get_2d(),
            Self::GlobalSobol(s) => s.get_2d(),
            Self::PaddedSobol(s) => s.get_2d(),
            Self::Halton(s) => s.get_2d(),
            Self::Pmj02bn(s) => s.get_2d(),
            Self::Stratified(s) => s.get_2d(),
        }
    }

    /// The film position in the pixel: the global Sobol' sampler's, Halton's and pmj02bn's own
    /// first dimensions, the next 2D draw for the others.
    #[inline(never)]
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        match self {
            Self::GlobalSobol(s) => s.get_pixel_2d(),
            Self::Halton(s) => s.get_pixel_2d(),
            Self::Pmj02bn(s) => s.get_pixel_2d(),
            _ => self.get_2d(),
        }
    }
}

#[cfg(test)]
mod tests;

//! pbrt-v4's `StratifiedSampler`: each 1D draw puts the pixel's n = x·y samples one per stratum
//! of width 1/n, each 2D draw one per cell of an x × y grid, the strata assigned to sample
//! indices by a per-(pixel, dimension) random permutation; jittered within the stratum, or at its
//! centre.

use super::padded_sobol::{permuted_index, pixel_dimension_hash};
use crate::sampling::Rng;
use glam::Vec2;

/// The sampler's settings and its place (pixel sample, dimension).
#[derive(Clone, Debug)]
pub struct Stratified {
    x: u32,
    y: u32,
    jitter: bool,
    seed: u64,
    pixel: (u32, u32),
    index: u64,
    dimension: u64,
    /// The jitter stream of this pixel sample.
    rng: Rng,
}

impl Stratified {
    /// An `x` × `y` grid of strata.
    pub fn new(x: u32, y: u32, jitter: bool, seed: u64) -> Self {
        let (x, y) = (x.max(1), y.max(1));
        Self { x, y, jitter, seed, pixel: (0, 0), index: 0, dimension: 0, rng: Rng::new(0, 0) }
    }

    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        (self.pixel, self.index, self.dimension) = (pixel, index, 0);
        // Each sample's jitters: 2^16 consecutive values of the pixel's stream (as pbrt-v4).
        self.rng = Rng::new(0, u64::from(pixel.0) | u64::from(pixel.1) << 16 | self.seed << 32);
        self.rng.advance(index.wrapping_mul(1 << 16));
    }

    /// The stratum of this sample in the next draw (indices past x·y start a new permutation).
    fn stratum(&mut self, dims: u64) -> u32 {
        let n = self.x * self.y;
        let hash = pixel_dimension_hash(self.pixel, self.dimension, self.seed);
        self.dimension += dims;
        (permuted_index(self.index, n, hash) % u64::from(n)) as u32
    }

    fn offset(&mut self) -> f32 {
        if self.jitter {
            self.rng.uniform()
        } else {
            0.5
        }
    }

    pub fn get_1d(&mut self) -> f32 {
        let n = self.x * self.y;
        let s = self.stratum(1);
        ((s as f32 + self.offset()) / n as f32).min(ONE_MINUS_EPSILON)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let s = self.stratum(2);
        let (sx, sy) = (s % self.x, s / self.x);
        let (dx, dy) = (self.offset(), self.offset());
        Vec2::new(
            ((sx as f32 + dx) / self.x as f32).min(ONE_MINUS_EPSILON),
            ((sy as f32 + dy) / self.y as f32).min(ONE_MINUS_EPSILON),
        )
    }
}

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exactly_one_sample_per_stratum_in_every_draw() {
        for (x, y, jitter) in [(4, 4, true), (3, 5, true), (2, 7, false)] {
            let n = (x * y) as usize;
            let mut s = Stratified::new(x, y, jitter, 11);
            let (mut one_d, mut two_d) = (vec![0; n], vec![0; n]);
            for i in 0..n as u64 {
                s.start((17, 4), i);
                let a = s.get_1d();
                let b = s.get_2d();
                one_d[(a * n as f32) as usize] += 1;
                two_d[(b.y * y as f32) as usize * x as usize + (b.x * x as f32) as usize] += 1;
                if !jitter {
                    // Centres of the strata.
                    assert_eq!((a * n as f32).fract(), 0.5);
                }
            }
            assert!(one_d.iter().all(|&c| c == 1), "{x}×{y}: {one_d:?}");
            assert!(two_d.iter().all(|&c| c == 1), "{x}×{y}: {two_d:?}");
        }
    }
}

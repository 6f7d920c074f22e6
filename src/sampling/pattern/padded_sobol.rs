//! pbrt-v4's `PaddedSobolSampler`: every draw takes dimensions 0 (and 1) of the Sobol' sequence
//! at a per-(pixel, dimension) random permutation of the pixel's sample indices, randomised per
//! draw ("padding" low-dimensional points instead of using high Sobol' dimensions; Kollig &
//! Keller 2002).

use super::scramble::{mix_bits, permutation_element, scramble_base2_rev, unit_from_bits, Randomize};
use super::sobol2d::{sobol_0_rev, sobol_1_rev};
use glam::Vec2;

/// The sampler's settings and its place (pixel sample, dimension).
#[derive(Clone, Debug)]
pub struct PaddedSobol {
    randomize: Randomize,
    seed: u64,
    spp: u32,
    pixel: (u32, u32),
    index: u64,
    dimension: u64,
}

/// The hash of a pixel, dimension and seed that pbrt-v4's padded samplers key their
/// permutations and randomisations by.
pub(super) fn pixel_dimension_hash(pixel: (u32, u32), dimension: u64, seed: u64) -> u64 {
    mix_bits(u64::from(pixel.0) << 48 ^ u64::from(pixel.1) << 32 ^ dimension << 16 ^ seed)
}

/// Sample `index` of the pixel's blocks of `spp`: the block's start plus a permutation of the
/// index within the block, chosen by `hash` and the block.
pub(super) fn permuted_index(index: u64, spp: u32, hash: u64) -> u64 {
    let (block, within) = (index / u64::from(spp), (index % u64::from(spp)) as u32);
    let p = (hash ^ mix_bits(block)) as u32;
    block * u64::from(spp) + u64::from(permutation_element(within, spp, p))
}

impl PaddedSobol {
    /// For `spp` samples per pixel.
    pub fn new(randomize: Randomize, seed: u64, spp: u64) -> Self {
        let spp = spp.clamp(1, u32::MAX as u64) as u32;
        Self { randomize, seed, spp, pixel: (0, 0), index: 0, dimension: 0 }
    }

    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        (self.pixel, self.index, self.dimension) = (pixel, index, 0);
    }

    /// The draw's Sobol' index and random word.
    fn next(&mut self, dims: u64) -> (u64, u64) {
        let hash = pixel_dimension_hash(self.pixel, self.dimension, self.seed);
        self.dimension += dims;
        (permuted_index(self.index, self.spp, hash), hash)
    }

    pub fn get_1d(&mut self) -> f32 {
        let (a, hash) = self.next(1);
        unit_from_bits(scramble_base2_rev(sobol_0_rev(a), self.randomize, (hash >> 32) as u32))
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let (a, hash) = self.next(2);
        Vec2::new(
            unit_from_bits(scramble_base2_rev(sobol_0_rev(a), self.randomize, hash as u32)),
            unit_from_bits(scramble_base2_rev(sobol_1_rev(a), self.randomize, (hash >> 32) as u32)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_draw_of_a_pixels_samples_is_a_0_m_2_net_and_draws_are_shuffled_apart() {
        let m = 4;
        let mut s = PaddedSobol::new(Randomize::Owen, 3, 1 << m);
        let mut draws = vec![vec![]; 3];
        for i in 0..1u64 << m {
            s.start((5, 9), i);
            for d in &mut draws {
                d.push(s.get_2d());
            }
        }
        for d in &draws {
            for k in 0..=m {
                let mut cells = vec![0; 1 << m];
                for u in d {
                    cells[((u.x * (1 << k) as f32) as usize) << (m - k) | (u.y * (1 << (m - k)) as f32) as usize] += 1;
                }
                assert!(cells.iter().all(|&c| c == 1), "shape {k}");
            }
        }
        // The same sample index meets different Sobol' points in different draws.
        assert!((0..16).any(|i| draws[0][i] != draws[1][i]));
    }
}

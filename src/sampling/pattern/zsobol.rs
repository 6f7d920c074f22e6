//! pbrt-v4's `ZSobolSampler` (Ahmed & Wonka 2020, "Screen-space blue-noise diffusion of Monte
//! Carlo sampling error via hierarchical ordering of pixels"): the pixels are numbered along a
//! Morton (Z) curve and their samples follow one another in one 2D Sobol' sequence, the index's
//! base-4 digits randomly permuted per dimension (each permutation chosen by the digits above
//! it), so neighbouring pixels get complementary points. Every draw is dimensions 0 (and 1) of
//! the sequence, randomised per dimension.

use super::scramble::{mix_bits, scramble_base2_rev, unit_from_bits, Randomize};
use super::sobol2d::{sobol_0_rev, sobol_1_rev};
use glam::Vec2;

/// The 24 orders of four base-4 digit values, lexicographic.
const PERMUTATIONS: [[u8; 4]; 24] = {
    let mut out = [[0u8; 4]; 24];
    let mut n = 0;
    let mut a = 0;
    while a < 4 {
        let mut b = 0;
        while b < 4 {
            let mut c = 0;
            while c < 4 {
                if a != b && a != c && b != c {
                    out[n] = [a, b, c, 6 - a - b - c];
                    n += 1;
                }
                c += 1;
            }
            b += 1;
        }
        a += 1;
    }
    out
};

/// The sampler's settings and its place (pixel sample, dimension).
#[derive(Clone, Debug)]
pub struct ZSobol {
    randomize: Randomize,
    seed: u64,
    /// log2 of the samples per pixel, rounded up to a power of two.
    log2_spp: u32,
    /// Base-4 digits of a pixel sample's Morton index that are permuted.
    base4_digits: u32,
    morton_index: u64,
    dimension: u64,
    /// Per dimension, the permuted digits above the sample's own: they depend only on the
    /// pixel (and on indices past the samples per pixel), so a pixel's samples share them.
    /// Held for the pixel sample positions whose `morton_index >> log2_spp` is `high_key`.
    high: Vec<Option<u64>>,
    high_key: u64,
}

/// Dimensions whose permuted high digits [`ZSobol`] keeps (a path draws fewer; a longer one
/// computes the rest afresh).
const CACHED_DIMENSIONS: usize = 256;

/// Interleaves the bits of `x` (even bits) and `y` (odd bits).
fn encode_morton(x: u32, y: u32) -> u64 {
    let spread = |v: u32| {
        let mut v = v as u64;
        v = (v | v << 16) & 0x0000_ffff_0000_ffff;
        v = (v | v << 8) & 0x00ff_00ff_00ff_00ff;
        v = (v | v << 4) & 0x0f0f_0f0f_0f0f_0f0f;
        v = (v | v << 2) & 0x3333_3333_3333_3333;
        (v | v << 1) & 0x5555_5555_5555_5555
    };
    spread(x) | spread(y) << 1
}

impl ZSobol {
    /// For `spp` samples per pixel of an image of `resolution` pixels.
    pub fn new(randomize: Randomize, seed: u64, spp: u64, resolution: (u32, u32)) -> Self {
        let log2_spp = spp.max(1).next_power_of_two().trailing_zeros();
        let log2_res = resolution.0.max(resolution.1).max(1).next_power_of_two().trailing_zeros();
        let base4_digits = log2_res + log2_spp.div_ceil(2);
        Self { randomize, seed, log2_spp, base4_digits, morton_index: 0, dimension: 0, high: Vec::new(), high_key: 0 }
    }

    /// Positions the sampler at sample `index` of `pixel`. Indices past the samples per pixel
    /// (a render extended later) continue the sequence above the image's points.
    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        let spp_mask = (1u64 << self.log2_spp) - 1;
        let low_bits = 2 * (self.base4_digits - self.log2_spp.div_ceil(2)) + self.log2_spp;
        let beyond = (index >> self.log2_spp).checked_shl(low_bits).unwrap_or(0);
        self.morton_index = beyond | encode_morton(pixel.0, pixel.1) << self.log2_spp | (index & spp_mask);
        self.dimension = 0;
        let key = self.morton_index >> self.log2_spp;
        if key != self.high_key {
            self.high.clear();
            self.high_key = key;
        }
    }

    /// The Sobol' index of the current pixel sample for the current dimension: the Morton index
    /// with each base-4 digit permuted by a permutation chosen by the digits above it.
    fn sample_index(&mut self) -> u64 {
        let odd = self.log2_spp & 1;
        let dim_hash = self.dimension.wrapping_mul(0x5555_5555);
        // Digits from `first_high` up lie above the sample's bits.
        let first_high = self.log2_spp.div_ceil(2);
        let d = self.dimension as usize;
        let high = match self.high.get(d) {
            Some(&Some(h)) => h,
            _ => {
                let top = self.morton_index & !((1u64 << (2 * self.base4_digits - odd)) - 1);
                let h = top | self.permuted_digits(first_high..self.base4_digits, dim_hash);
                if d < CACHED_DIMENSIONS {
                    if self.high.len() <= d {
                        self.high.resize(d + 1, None);
                    }
                    self.high[d] = Some(h);
                }
                h
            }
        };
        let mut index = high | self.permuted_digits(odd..first_high, dim_hash);
        if odd == 1 {
            // An odd power of two: the last digit is a single bit, flipped at random.
            let flip = mix_bits((self.morton_index >> 1) ^ dim_hash) & 1;
            index |= (self.morton_index & 1) ^ flip;
        }
        index
    }

    /// Base-4 digits `digits` of the Morton index, each permuted by the permutation the digits
    /// above it and the dimension's hash choose, in place.
    fn permuted_digits(&self, digits: std::ops::Range<u32>, dim_hash: u64) -> u64 {
        let odd = self.log2_spp & 1;
        let mut index = 0;
        for i in digits {
            let shift = 2 * i - odd;
            let digit = (self.morton_index >> shift) & 3;
            let higher = self.morton_index >> (shift + 2);
            let p = (mix_bits(higher ^ dim_hash) >> 24) % 24;
            index |= u64::from(PERMUTATIONS[p as usize][digit as usize]) << shift;
        }
        index
    }

    fn scramble_seed(&self) -> u64 {
        mix_bits(self.dimension ^ self.seed.wrapping_mul(0x9e37_79b9_7f4a_7c15))
    }

    pub fn get_1d(&mut self) -> f32 {
        let a = self.sample_index();
        self.dimension += 1;
        unit_from_bits(scramble_base2_rev(sobol_0_rev(a), self.randomize, self.scramble_seed() as u32))
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let a = self.sample_index();
        self.dimension += 2;
        let h = self.scramble_seed();
        Vec2::new(
            unit_from_bits(scramble_base2_rev(sobol_0_rev(a), self.randomize, h as u32)),
            unit_from_bits(scramble_base2_rev(sobol_1_rev(a), self.randomize, (h >> 32) as u32)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn morton_interleaves_x_in_even_bits() {
        assert_eq!(encode_morton(0b11, 0), 0b0101);
        assert_eq!(encode_morton(0, 0b11), 0b1010);
        // x = 101₂ in bits 0, 4; y = 1001₂ in bits 1, 7.
        assert_eq!(encode_morton(5, 9), 0b1001_0011);
        assert_eq!(PERMUTATIONS.iter().collect::<std::collections::HashSet<_>>().len(), 24);
    }

    #[test]
    fn each_pixels_samples_are_a_scrambled_0_m_2_net_in_every_2d_dimension() {
        // A pixel's 2^m sample indices are one aligned block of the Sobol' sequence (the digit
        // permutations only reorder it), and base-2 scrambles keep (0,m,2)-nets nets: every
        // elementary interval of area 2^-m holds exactly one point.
        for (spp, m) in [(16u64, 4u32), (32, 5), (64, 6)] {
            for how in [Randomize::None, Randomize::PermuteDigits, Randomize::FastOwen, Randomize::Owen] {
                let mut s = ZSobol::new(how, 7, spp, (200, 120));
                for pixel in [(0, 0), (13, 77), (199, 119)] {
                    for draw in 0..3 {
                        let mut cells = vec![vec![0u32; 1 << m]; m as usize + 1];
                        for i in 0..spp {
                            s.start(pixel, i);
                            for _ in 0..draw {
                                s.get_2d();
                            }
                            let u = s.get_2d();
                            assert!((0.0..1.0).contains(&u.x) && (0.0..1.0).contains(&u.y));
                            for (k, c) in cells.iter_mut().enumerate() {
                                let (nx, ny) = (1u32 << k, 1u32 << (m as usize - k));
                                let cell = (u.x * nx as f32) as u32 * ny + (u.y * ny as f32) as u32;
                                c[cell as usize] += 1;
                            }
                        }
                        for (k, c) in cells.iter().enumerate() {
                            assert!(c.iter().all(|&n| n == 1), "{how:?} spp {spp} {pixel:?} draw {draw} shape {k}");
                        }
                    }
                }
            }
        }
    }

    /// The Sobol' index of `s`'s current pixel sample and dimension, every digit permuted afresh.
    fn uncached_index(s: &ZSobol) -> u64 {
        let odd = s.log2_spp & 1;
        let mut index = s.morton_index & !((1u64 << (2 * s.base4_digits - odd)) - 1);
        let dim_hash = s.dimension.wrapping_mul(0x5555_5555);
        for i in odd..s.base4_digits {
            let shift = 2 * i - odd;
            let (digit, higher) = ((s.morton_index >> shift) & 3, s.morton_index >> (shift + 2));
            let p = (mix_bits(higher ^ dim_hash) >> 24) % 24;
            index |= u64::from(PERMUTATIONS[p as usize][digit as usize]) << shift;
        }
        if odd == 1 {
            index |=
                (s.morton_index & 1) ^ (mix_bits((s.morton_index >> 1) ^ s.dimension.wrapping_mul(0x5555_5555)) & 1);
        }
        index
    }

    #[test]
    fn a_pixels_shared_digits_are_reused_exactly() {
        // Pixels visited, left and revisited; indices past the samples per pixel; paths longer
        // than the dimensions kept; even and odd powers of two.
        for spp in [1u64, 2, 8, 16, 64, 128] {
            let mut s = ZSobol::new(Randomize::FastOwen, 3, spp, (300, 200));
            for (pixel, index) in [((0, 0), 0), ((0, 0), 1), ((7, 9), 0), ((0, 0), 2), ((7, 9), spp + 3), ((7, 9), 1)] {
                s.start(pixel, index);
                for draw in 0..300 {
                    let want = uncached_index(&s);
                    assert_eq!(s.sample_index(), want, "spp {spp} {pixel:?} {index} draw {draw}");
                    s.dimension += 1 + draw % 2;
                }
            }
        }
    }

    #[test]
    fn neighbouring_pixels_draw_different_points() {
        let mut s = ZSobol::new(Randomize::FastOwen, 0, 16, (64, 64));
        let mut first = |p| {
            s.start(p, 0);
            s.get_2d()
        };
        assert_ne!(first((0, 0)), first((1, 0)));
        assert_ne!(first((1, 0)), first((0, 1)));
    }
}

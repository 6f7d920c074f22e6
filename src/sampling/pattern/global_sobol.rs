//! pbrt-v4's `SobolSampler`: one Sobol' sequence over the whole image. The image is covered by
//! a 2^m × 2^m grid of pixels (2^m: the larger side rounded up to a power of two), dimensions 0
//! and 1 of the sequence scaled by 2^m are the film position, and sample i of a pixel is the
//! i-th point of the sequence that falls in it. The first two dimensions form a
//! (0,2)-sequence, so the points with indices in [i·4^m, (i+1)·4^m) put exactly one point in
//! each pixel; its index is found by inverting the generator matrices on the pixel's bits
//! (Grünschloß, Raab & Keller 2012, "Enumerating quasi-Monte Carlo point sequences in
//! elementary intervals"). The other dimensions are the same point's higher Sobol' dimensions,
//! randomised per dimension by the render's seed.

use super::scramble::{mix_bits, scramble_base2, unit_from_bits, Randomize};
use super::sobol2d::{sobol_0, sobol_1};
use super::sobol_matrices::{sobol_bits, DIMENSIONS};
use glam::Vec2;

/// The sampler's settings and its place (Sobol' index, dimension).
#[derive(Clone, Debug)]
pub struct GlobalSobol {
    randomize: Randomize,
    seed: u64,
    /// m: the grid is 2^m pixels on a side.
    log2_scale: u32,
    /// Column k: the index bits m..2m (as an m-bit number) that put bit k, alone, in the top
    /// m bits of dimension 1; the inverse of that (nonsingular) part of its generator matrix.
    inverse: [u32; 32],
    index: u64,
    dimension: usize,
}

impl GlobalSobol {
    /// For an image of `resolution` pixels (up to 2³¹ on a side).
    pub fn new(randomize: Randomize, seed: u64, resolution: (u32, u32)) -> Self {
        let side = resolution.0.max(resolution.1).clamp(1, 1 << 31);
        let log2_scale = side.next_power_of_two().trailing_zeros();
        Self { randomize, seed, log2_scale, inverse: inverse_of_mid_block(log2_scale), index: 0, dimension: 2 }
    }

    /// Positions the sampler at sample `index` of `pixel`: the index of the sequence's point in
    /// that pixel among the points `index`·4^m … (`index`+1)·4^m − 1. A pixel outside the grid
    /// (a sample stream other than the camera's, such as photons) takes the grid pixel of its
    /// low bits, its samples continued past 2³² per group of its high bits.
    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        self.dimension = 2;
        let m = self.log2_scale;
        let mask = (1u32 << m) - 1;
        let mut frame = index;
        if (pixel.0 | pixel.1) > mask {
            frame = frame.wrapping_add((u64::from(pixel.0 >> m) + 1) << 32);
        }
        if m == 0 {
            self.index = frame;
            return;
        }
        let (px, py) = (pixel.0 & mask, pixel.1 & mask);
        // Dimension 0 mirrors the index bits: the low m bits are the pixel column, reversed.
        let low = u64::from(px.reverse_bits() >> (32 - m));
        let base = frame.wrapping_shl(2 * m) | low;
        // The middle m bits must make dimension 1's top m bits the pixel row.
        let target = py ^ (sobol_1(base) >> (32 - m));
        let mid = (0..m).filter(|k| target >> k & 1 == 1).fold(0, |acc, k| acc ^ self.inverse[k as usize]);
        self.index = base | u64::from(mid) << m;
    }

    /// Dimension `d` (≥ 2) of the current point, randomised by a word of the seed and `d`.
    fn sample_dimension(&self, d: usize) -> f32 {
        let word = mix_bits((d as u64) << 32 ^ self.seed) as u32;
        unit_from_bits(scramble_base2(sobol_bits(self.index, d), self.randomize, word))
    }

    pub fn get_1d(&mut self) -> f32 {
        if self.dimension >= DIMENSIONS {
            self.dimension = 2;
        }
        self.dimension += 1;
        self.sample_dimension(self.dimension - 1)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        if self.dimension + 1 >= DIMENSIONS {
            self.dimension = 2;
        }
        let d = self.dimension;
        self.dimension += 2;
        Vec2::new(self.sample_dimension(d), self.sample_dimension(d + 1))
    }

    /// The point's position in its pixel: dimensions 0 and 1 without the m bits that chose the
    /// pixel (unrandomised, as the pixel choice is).
    pub fn get_pixel_2d(&self) -> Vec2 {
        let m = self.log2_scale;
        let within = |v: u32| unit_from_bits(v.checked_shl(m).unwrap_or(0));
        Vec2::new(within(sobol_0(self.index)), within(sobol_1(self.index)))
    }
}

/// The inverse of the m × m block of dimension 1's generator matrix that maps index bits
/// m..2m to output bits 1..m (Gauss–Jordan elimination over GF(2)). The block is nonsingular
/// because aligned blocks of 4^m points are (0,2m,2)-nets: with the low bits (the pixel column)
/// fixed, the 2^m choices of the middle bits fill the column's 2^m rows.
fn inverse_of_mid_block(m: u32) -> [u32; 32] {
    let top = |a: u64| if m == 0 { 0 } else { sobol_1(a) >> (32 - m) };
    // Rows of (image, preimage): row j starts as (block · e_j, e_j).
    let mut rows: Vec<(u32, u32)> = (0..m).map(|j| (top(1u64 << (m + j)), 1u32 << j)).collect();
    let mut inverse = [0u32; 32];
    for k in 0..m as usize {
        let pivot =
            (k..rows.len()).find(|&r| rows[r].0 >> k & 1 == 1).expect("a (0,2)-sequence's block is nonsingular");
        rows.swap(k, pivot);
        let (image, pre) = rows[k];
        for (r, row) in rows.iter_mut().enumerate() {
            if r != k && row.0 >> k & 1 == 1 {
                *row = (row.0 ^ image, row.1 ^ pre);
            }
        }
    }
    for (k, row) in rows.iter().enumerate() {
        debug_assert_eq!(row.0, 1 << k);
        inverse[k] = row.1;
    }
    inverse
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The film coordinates of a pixel sample: pixel + position in the pixel, from the
    /// unscaled dimensions 0 and 1 of the sequence point (independent of `get_pixel_2d`).
    fn film(s: &GlobalSobol) -> (f64, f64) {
        let scale = f64::from(1u32 << s.log2_scale);
        let f = |v: u32| f64::from(v) / 2f64.powi(32) * scale;
        (f(sobol_0(s.index)), f(sobol_1(s.index)))
    }

    #[test]
    fn every_sample_lies_in_its_pixel() {
        for resolution in [(1, 1), (3, 1), (37, 21), (200, 120), (64, 64), (65, 9), (1000, 7)] {
            let mut s = GlobalSobol::new(Randomize::FastOwen, 5, resolution);
            for py in (0..resolution.1).step_by(3) {
                for px in (0..resolution.0).step_by(7) {
                    for i in [0u64, 1, 2, 7, 15, 16, 255, 100_000] {
                        s.start((px, py), i);
                        let (x, y) = film(&s);
                        assert!(
                            (x.floor(), y.floor()) == (f64::from(px), f64::from(py)),
                            "{resolution:?}: sample {i} of ({px}, {py}) at ({x}, {y})"
                        );
                        let u = s.get_pixel_2d();
                        let close = |a: f64, b: f32| (a.fract() - f64::from(b)).abs() < 1e-6;
                        assert!(close(x, u.x) && close(y, u.y), "{resolution:?} ({px}, {py}) {i}: {u}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_pixels_samples_are_the_sequences_points_in_it_in_order() {
        // A 5 × 3 image (grid 8 × 8): walk the sequence and collect each pixel's points.
        let mut s = GlobalSobol::new(Randomize::None, 0, (5, 3));
        let mut found = vec![vec![]; 64];
        for a in 0..64 * 8u64 {
            let cell = |v: u32| (v >> 29) as usize;
            found[cell(sobol_1(a)) * 8 + cell(sobol_0(a))].push(a);
        }
        for (p, indices) in found.iter().enumerate() {
            for (i, &a) in indices.iter().enumerate() {
                s.start(((p % 8) as u32, (p / 8) as u32), i as u64);
                assert_eq!(s.index, a, "pixel {p}, sample {i}");
            }
        }
    }

    #[test]
    fn a_pixels_first_samples_are_stratified_in_it() {
        // Within a pixel the sequence points are again a (0,2)-sequence's blocks: the first 2^k
        // samples put one in each elementary interval of area 2^-k of the pixel.
        let mut s = GlobalSobol::new(Randomize::Owen, 1, (300, 170));
        for pixel in [(0, 0), (299, 169), (123, 45)] {
            for k in 0..=8u32 {
                for shape in 0..=k {
                    let mut cells = vec![0u32; 1 << k];
                    for i in 0..1u64 << k {
                        s.start(pixel, i);
                        let u = s.get_pixel_2d();
                        let (nx, ny) = (1u32 << shape, 1u32 << (k - shape));
                        cells[((u.x * nx as f32) as u32 * ny + (u.y * ny as f32) as u32) as usize] += 1;
                    }
                    assert!(cells.iter().all(|&c| c == 1), "{pixel:?}: 2^{k} samples, shape {shape}");
                }
            }
        }
    }

    #[test]
    fn pixels_outside_the_grid_draw_points_of_their_own() {
        for (resolution, inside) in [((16, 16), (3, 15)), ((1, 1), (0, 0))] {
            let mut s = GlobalSobol::new(Randomize::None, 0, resolution);
            let mut draw = |p, i| {
                s.start(p, i);
                s.get_2d()
            };
            let inside = draw(inside, 0);
            assert_ne!(draw((3, u32::MAX), 0), inside, "{resolution:?}");
            assert_ne!(draw((3, u32::MAX), 0), draw((19, u32::MAX), 0), "{resolution:?}");
        }
    }
}

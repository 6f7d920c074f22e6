//! pbrt-v4's `HaltonSampler`: dimension d of sample i is the radical inverse of i in the d-th
//! prime base (Halton 1964). The image plane is covered by the first two dimensions: the
//! samples of a pixel are the points of the one global sequence that fall in it, found by
//! inverting the radical inverse of the pixel's coordinates and combining them with the Chinese
//! remainder theorem (Grünschloß, Raab & Keller 2012, "Enumerating quasi-Monte Carlo point
//! sequences in elementary intervals"). The other dimensions are randomised by random digit
//! permutations (Faure & Lemieux 2009) or Owen scrambling.

use super::scramble::{mix_bits, permutation_element, Randomize};
use glam::Vec2;
use std::sync::LazyLock;

/// Dimensions (prime bases) used before the dimension counter wraps back to 2.
pub const PRIME_TABLE_SIZE: usize = 1000;

/// The first [`PRIME_TABLE_SIZE`] primes (sieve of Eratosthenes).
static PRIMES: LazyLock<Vec<u32>> = LazyLock::new(|| {
    let limit = 8000; // the 1000th prime is 7919
    let mut composite = vec![false; limit];
    let mut primes = Vec::with_capacity(PRIME_TABLE_SIZE);
    for n in 2..limit {
        if !composite[n] {
            primes.push(n as u32);
            (n * n..limit).step_by(n).for_each(|k| composite[k] = true);
        }
    }
    primes.truncate(PRIME_TABLE_SIZE);
    primes
});

/// The pixel footprint of the first two dimensions is at most this many pixels on a side.
const MAX_HALTON_RESOLUTION: u32 = 128;

/// The sampler's settings and its place (pixel sample, dimension).
#[derive(Clone, Debug)]
pub struct Halton {
    randomize: Randomize,
    seed: u64,
    /// 2^j and 3^k: the first two dimensions' strata per pixel row and column repeat.
    base_scales: [u64; 2],
    base_exponents: [u32; 2],
    /// (3^k)⁻¹ mod 2^j and (2^j)⁻¹ mod 3^k.
    mult_inverse: [u64; 2],
    halton_index: u64,
    dimension: usize,
}

/// The radical inverse of `a` in `base`: its digits mirrored about the radix point.
pub fn radical_inverse(base: u32, mut a: u64) -> f32 {
    let b = u64::from(base);
    let (mut reversed, mut scale) = (0u64, 1.0f64);
    while a > 0 {
        reversed = reversed * b + a % b;
        scale /= b as f64;
        a /= b;
    }
    ((reversed as f64 * scale) as f32).min(ONE_MINUS_EPSILON)
}

/// The index whose first `digits` base-`base` digits mirrored give `inverse`: the inverse of
/// [`radical_inverse`] on numbers of `digits` digits.
fn inverse_radical_inverse(mut inverse: u64, base: u64, digits: u32) -> u64 {
    let mut index = 0;
    for _ in 0..digits {
        index = index * base + inverse % base;
        inverse /= base;
    }
    index
}

/// x with a·x ≡ 1 (mod n), for coprime a and n (extended Euclid).
fn multiplicative_inverse(a: u64, n: u64) -> u64 {
    let (mut r0, mut r1) = (a as i64, n as i64);
    let (mut s0, mut s1) = (1i64, 0i64);
    while r1 != 0 {
        let q = r0 / r1;
        (r0, r1) = (r1, r0 - q * r1);
        (s0, s1) = (s1, s0 - q * s1);
    }
    s0.rem_euclid(n as i64) as u64
}

/// Digits in base `base` that resolve 2^-24 (a float's precision).
fn digits_needed(base: u32) -> u32 {
    let (mut n, mut scale) = (0, 1u64);
    while scale < 1 << 24 {
        scale *= u64::from(base);
        n += 1;
    }
    n
}

/// The radical inverse of `a` in `base` with digit k replaced by `permute(k, prefix, digit)`
/// for every one of the digits a float resolves (zeros beyond `a`'s last digit too, so the
/// point moves anywhere in its stratum); `prefix` is the permuted digits before digit k.
fn permuted_radical_inverse(base: u32, mut a: u64, permute: impl Fn(u32, u64, u32) -> u32) -> f32 {
    let b = u64::from(base);
    let (mut reversed, mut scale) = (0u64, 1.0f64);
    for k in 0..digits_needed(base) {
        let digit = permute(k, reversed, (a % b) as u32);
        reversed = reversed * b + u64::from(digit);
        scale /= b as f64;
        a /= b;
    }
    ((reversed as f64 * scale) as f32).min(ONE_MINUS_EPSILON)
}

impl Halton {
    /// For an image of `resolution` pixels.
    pub fn new(randomize: Randomize, seed: u64, resolution: (u32, u32)) -> Self {
        let mut base_scales = [1u64; 2];
        let mut base_exponents = [0u32; 2];
        for (i, (base, res)) in [(2u64, resolution.0), (3, resolution.1)].into_iter().enumerate() {
            while base_scales[i] < u64::from(res.clamp(1, MAX_HALTON_RESOLUTION)) {
                base_scales[i] *= base;
                base_exponents[i] += 1;
            }
        }
        let mult_inverse = [
            multiplicative_inverse(base_scales[1], base_scales[0]),
            multiplicative_inverse(base_scales[0], base_scales[1]),
        ];
        Self { randomize, seed, base_scales, base_exponents, mult_inverse, halton_index: 0, dimension: 2 }
    }

    /// Positions the sampler at sample `index` of `pixel`: the index-th point of the global
    /// sequence inside the pixel (its footprint repeats every 2^j × 3^k pixels).
    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        let stride = self.base_scales[0] * self.base_scales[1];
        let mut offset = 0u64;
        if stride > 1 {
            let pm = [u64::from(pixel.0 % MAX_HALTON_RESOLUTION), u64::from(pixel.1 % MAX_HALTON_RESOLUTION)];
            for (i, (p, base)) in pm.into_iter().zip([2, 3]).enumerate() {
                let dim_offset = inverse_radical_inverse(p, base, self.base_exponents[i]);
                // Each term is ≡ dim_offset (mod its own base's scale) and ≡ 0 (mod the other's).
                let term =
                    (dim_offset as u128 * u128::from(stride / self.base_scales[i]) * u128::from(self.mult_inverse[i]))
                        % u128::from(stride);
                offset = (offset + term as u64) % stride;
            }
        }
        self.halton_index = offset + index * stride;
        self.dimension = 2;
    }

    /// Dimension `d` (≥ 2) of the current point, randomised.
    fn sample_dimension(&self, d: usize) -> f32 {
        let base = PRIMES[d];
        let a = self.halton_index;
        match self.randomize {
            Randomize::None => radical_inverse(base, a),
            // One random permutation per digit position and base, the same for every prefix.
            Randomize::PermuteDigits => {
                let dim_seed = mix_bits(u64::from(base) ^ self.seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
                permuted_radical_inverse(base, a, |k, _, digit| {
                    permutation_element(digit, base, mix_bits(dim_seed ^ u64::from(k)) as u32)
                })
            }
            // Nested: each digit's permutation chosen by the digits before it (Owen 1995).
            Randomize::Owen | Randomize::FastOwen => {
                let dim_seed = mix_bits((1 + ((d as u64) << 4)) ^ (self.seed << 32));
                permuted_radical_inverse(base, a, |k, prefix, digit| {
                    let h = mix_bits(dim_seed ^ mix_bits(prefix ^ u64::from(k) << 56));
                    permutation_element(digit, base, h as u32)
                })
            }
        }
    }

    pub fn get_1d(&mut self) -> f32 {
        if self.dimension >= PRIME_TABLE_SIZE {
            self.dimension = 2;
        }
        self.dimension += 1;
        self.sample_dimension(self.dimension - 1)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        if self.dimension + 1 >= PRIME_TABLE_SIZE {
            self.dimension = 2;
        }
        let d = self.dimension;
        self.dimension += 2;
        Vec2::new(self.sample_dimension(d), self.sample_dimension(d + 1))
    }

    /// The point's position in its pixel: dimensions 0 and 1 with the digits that chose the
    /// pixel removed (unrandomised, as the pixel choice is).
    pub fn get_pixel_2d(&self) -> Vec2 {
        Vec2::new(
            radical_inverse(2, self.halton_index >> self.base_exponents[0]),
            radical_inverse(3, self.halton_index / self.base_scales[1]),
        )
    }
}

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radical_inverses_of_known_indices() {
        // Base 2: 1 → .1 = ½, 6 = 110₂ → .011 = 3/8; base 3: 5 = 12₃ → .21₃ = 7/9;
        // base 5: 7 = 12₅ → .21₅ = 11/25.
        assert_eq!(radical_inverse(2, 1), 0.5);
        assert_eq!(radical_inverse(2, 6), 0.375);
        assert!((radical_inverse(3, 5) - 7.0 / 9.0).abs() < 1e-7);
        assert!((radical_inverse(5, 7) - 11.0 / 25.0).abs() < 1e-7);
        assert_eq!(radical_inverse(7, 0), 0.0);
        assert_eq!(&PRIMES[..6], &[2, 3, 5, 7, 11, 13]);
        assert_eq!(PRIMES[999], 7919);
        assert_eq!(multiplicative_inverse(27, 32), 19); // 27·19 = 513 = 16·32 + 1
    }

    #[test]
    fn a_pixels_samples_are_the_global_points_inside_it() {
        // For a 100×60 image: 2^7 = 128 columns and 3^4 = 81 rows of the first two dimensions.
        // Sample i of pixel (x, y) is a point of the unscrambled Halton sequence whose first
        // coordinate ·128 lies in [x, x+1) and second ·81 in [y, y+1), and its in-pixel
        // position is that fractional part.
        let mut s = Halton::new(Randomize::None, 0, (100, 60));
        for pixel in [(0u32, 0u32), (37, 11), (99, 59)] {
            let mut seen = std::collections::HashSet::new();
            for i in 0..8 {
                s.start(pixel, i);
                let a = s.halton_index;
                assert!(seen.insert(a));
                let (x, y) = (radical_inverse(2, a) as f64 * 128.0, radical_inverse(3, a) as f64 * 81.0);
                assert_eq!((x.floor() as u32, y.floor() as u32), pixel, "sample {i}");
                let p = s.get_pixel_2d();
                assert!((p.x as f64 - x.fract()).abs() < 1e-4 && (p.y as f64 - y.fract()).abs() < 1e-4);
                // Dimension 2 is base 5.
                assert_eq!(s.get_1d(), radical_inverse(5, a));
            }
        }
    }

    #[test]
    fn randomised_dimensions_stay_stratified_in_each_base() {
        // The first b^k points of a base-b radical inverse put one point in each stratum of
        // width b^-k; digit permutations and Owen scrambling keep that.
        for how in [Randomize::None, Randomize::PermuteDigits, Randomize::Owen] {
            let mut s = Halton::new(how, 5, (1, 1));
            for (dim, base, n) in [(2usize, 5u64, 25u64), (3, 7, 49), (10, 31, 31)] {
                let mut cells = vec![0; n as usize];
                for i in 0..n {
                    s.start((0, 0), i);
                    let u = s.sample_dimension(dim);
                    assert!((0.0..1.0).contains(&u));
                    // Unrandomised points sit on stratum edges k/n, which a float may round
                    // just below: a margin far below the randomised digits' resolution.
                    cells[(u as f64 * n as f64 + 1e-5) as usize] += 1;
                }
                assert!(cells.iter().all(|&c| c == 1), "{how:?} base {base}: {cells:?}");
            }
        }
    }
}

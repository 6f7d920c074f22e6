//! PCG32 random number generator (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
//! Statistically Good Algorithms for Random Number Generation"), XSH-RR output.

const MULT: u64 = 0x5851_f42d_4c95_7f2d;

/// A small, seedable, stream-splittable generator. Deterministic across platforms.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    inc: u64,
}

impl Rng {
    /// A generator for `seed` on stream `stream` (distinct streams are independent sequences).
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut r = Self { state: 0, inc: (stream << 1) | 1 };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    /// Next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1), never 1.
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        // 24 random mantissa bits: exactly representable, strictly below 1.
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// Uniform in [0, 1) as f64 (for tests and tables needing more resolution).
    #[inline]
    pub fn uniform_f64(&mut self) -> f64 {
        let hi = (self.next_u32() >> 5) as u64;
        let lo = (self.next_u32() >> 6) as u64;
        ((hi << 26) | lo) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Skips `delta` steps ahead in O(log delta) (Brown 1994, "Random number generation with
    /// arbitrary strides").
    pub fn advance(&mut self, mut delta: u64) {
        let (mut cur_mult, mut cur_plus) = (MULT, self.inc);
        let (mut acc_mult, mut acc_plus) = (1u64, 0u64);
        while delta > 0 {
            if delta & 1 == 1 {
                acc_mult = acc_mult.wrapping_mul(cur_mult);
                acc_plus = acc_plus.wrapping_mul(cur_mult).wrapping_add(cur_plus);
            }
            cur_plus = cur_mult.wrapping_add(1).wrapping_mul(cur_plus);
            cur_mult = cur_mult.wrapping_mul(cur_mult);
            delta >>= 1;
        }
        self.state = acc_mult.wrapping_mul(self.state).wrapping_add(acc_plus);
    }
}

/// 64-bit hash of a few integers (splitmix64 finaliser), for deterministic per-pixel seeds.
#[inline]
pub fn hash64(values: &[u64]) -> u64 {
    values.iter().fold(HASH64_START, |h, &v| hash64_step(h, v))
}

/// The state [`hash64`] starts from: `hash64(&[a, b])` = `hash64_step(hash64_step(HASH64_START, a), b)`.
pub const HASH64_START: u64 = 0x9e37_79b9_7f4a_7c15;

/// Mixes one more value into a [`hash64`] state (to reuse the state of a common prefix).
#[inline]
pub fn hash64_step(mut h: u64, v: u64) -> u64 {
    h ^= v.wrapping_add(0x9e37_79b9_7f4a_7c15).wrapping_add(h << 6).wrapping_add(h >> 2);
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^ (h >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_is_in_unit_interval_with_right_mean_and_variance() {
        let mut r = Rng::new(7, 3);
        let n = 200_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let u = r.uniform();
            assert!((0.0..1.0).contains(&u));
            s += u as f64;
            s2 += (u * u) as f64;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        // Standard error of the mean of U(0,1) is sqrt(1/12/n) ≈ 6.5e-4; allow 4σ.
        assert!((mean - 0.5).abs() < 4.0 * (1.0 / 12.0 / n as f64).sqrt(), "{mean}");
        assert!((var - 1.0 / 12.0).abs() < 2e-3, "{var}");
    }

    #[test]
    fn advance_matches_stepping() {
        let mut a = Rng::new(42, 1);
        let mut b = a.clone();
        for _ in 0..1000 {
            a.next_u32();
        }
        b.advance(1000);
        assert_eq!(a.next_u32(), b.next_u32());
    }

    #[test]
    fn streams_differ() {
        let mut a = Rng::new(1, 1);
        let mut b = Rng::new(1, 2);
        let same = (0..64).filter(|_| a.next_u32() == b.next_u32()).count();
        assert!(same < 4);
    }
}

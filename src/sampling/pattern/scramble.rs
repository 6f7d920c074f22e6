//! The randomisations of base-2 digit sequences pbrt-v4's samplers choose between
//! (`"randomization"`), the index permutation of Kensler (2013) and the bit mixer they hash with.

use crate::named::name_table;

/// How a sampler randomises its low-discrepancy points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Randomize {
    /// The points as the sequence defines them.
    None,
    /// A random permutation of each digit's values, the same for every prefix (in base 2: an
    /// XOR with a random word; Kollig & Keller 2002, "Efficient multidimensional sampling").
    PermuteDigits,
    /// Owen scrambling approximated by a hash of the reversed bits (Laine & Karras 2011,
    /// "Stratified sampling for stochastic transparency", with Burley 2020's constants).
    FastOwen,
    /// Nested uniform scrambling (Owen 1995): each digit's permutation depends on all
    /// digits before it.
    Owen,
}

name_table!(Randomize, "randomization", {
    "none" => Randomize::None,
    "permutedigits" => Randomize::PermuteDigits,
    "fastowen" => Randomize::FastOwen,
    "owen" => Randomize::Owen,
});

/// A 64-bit finaliser: every input bit affects every output bit (splitmix64's, Steele, Lea &
/// Flood 2014, "Fast splittable pseudorandom number generators").
#[inline]
pub fn mix_bits(mut v: u64) -> u64 {
    v = (v ^ (v >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    v = (v ^ (v >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    v ^ (v >> 31)
}

/// Element `i` of a random permutation of 0..`l` chosen by `p`, without building it
/// (Kensler 2013, "Correlated multi-jittered sampling", §3: a hash that is a bijection on the
/// next power of two, cycle-walked until it lands below `l`). `i` < `l`.
pub fn permutation_element(mut i: u32, l: u32, p: u32) -> u32 {
    debug_assert!(i < l);
    let mut w = l.wrapping_sub(1);
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            return ((i as u64 + p as u64) % l as u64) as u32;
        }
    }
}

/// The 32-bit fraction `v` (bit 31 = ½) randomised by `how` with the random word `seed`.
#[inline]
pub fn scramble_base2(v: u32, how: Randomize, seed: u32) -> u32 {
    match how {
        Randomize::None => v,
        Randomize::PermuteDigits => v ^ seed,
        Randomize::FastOwen => sobol_burley::parts::owen_scramble_rev(v.reverse_bits(), seed).reverse_bits(),
        Randomize::Owen => owen_scramble(v, seed),
    }
}

/// [`scramble_base2`] of the fraction whose bits reversed are `v_rev` (bit 0 = ½): the same
/// value, with the two reversals of the hash-based Owen scramble (which works on reversed bits)
/// left out.
#[inline]
pub fn scramble_base2_rev(v_rev: u32, how: Randomize, seed: u32) -> u32 {
    match how {
        Randomize::FastOwen => sobol_burley::parts::owen_scramble_rev(v_rev, seed).reverse_bits(),
        _ => scramble_base2(v_rev.reverse_bits(), how, seed),
    }
}

/// Nested uniform scrambling of the 32-bit fraction `v`: bit 31 − b is flipped when a hash of
/// `seed` and the b bits above it says so, so points that share a prefix share its flips.
fn owen_scramble(v: u32, seed: u32) -> u32 {
    let mut out = v;
    for b in 0..32u32 {
        let prefix = if b == 0 { 0 } else { v >> (32 - b) };
        let h = mix_bits(u64::from(seed) << 32 ^ u64::from(prefix) << 5 ^ u64::from(b));
        out ^= ((h & 1) as u32) << (31 - b);
    }
    out
}

/// The 32-bit fraction `v` as a float in [0, 1) (24 bits, rounded down: never 1).
#[inline]
pub fn unit_from_bits(v: u32) -> f32 {
    (v >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scrambling_reversed_bits_gives_the_same_value() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..20_000 {
            x = mix_bits(x);
            let (v, seed) = (x as u32, (x >> 32) as u32);
            for how in [Randomize::None, Randomize::PermuteDigits, Randomize::FastOwen, Randomize::Owen] {
                assert_eq!(
                    scramble_base2_rev(v.reverse_bits(), how, seed),
                    scramble_base2(v, how, seed),
                    "{how:?} {v} {seed}"
                );
            }
        }
    }

    #[test]
    fn permutation_element_is_a_permutation_for_any_length_and_seed() {
        for l in [1u32, 2, 3, 5, 16, 17, 100, 1024] {
            for p in [0u32, 1, 0xdead_beef, u32::MAX] {
                let mut seen = vec![false; l as usize];
                for i in 0..l {
                    let j = permutation_element(i, l, p);
                    assert!(j < l && !seen[j as usize], "l {l} p {p}: {i} → {j} twice or out of range");
                    seen[j as usize] = true;
                }
            }
        }
        // Different seeds give different orders.
        let order = |p| (0..64).map(|i| permutation_element(i, 64, p)).collect::<Vec<_>>();
        assert_ne!(order(1), order(2));
    }

    #[test]
    fn every_scramble_is_a_bijection_that_keeps_dyadic_intervals_together() {
        // A base-2 scramble maps each dyadic interval [k/2^m, (k+1)/2^m) onto one such
        // interval: so the 2^8 values k·2^24 (one per interval of length 2^-8) map to 2^8
        // distinct intervals, and values sharing their top 8 bits stay together.
        for how in [Randomize::None, Randomize::PermuteDigits, Randomize::FastOwen, Randomize::Owen] {
            for seed in [0u32, 7, 0x1234_5678] {
                let mut hit = [false; 256];
                for k in 0..256u32 {
                    let a = scramble_base2(k << 24, how, seed) >> 24;
                    let b = scramble_base2(k << 24 | 0x00ff_ffff, how, seed) >> 24;
                    assert_eq!(a, b, "{how:?}: interval {k} split");
                    assert!(!hit[a as usize], "{how:?}: two intervals onto {a}");
                    hit[a as usize] = true;
                }
            }
        }
        assert!(unit_from_bits(u32::MAX) < 1.0 && unit_from_bits(0) == 0.0);
    }
}

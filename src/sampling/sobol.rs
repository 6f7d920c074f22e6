//! `sobol_burley::sample_4d` for dimension set 0 (the only one the padded sampler uses), with the
//! Sobol matrix–vector product replaced by two table lookups.
//!
//! The padded sampler shuffles the sample index per group, so the index is a random 16-bit
//! number and the crate's bit-by-bit product (one XOR per set bit, ~8 per call, a serial chain)
//! was most of the sampler's cost. The product is linear over GF(2): sobol(a ⊕ b) = sobol(a) ⊕
//! sobol(b), so it splits into the index's two bytes, each looked up in a 256-entry table (8 KiB,
//! L1-resident). Everything else is the crate's own building blocks (its scalar hash and scramble,
//! lane by lane, where the crate's `Int4` emulates 32-bit multiplies on SSE2), in the crate's
//! order, so the values are bit-identical (tested for both compiled variants).

use std::sync::LazyLock;

use multiversion::multiversion;
use sobol_burley::parts::{hash, owen_scramble_rev, sobol_int4_rev};

/// Sobol points of dimensions 0–3 (bit-reversed) for each value of the reversed index's top byte
/// (`hi`) and next byte (`lo`).
struct Tables {
    hi: [[u32; 4]; 256],
    lo: [[u32; 4]; 256],
}

static TABLES: LazyLock<Tables> = LazyLock::new(|| {
    let mut t = Tables { hi: [[0; 4]; 256], lo: [[0; 4]; 256] };
    for b in 0..256u32 {
        t.hi[b as usize] = sobol_int4_rev(b << 24, 0).into();
        t.lo[b as usize] = sobol_int4_rev(b << 16, 0).into();
    }
    t
});

/// Equals `sobol_burley::sample_4d(sample_index, 0, seed)` with `index_rev` =
/// `sample_index.reverse_bits()` (a sampler draws several groups for one index, so it reverses
/// it once): dimensions 0–3 of the Owen-scrambled Sobol point `sample_index` (< 2¹⁶) of the
/// sequence seeded by `seed`, in [0, 1).
///
/// The four lanes' hash and scramble are 32-bit multiplies, which baseline x86-64 (SSE2) has
/// only as two 64-bit halves and shuffles; SSE4.1's `pmulld` does them in one instruction and
/// SSSE3's byte shuffle reverses the bits. So the group is compiled for both and the variant
/// picked once at run time (`multiversion`, as the obvhs queries are): the same integer
/// operations, so the same bits.
#[multiversion(targets("x86_64+sse4.1+ssse3"))]
pub fn sample_4d_rev(index_rev: u32, seed: u32) -> [f32; 4] {
    group(index_rev, seed)
}

/// [`sample_4d_rev`], inlined into each variant.
#[inline(always)]
fn group(index_rev: u32, seed: u32) -> [f32; 4] {
    let rev = owen_scramble_rev(index_rev, hash(seed ^ 0x79c68e4a));
    let t = &*TABLES;
    let (a, b) = (t.hi[(rev >> 24) as usize], t.lo[((rev >> 16) & 0xff) as usize]);
    let sobol: [u32; 4] = std::array::from_fn(|i| a[i] ^ b[i]);
    // The crate's scramble for dimension set 0.
    let dims = [0x912f69ba, 0x174f18ab, 0x691e72ca, 0xb40cc1b8];
    let scramble = dims.map(|d| hash(seed.wrapping_mul(0x9c8f2d3b) ^ d));
    std::array::from_fn(|i| {
        let n = owen_scramble_rev(sobol[i], scramble[i]).reverse_bits();
        f32::from_bits((n >> 9) | 0x3f80_0000) - 1.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn both_variants_equal_the_crates_sample_4d_bit_for_bit() {
        let mut rng = Rng::new(3, 9);
        let mut cases: Vec<(u32, u32)> = (0..200_000).map(|_| (rng.next_u32() & 0xffff, rng.next_u32())).collect();
        cases.extend([(0, 0), (0xffff, 0), (1, u32::MAX), (0x8000, 12345)]);
        for (i, s) in cases {
            // The variant this CPU runs, and the baseline one (compiled for the crate's target).
            let expect = sobol_burley::sample_4d(i, 0, s).map(f32::to_bits);
            assert_eq!(sample_4d_rev(i.reverse_bits(), s).map(f32::to_bits), expect, "{i} {s}");
            assert_eq!(group(i.reverse_bits(), s).map(f32::to_bits), expect, "{i} {s}");
        }
    }
}

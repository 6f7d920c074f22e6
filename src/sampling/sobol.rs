//! `sobol_burley::sample_4d` for dimension set 0 (the only one the padded sampler uses), with the
//! Sobol matrix–vector product replaced by two table lookups.
//!
//! The padded sampler shuffles the sample index per group, so the index is a random 16-bit
//! number and the crate's bit-by-bit product (one XOR per set bit, ~8 per call, a serial chain)
//! was most of the sampler's cost. The product is linear over GF(2): sobol(a ⊕ b) = sobol(a) ⊕
//! sobol(b), so it splits into the index's two bytes, each looked up in a 256-entry table (8 KiB,
//! L1-resident). Everything else is the crate's own building blocks, in the crate's order, so the
//! values are bit-identical (tested).

use std::sync::LazyLock;

use sobol_burley::parts::{hash, hash_int4, owen_scramble_int4_rev, owen_scramble_rev, sobol_int4_rev, Int4};

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
#[inline]
pub fn sample_4d_rev(index_rev: u32, seed: u32) -> [f32; 4] {
    let rev = owen_scramble_rev(index_rev, hash(seed ^ 0x79c68e4a));
    let t = &*TABLES;
    let (a, b) = (t.hi[(rev >> 24) as usize], t.lo[((rev >> 16) & 0xff) as usize]);
    let sobol: Int4 = [a[0] ^ b[0], a[1] ^ b[1], a[2] ^ b[2], a[3] ^ b[3]].into();
    // The crate's scramble for dimension set 0.
    let scramble: Int4 = [seed.wrapping_mul(0x9c8f2d3b); 4].into();
    let scramble = scramble ^ [0x912f69ba, 0x174f18ab, 0x691e72ca, 0xb40cc1b8].into();
    owen_scramble_int4_rev(sobol, hash_int4(scramble)).reverse_bits().to_f32_norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn equals_the_crates_sample_4d_bit_for_bit() {
        let mut rng = Rng::new(3, 9);
        let mut cases: Vec<(u32, u32)> = (0..200_000).map(|_| (rng.next_u32() & 0xffff, rng.next_u32())).collect();
        cases.extend([(0, 0), (0xffff, 0), (1, u32::MAX), (0x8000, 12345)]);
        for (i, s) in cases {
            assert_eq!(
                sample_4d_rev(i.reverse_bits(), s).map(f32::to_bits),
                sobol_burley::sample_4d(i, 0, s).map(f32::to_bits),
                "{i} {s}"
            );
        }
    }
}

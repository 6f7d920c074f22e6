//! The Sobol' generator matrices of all of `sobol_burley`'s dimensions (Joe & Kuo 2008's
//! direction numbers, "Constructing Sobol sequences with better two-dimensional projections"),
//! extended from the crate's 16 columns (indices below 2¹⁶) to 64 (any `u64` index).
//!
//! Column j of dimension d is the direction number v_{j+1} = m_{j+1} / 2^{j+1} as a 32-bit
//! fraction. Every dimension but the first follows Sobol's recurrence for a primitive
//! polynomial x^s + a_1 x^{s−1} + … + a_{s−1} x + 1 (Bratley & Fox 1988, eq. 2):
//! v_j = a_1 v_{j−1} ⊕ … ⊕ a_{s−1} v_{j−s+1} ⊕ v_{j−s} ⊕ v_{j−s} / 2^s.
//! The crate keeps only the columns, so the degree s and the coefficients a_k are read back
//! from them: the columns are triangular (v_j's lowest set bit has weight 2^{−(j+1)}), so the
//! equation for v_s determines the a_k by elimination from the lowest bit up; the smallest s
//! whose recurrence also reproduces every later column is the polynomial's degree. The
//! recurrence is exact in truncated 32-bit fractions (⌊x/2^s⌋ = ⌊⌊x⌋/2^s⌋), so the extended
//! columns are those of the full-precision construction.

use std::sync::LazyLock;

use sobol_burley::NUM_DIMENSIONS;

/// Sobol' dimensions available; pbrt-v4's table holds 1024.
pub const DIMENSIONS: usize = NUM_DIMENSIONS as usize;
/// Columns per generator matrix: index bits.
const COLUMNS: usize = 64;
/// Columns the crate stores.
const CRATE_COLUMNS: usize = 16;

/// `MATRICES[d][j]`: column j of dimension d's generator matrix.
static MATRICES: LazyLock<Vec<[u32; COLUMNS]>> = LazyLock::new(|| {
    (0..DIMENSIONS)
        .map(|d| {
            if d == 0 {
                // The van der Corput sequence: the identity, bits past 32 vanish.
                return std::array::from_fn(|j| 1u32.checked_shl(31u32.wrapping_sub(j as u32)).unwrap_or(0));
            }
            let known: [u32; CRATE_COLUMNS] = std::array::from_fn(|j| {
                sobol_burley::parts::sobol_rev((1u32 << j).reverse_bits(), d as u32).reverse_bits()
            });
            extend(&known).unwrap_or_else(|| panic!("Sobol' dimension {d}: no primitive-polynomial recurrence"))
        })
        .collect()
});

/// Column j of a dimension from the s before it, for the coefficients `a` (bit k set: a_k = 1).
fn recur(v: &[u32], j: usize, s: usize, a: u32) -> u32 {
    let mut next = v[j - s] ^ (v[j - s] >> s);
    for k in 1..s {
        if a >> k & 1 == 1 {
            next ^= v[j - k];
        }
    }
    next
}

/// The 64 columns of the dimension whose first columns are `known`, or `None` when no
/// recurrence of degree below `known.len()` − 2 reproduces them (at least three equations
/// check each candidate).
fn extend(known: &[u32]) -> Option<[u32; COLUMNS]> {
    let n = known.len();
    let (s, a) = (1..n - 2).find_map(|s| {
        // v_s ⊕ v_0 ⊕ v_0/2^s = Σ a_k v_{s−k}: eliminate from the lowest bit up.
        let mut rest = known[s] ^ known[0] ^ (known[0] >> s);
        let mut a = 0u32;
        for j in (1..s).rev() {
            if rest >> (31 - j) & 1 == 1 {
                rest ^= known[j];
                a |= 1 << (s - j);
            }
        }
        (rest == 0 && (s + 1..n).all(|j| recur(known, j, s, a) == known[j])).then_some((s, a))
    })?;
    let mut v = [0u32; COLUMNS];
    v[..n].copy_from_slice(known);
    for j in n..COLUMNS {
        v[j] = recur(&v, j, s, a);
    }
    Some(v)
}

/// Dimension `d` (< [`DIMENSIONS`]) of Sobol' point `a` as a 32-bit fraction (bit 31 = ½).
#[inline]
pub fn sobol_bits(mut a: u64, d: usize) -> u32 {
    let columns = &MATRICES[d];
    let mut v = 0;
    while a != 0 {
        v ^= columns[a.trailing_zeros() as usize];
        a &= a - 1;
    }
    v
}

#[cfg(test)]
mod tests {
    use super::super::sobol2d::{sobol_0, sobol_1};
    use super::*;

    /// Lines of Joe & Kuo's new-joe-kuo-6 table: dimension (1-based), s, a, m_1 … m_s.
    const JOE_KUO: [(usize, usize, u32, &[u128]); 5] = [
        (3, 2, 1, &[1, 3]),
        (7, 4, 4, &[1, 3, 5, 13]),
        (101, 9, 253, &[1, 3, 3, 7, 29, 37, 33, 123, 147]),
        (200, 11, 227, &[1, 3, 1, 3, 29, 25, 21, 155, 11, 191, 197]),
        (256, 11, 560, &[1, 1, 1, 5, 19, 3, 53, 133, 97, 863, 983]),
    ];

    #[test]
    fn extended_columns_are_joe_and_kuos_direction_numbers() {
        // The integer form of the recurrence (Bratley & Fox 1988, eq. 3):
        // m_k = 2a_1 m_{k−1} ⊕ 4a_2 m_{k−2} ⊕ … ⊕ 2^s m_{k−s} ⊕ m_{k−s}, in exact integers.
        for (dim, s, a, init) in JOE_KUO {
            let mut m: Vec<u128> = init.to_vec();
            for k in s..COLUMNS {
                let mut next = m[k - s] << s ^ m[k - s];
                for i in 1..s {
                    if a >> (s - 1 - i) & 1 == 1 {
                        next ^= m[k - i] << i;
                    }
                }
                m.push(next);
            }
            for (j, &mj) in m.iter().enumerate() {
                // v_{j+1} = m_{j+1} / 2^{j+1}, truncated to 32 bits.
                let expect = if j < 32 { (mj << (31 - j)) as u32 } else { (mj >> (j - 31)) as u32 };
                assert_eq!(sobol_bits(1 << j, dim - 1), expect, "dimension {dim}, column {j}");
            }
        }
    }

    #[test]
    fn the_first_two_dimensions_are_the_closed_forms() {
        for a in [0u64, 1, 5, 0xffff, 1 << 20 | 77, 0xdead_beef_1234, u64::MAX >> 1] {
            assert_eq!(sobol_bits(a, 0), sobol_0(a), "{a}");
            assert_eq!(sobol_bits(a, 1), sobol_1(a), "{a}");
        }
    }

    #[test]
    fn every_dimension_is_a_0_m_1_sequence_far_into_the_index() {
        // Each aligned block of 2^m points puts one point in each interval of length 2^-m: so
        // the extended columns stay a nonsingular triangle.
        for d in 0..DIMENSIONS {
            for start in [0u64, 1 << 20, 3 << 40] {
                let m = 10;
                let mut seen = vec![false; 1 << m];
                for a in start..start + (1 << m) {
                    let cell = (sobol_bits(a, d) >> (32 - m)) as usize;
                    assert!(!seen[cell], "dimension {d}, block at {start}");
                    seen[cell] = true;
                }
            }
        }
    }

    #[test]
    fn a_broken_column_is_detected() {
        let mut known: [u32; CRATE_COLUMNS] = std::array::from_fn(|j| sobol_bits(1 << j, 40));
        assert_eq!(extend(&known).map(|v| v[..CRATE_COLUMNS] == known), Some(true));
        known[14] ^= 1 << 25;
        assert_eq!(extend(&known), None);
    }
}

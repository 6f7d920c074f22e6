//! Dimensions 0 and 1 of the Sobol' sequence for indices of any size: their generator matrices
//! are the identity (van der Corput) and Pascal's triangle mod 2, so no direction-number table is
//! needed (Sobol' 1967; Joe & Kuo 2008 list the same first two dimensions). Together they form a
//! (0,2)-sequence in base 2: every block of 2^m consecutive points aligned at a multiple of 2^m
//! puts one point in each elementary interval of area 2^-m.

/// Column j of dimension 1's generator matrix as a 32-bit fraction: output bit i (weight
/// 2^-(i+1)) is binom(j, i) mod 2, which by Lucas' theorem is 1 exactly when the bits of i are a
/// subset of those of j.
const PASCAL: [u32; 64] = {
    let mut c = [0u32; 64];
    let mut j = 0;
    while j < 64 {
        let mut i = 0;
        while i < 32 {
            if i & j == i {
                c[j] |= 1 << (31 - i);
            }
            i += 1;
        }
        j += 1;
    }
    c
};

/// Dimension 0 of Sobol' point `a` as a 32-bit fraction: the bits of `a` mirrored about the
/// binary point (the van der Corput sequence; bits of `a` above 31 do not reach 32 bits).
#[inline]
pub fn sobol_0(a: u64) -> u32 {
    (a as u32).reverse_bits()
}

/// Dimension 1's points, bits reversed, for each value of each of the index's eight bytes: the
/// generator matrix is linear over GF(2), so point `a` is the XOR of the points of its bytes,
/// each one lookup (8 KiB, L1-resident) instead of one XOR per set bit of `a`.
static BYTE_COLUMNS_REV: [[u32; 256]; 8] = {
    let mut t = [[0u32; 256]; 8];
    let mut k = 0;
    while k < 8 {
        let mut b = 0;
        while b < 256 {
            let mut v = 0;
            let mut i = 0;
            while i < 8 {
                if b >> i & 1 == 1 {
                    v ^= PASCAL[8 * k + i];
                }
                i += 1;
            }
            t[k][b] = v.reverse_bits();
            b += 1;
        }
        k += 1;
    }
    t
};

/// Dimension 1 of Sobol' point `a` as a 32-bit fraction.
#[inline]
pub fn sobol_1(a: u64) -> u32 {
    sobol_1_rev(a).reverse_bits()
}

/// [`sobol_0`] with its bits reversed (bit 0 = ½): the index's low 32 bits.
#[inline]
pub fn sobol_0_rev(a: u64) -> u32 {
    a as u32
}

/// [`sobol_1`] with its bits reversed (bit 0 = ½).
#[inline]
pub fn sobol_1_rev(a: u64) -> u32 {
    let mut v = 0;
    for (k, column) in BYTE_COLUMNS_REV.iter().enumerate() {
        v ^= column[(a >> (8 * k)) as usize & 0xff];
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_points_are_sobols() {
        // Sobol' (1967) / Joe & Kuo: direction numbers of dimension 1 are m = 1, 3, 5, 15, 17, 51:
        // v_j = m_j / 2^j.
        let m = [1u32, 3, 5, 15, 17, 51];
        for (j, mj) in m.iter().enumerate() {
            assert_eq!(sobol_1(1 << j), mj << (31 - j), "column {j}");
        }
        // Points 0..4 of the 2D sequence: (0,0), (½,½), (¼,¾), (¾,¼).
        let p = |a| (sobol_0(a) as f64 / 2f64.powi(32), sobol_1(a) as f64 / 2f64.powi(32));
        assert_eq!([p(0), p(1), p(2), p(3)], [(0.0, 0.0), (0.5, 0.5), (0.25, 0.75), (0.75, 0.25)]);
    }

    #[test]
    fn the_byte_tables_sum_the_columns_of_the_set_bits() {
        let by_bits = |a: u64| (0..64).filter(|j| a >> j & 1 == 1).fold(0, |v, j| v ^ PASCAL[j]);
        let mut a = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..10_000 {
            a = a.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            for x in [a, a >> 20, a >> 40, a & 0xffff] {
                assert_eq!(sobol_1(x), by_bits(x), "{x}");
            }
        }
        assert_eq!(sobol_1(u64::MAX), by_bits(u64::MAX));
    }

    #[test]
    fn aligned_blocks_are_0_m_2_nets_far_into_the_sequence() {
        // Each elementary interval 2^-i × 2^-(m-i) holds exactly one of the 2^m points.
        for start in [0u64, 1 << 20, 0xdead_0000, 3 << 40] {
            let m = 8;
            for i in 0..=m {
                let mut cells = vec![0u32; 1 << m];
                for a in start..start + (1 << m) {
                    let (x, y) = ((sobol_0(a) as u64) >> (32 - i), (sobol_1(a) as u64) >> (32 - (m - i)));
                    cells[(x << (m - i) | y) as usize] += 1;
                }
                assert!(cells.iter().all(|&c| c == 1), "start {start}, shape {i}");
            }
        }
    }
}

//! Perlin's improved gradient noise (Perlin 2002, "Improving Noise", SIGGRAPH): a lattice of
//! pseudo-random gradients chosen by hashing the integer cell corner through a permutation of
//! 0..256, blended with the quintic fade 6t⁵ − 15t⁴ + 10t³ so the second derivative is
//! continuous across cells. The value is 0 at every lattice point and lies in about [−1, 1].

use crate::math::floor;
use glam::Vec3;

/// The permutation of 0..256 of Perlin's reference implementation (pbrt-v4 uses the same one, so
/// prism's noise patterns match pbrt-v4's).
const PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69, 142, 8, 99, 37, 240,
    21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88,
    237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83,
    111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216,
    80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173, 186,
    3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17,
    182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129,
    22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238,
    210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184,
    84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195,
    78, 66, 215, 61, 156, 180,
];

/// The permutation extended periodically, so hashes of corners up to 511 need no wrapping.
fn perm(i: usize) -> usize {
    PERMUTATION[i & 255] as usize
}

/// Perlin's fade curve 6t⁵ − 15t⁴ + 10t³: 0 and 1 at the ends with zero first and second
/// derivatives there.
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The dot product of the offset (x, y, z) from a lattice corner with one of the 12 edge
/// directions of a cube, (±1, ±1, 0) and its permutations, chosen by the low 4 bits of `hash`.
/// The paper maps the 16 hashes onto the 12 directions by repeating four of them; for hashes
/// 12–15 this is pbrt-v4's assignment ((1,1,0), (−1,1,0), (0,1,−1), (0,−1,−1)), which differs
/// from the paper's listing for 13 and 14, so that prism's noise patterns are pbrt-v4's.
/// Looked up in a table rather than chosen by branches on the (random) hash.
#[inline]
fn gradient(hash: usize, x: f32, y: f32, z: f32) -> f32 {
    let [gx, gy, gz] = GRADIENTS[hash & 15];
    (gx * x + gy * y) + gz * z
}

/// The direction of each hash: for h < 12 bit 2–3 pick the plane ((x, y), (x, z), (y, z)) and
/// bits 0 and 1 the signs; 12–15 repeat four of them.
const GRADIENTS: [[f32; 3]; 16] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
];

/// Improved noise at `p`: 0 on the integer lattice, smooth elsewhere, range about [−1, 1].
pub fn noise(p: Vec3) -> f32 {
    // Reduce large coordinates so the integer cell fits an i32 (the noise has period 256).
    let reduce = |x: f32| {
        const PERIOD: f32 = (1u32 << 30) as f32;
        if x.abs() < PERIOD {
            x
        } else {
            x % PERIOD
        }
    };
    let (x, y, z) = (reduce(p.x), reduce(p.y), reduce(p.z));
    let (fx, fy, fz) = (floor(x), floor(y), floor(z));
    let (dx, dy, dz) = (x - fx, y - fy, z - fz);
    let (ix, iy, iz) = ((fx as i32 & 255) as usize, (fy as i32 & 255) as usize, (fz as i32 & 255) as usize);
    let corner = |i: usize, j: usize, k: usize| {
        let h = perm(perm(perm(ix + i) + iy + j) + iz + k);
        gradient(h, dx - i as f32, dy - j as f32, dz - k as f32)
    };
    let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
    let (u, v, w) = (fade(dx), fade(dy), fade(dz));
    let x00 = lerp(u, corner(0, 0, 0), corner(1, 0, 0));
    let x10 = lerp(u, corner(0, 1, 0), corner(1, 1, 0));
    let x01 = lerp(u, corner(0, 0, 1), corner(1, 0, 1));
    let x11 = lerp(u, corner(0, 1, 1), corner(1, 1, 1));
    lerp(w, lerp(v, x00, x10), lerp(v, x01, x11))
}

/// Noise in the plane z = ½ (pbrt-v4's two-argument `Noise(x, y)`).
pub fn noise_2d(x: f32, y: f32) -> f32 {
    noise(Vec3::new(x, y, 0.5))
}

#[cfg(test)]
mod tests {
    /// The gradient table against Perlin's branch form (u, v chosen by the hash's bits) with
    /// pbrt-v4's assignment of hashes 12–15.
    #[test]
    fn gradient_table_is_the_branch_form() {
        let branches = |h: usize, x: f32, y: f32, z: f32| {
            let low = h == 12 || h == 13;
            let u = if h < 8 || low { x } else { y };
            let v = if h < 4 || low { y } else { z };
            (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
        };
        for h in 0..16 {
            for (x, y, z) in [(0.3f32, -0.7f32, 0.11f32), (-0.9, 0.25, 0.6), (0.5, 0.5, -0.5)] {
                assert_eq!(super::gradient(h, x, y, z), branches(h, x, y, z), "hash {h}");
            }
        }
    }

    use super::*;

    #[test]
    fn the_permutation_is_a_permutation() {
        let mut seen = [false; 256];
        for &v in &PERMUTATION {
            assert!(!seen[v as usize], "{v} repeats");
            seen[v as usize] = true;
        }
    }

    #[test]
    fn noise_is_zero_on_the_lattice() {
        for &(x, y, z) in &[(0, 0, 0), (1, 2, 3), (-5, 7, 100), (255, 256, -1), (1000, -3000, 17)] {
            let n = noise(Vec3::new(x as f32, y as f32, z as f32));
            assert_eq!(n, 0.0, "noise({x}, {y}, {z}) = {n}");
        }
    }

    #[test]
    fn noise_matches_a_value_worked_by_hand() {
        // At (½, ½, ½) every fade weight is ½, so the value is the mean of the eight corner
        // terms. Corner (i, j, k) has hash P[P[P[i] + j] + k] (P the permutation) and offset
        // d = (½ − i, ½ − j, ½ − k). From the table: P[0] = 151, P[1] = 160, P[151] = 17,
        // P[152] = 182, P[160] = 119, P[161] = 248, P[17] = 36, P[18] = 103, P[182] = 108,
        // P[183] = 110, P[119] = 86, P[120] = 164, P[248] = 128, P[249] = 195. Low 4 bits
        // and gradient terms:
        //   (0,0,0):  36 → 4  =  x + z =  ½ + ½ =  1
        //   (0,0,1): 103 → 7  = −x − z = −½ + ½ =  0
        //   (0,1,0): 108 → 12 =  x + y =  ½ − ½ =  0
        //   (0,1,1): 110 → 14 =  y − z = −½ + ½ =  0
        //   (1,0,0):  86 → 6  =  x − z = −½ − ½ = −1
        //   (1,0,1): 164 → 4  =  x + z = −½ − ½ = −1
        //   (1,1,0): 128 → 0  =  x + y = −½ − ½ = −1
        //   (1,1,1): 195 → 3  = −x − y =  ½ + ½ =  1
        // Sum −1, mean −⅛.
        let n = noise(Vec3::splat(0.5));
        assert!((n + 0.125).abs() < 1e-6, "{n}");
    }

    #[test]
    fn noise_stays_in_range_and_has_zero_mean() {
        let (mut lo, mut hi, mut sum) = (f32::MAX, f32::MIN, 0.0f64);
        let n = 200_000;
        let mut s = 12345u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32 * 64.0 - 32.0
        };
        for _ in 0..n {
            let v = noise(Vec3::new(next(), next(), next()));
            lo = lo.min(v);
            hi = hi.max(v);
            sum += v as f64;
        }
        // Gradient noise with the 12 cube-edge gradients is bounded by 1 in magnitude in
        // practice (the analytic bound is larger but not approached); it spans most of it.
        assert!(lo >= -1.05 && hi <= 1.05, "range [{lo}, {hi}]");
        assert!(lo < -0.6 && hi > 0.6, "range [{lo}, {hi}] is too narrow");
        // Every gradient has an opposite, so the mean is 0; sd ≈ 0.2, so 4σ of the mean is ~0.002.
        assert!((sum / n as f64).abs() < 0.003, "mean {}", sum / n as f64);
    }

    #[test]
    fn noise_is_continuous_across_cell_faces() {
        for &x in &[1.0f32, 7.0, -3.0] {
            let a = noise(Vec3::new(x - 1e-4, 0.3, 0.7));
            let b = noise(Vec3::new(x + 1e-4, 0.3, 0.7));
            assert!((a - b).abs() < 1e-3, "{a} vs {b}");
        }
    }
}

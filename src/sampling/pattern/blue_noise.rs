//! Blue-noise textures: per-pixel values in [0, 1) whose neighbours differ, so that offsets
//! read from them spread a pixel's error over the image as high-frequency noise (as pbrt-v4's
//! `BlueNoise(textureIndex, pixel)`: 48 textures of 128 × 128 pixels, tiled).
//!
//! Each texture ranks the pixels of the 128 × 128 torus by best-candidate sampling (Mitchell
//! 1991, "Spectrally optimal sampling for distribution ray tracing"): pixel r of the ranking is
//! the one, of a few random free pixels, farthest from the r before it, so every prefix is
//! spread evenly; a pixel's value is its rank's stratum, (r + ½)/128². Built once per process,
//! each texture when first read.

use super::torus_grid::TorusGrid;
use crate::sampling::Rng;
use std::sync::OnceLock;

/// Pixels per side.
pub const RESOLUTION: usize = 128;
/// Textures, indexed modulo their number.
const TEXTURES: usize = 48;
/// Free pixels compared per rank.
const CANDIDATES: usize = 16;

static TEXTURE: [OnceLock<Vec<f32>>; TEXTURES] = [const { OnceLock::new() }; TEXTURES];

/// The value of `pixel` (tiled) in texture `index` (modulo 48), in [0, 1).
pub fn blue_noise(index: u64, pixel: (u32, u32)) -> f32 {
    let t = TEXTURE[(index % TEXTURES as u64) as usize].get_or_init(|| texture(index % TEXTURES as u64));
    t[(pixel.1 as usize % RESOLUTION) * RESOLUTION + pixel.0 as usize % RESOLUTION]
}

/// Energy kernel of a placed pixel (Ulichney 1993's void-and-cluster: a Gaussian of σ = 1.5
/// pixels), cut off at this radius in pixels.
const KERNEL_RADIUS: i32 = 5;

/// Texture `index`, row-major.
fn texture(index: u64) -> Vec<f32> {
    let side = RESOLUTION as i32;
    let n = RESOLUTION * RESOLUTION;
    let mut rng = Rng::new(0x6e6f_6973_6562_6c75 ^ index, index);
    let mut free: Vec<u32> = (0..n as u32).collect();
    let mut grid = TorusGrid::new();
    // The centre of pixel i in 32-bit fixed point (units of 2^-32).
    let shift = 32 - RESOLUTION.trailing_zeros();
    let centre = |i: u32| {
        let (x, y) = (i % RESOLUTION as u32, i / RESOLUTION as u32);
        [x << shift | 1 << (shift - 1), y << shift | 1 << (shift - 1)]
    };
    let kernel: Vec<f32> = (-KERNEL_RADIUS..=KERNEL_RADIUS)
        .flat_map(|j| (-KERNEL_RADIUS..=KERNEL_RADIUS).map(move |i| (-((i * i + j * j) as f32) / 4.5).exp()))
        .collect();
    // The placed pixels' summed kernels at each pixel: it tells apart the candidates once the
    // distances to the nearest placed pixel are a few whole pixels and tie.
    let mut energy = vec![0.0f32; n];
    let mut value = vec![0.0; n];
    for rank in 0..n {
        let score = |s: usize| {
            let p = free[s];
            (grid.nearest_distance_squared(centre(p)), std::cmp::Reverse(energy[p as usize].to_bits()))
        };
        let slot = (0..CANDIDATES.min(free.len()))
            .map(|_| rng.next_u32() as usize % free.len())
            .max_by_key(|&s| score(s))
            .expect("a free pixel remains");
        let pixel = free.swap_remove(slot);
        grid.insert(centre(pixel));
        let (px, py) = ((pixel as usize % RESOLUTION) as i32, (pixel as usize / RESOLUTION) as i32);
        let width = 2 * KERNEL_RADIUS + 1;
        for (k, w) in kernel.iter().enumerate() {
            let (i, j) = (k as i32 % width - KERNEL_RADIUS, k as i32 / width - KERNEL_RADIUS);
            energy[((py + j).rem_euclid(side) * side + (px + i).rem_euclid(side)) as usize] += w;
        }
        value[pixel as usize] = (rank as f32 + 0.5) / n as f32;
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The variance of the means of the 4 × 4 blocks of a texture: its power at low
    /// frequencies.
    fn block_mean_variance(t: &[f32]) -> f64 {
        let b = RESOLUTION / 4;
        let means: Vec<f64> = (0..b * b)
            .map(|k| {
                let (bx, by) = (k % b * 4, k / b * 4);
                (0..16).map(|i| f64::from(t[(by + i / 4) * RESOLUTION + bx + i % 4])).sum::<f64>() / 16.0
            })
            .collect();
        let m = means.iter().sum::<f64>() / means.len() as f64;
        means.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (means.len() - 1) as f64
    }

    #[test]
    fn textures_hold_every_stratum_once_with_little_low_frequency_power() {
        let n = RESOLUTION * RESOLUTION;
        for index in [0, 1, 47] {
            let t: Vec<f32> =
                (0..n).map(|i| blue_noise(index, ((i % RESOLUTION) as u32, (i / RESOLUTION) as u32))).collect();
            let mut ranks: Vec<usize> = t.iter().map(|&v| (v * n as f32) as usize).collect();
            ranks.sort_unstable();
            assert!(ranks.iter().enumerate().all(|(i, &r)| i == r), "texture {index}: not one value per stratum");
            // White noise (the same values shuffled) gives 4 × 4 block means of variance
            // (1/12)/16 ≈ 0.0052; spread-out ranks cancel within a block. Measured: ≈ 0.0007
            // for these textures; the bound 0.0026 lies a factor 2 below white noise's.
            let v = block_mean_variance(&t);
            assert!(v < 0.0026, "texture {index}: block-mean variance {v}");
            let mut shuffled = t.clone();
            let mut rng = Rng::new(7, index);
            for i in (1..n).rev() {
                shuffled.swap(i, rng.next_u32() as usize % (i + 1));
            }
            let white = block_mean_variance(&shuffled);
            assert!(white > 0.0026, "shuffled texture {index}: {white}");
        }
        assert_eq!(blue_noise(0, (3, 5)), blue_noise(48, (3 + 128, 5 + 256)));
        assert_ne!(blue_noise(0, (3, 5)), blue_noise(1, (3, 5)));
    }
}

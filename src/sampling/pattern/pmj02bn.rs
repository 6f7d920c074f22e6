//! pbrt-v4's `PMJ02BNSampler`: 2D draws take point `index` of one of [`SETS`] blue-noise
//! pmj02 sequences shared by all pixels ([`super::pmj02`]), toroidally shifted per pixel and
//! dimension (Cranley & Patterson 1976) by blue-noise offsets ([`super::blue_noise`]); past the
//! sets the index is permuted per pixel. Film positions are the points of the first sequence's
//! 4^8 (or more) points, scaled over a tile of pixels: each pixel of the tile takes, in
//! sequence order, the points falling in it. 1D draws are strata of a random permutation of
//! the pixel's samples, offset by blue noise.

use super::blue_noise::blue_noise;
use super::padded_sobol::{permuted_index, pixel_dimension_hash};
use super::pmj02::pmj02bn;
use super::scramble::{mix_bits, unit_from_bits};
use glam::Vec2;
use std::collections::HashMap;
use std::sync::{Arc, LazyLock, Mutex};

/// Independent sequences a sampler draws its 2D dimensions from (as pbrt-v4).
const SETS: u64 = 5;

/// Points of the first sequence laid over the film tile (as pbrt-v4's tables: 4^8).
const FILM_POINTS: usize = 1 << 16;

/// What a sampler reads, for one (samples per pixel, seed).
#[derive(Debug)]
struct Tables {
    /// The [`SETS`] sequences, the first of [`FILM_POINTS`] points or more, the others of the
    /// samples per pixel rounded up to a power of two.
    sets: Vec<Vec<Vec2>>,
    /// Pixels per side of the film tile.
    tile: u32,
    /// The film positions of each pixel of the tile (row-major), samples-per-pixel each.
    film: Vec<Vec2>,
}

impl Tables {
    fn new(spp: u32, seed: u64) -> Self {
        // The power of 4 at or above spp: the points a tile pixel holds in the first sequence.
        let pow4 = 1usize << (2 * spp.next_power_of_two().trailing_zeros().div_ceil(2));
        let first = FILM_POINTS.max(pow4);
        let tile_bits = (first / pow4).trailing_zeros() / 2;
        let sequences: Vec<Vec<[u32; 2]>> = (0..SETS)
            .map(|s| pmj02bn(if s == 0 { first } else { spp.next_power_of_two() as usize }, mix_bits(seed ^ s)))
            .collect();
        // A point's pixel in the tile is its top tile_bits bits per axis, its position in the
        // pixel the bits below (exact in fixed point).
        let tile = 1u32 << tile_bits;
        let spp = spp as usize;
        let mut film = vec![Vec2::ZERO; (tile * tile) as usize * spp];
        let mut stored = vec![0usize; (tile * tile) as usize];
        let split = |v: u32| if tile_bits == 0 { (0, v) } else { (v >> (32 - tile_bits), v << tile_bits) };
        for p in &sequences[0] {
            let ((x, fx), (y, fy)) = (split(p[0]), split(p[1]));
            let pixel = (y * tile + x) as usize;
            if stored[pixel] < spp {
                film[pixel * spp + stored[pixel]] = Vec2::new(unit_from_bits(fx), unit_from_bits(fy));
                stored[pixel] += 1;
            }
        }
        debug_assert!(stored.iter().all(|&s| s == spp));
        let sets = sequences
            .iter()
            .map(|s| s.iter().map(|p| Vec2::new(unit_from_bits(p[0]), unit_from_bits(p[1]))).collect())
            .collect();
        Self { sets, tile, film }
    }
}

/// The tables of each (samples per pixel, seed).
type TableCache = Mutex<HashMap<(u32, u64), Arc<Tables>>>;

/// The tables, built once per process.
static TABLES: LazyLock<TableCache> = LazyLock::new(Default::default);

/// pbrt-v4's `PMJ02BNSampler`, positioned at a pixel sample (see the module's description).
#[derive(Clone, Debug)]
pub struct Pmj02bn {
    spp: u32,
    seed: u64,
    tables: Arc<Tables>,
    pixel: (u32, u32),
    index: u64,
    dimension: u64,
}

impl Pmj02bn {
    /// For `spp` samples per pixel.
    pub fn new(seed: u64, spp: u64) -> Self {
        let spp = spp.clamp(1, 1 << 20) as u32;
        let tables = {
            let mut cache = TABLES.lock().unwrap_or_else(|e| e.into_inner());
            cache.entry((spp, seed)).or_insert_with(|| Arc::new(Tables::new(spp, seed))).clone()
        };
        Self { spp, seed, tables, pixel: (0, 0), index: 0, dimension: 0 }
    }

    /// Positions the sampler at sample `index` of `pixel`; dimensions 0 and 1 are the film
    /// position's, so draws start at 2 (as pbrt-v4).
    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        (self.pixel, self.index, self.dimension) = (pixel, index, 2);
    }

    /// The film position: the pixel's point `index` in the tile (indices past the samples per
    /// pixel, a render extended later, wrap).
    pub fn get_pixel_2d(&self) -> Vec2 {
        let t = self.tables.tile;
        let pixel = (self.pixel.1 % t * t + self.pixel.0 % t) as u64;
        self.tables.film[(pixel * u64::from(self.spp) + self.index % u64::from(self.spp)) as usize]
    }

    pub fn get_1d(&mut self) -> f32 {
        let hash = pixel_dimension_hash(self.pixel, self.dimension, self.seed);
        let stratum = permuted_index(self.index, self.spp, hash) % u64::from(self.spp);
        let delta = blue_noise(self.dimension, self.pixel);
        self.dimension += 1;
        ((stratum as f32 + delta) / self.spp as f32).min(ONE_MINUS_EPSILON)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let instance = self.dimension / 2;
        let mut index = self.index;
        if instance >= SETS {
            index = permuted_index(self.index, self.spp, pixel_dimension_hash(self.pixel, self.dimension, self.seed));
        }
        let set = &self.tables.sets[(instance % SETS) as usize];
        // Indices past the sequence (a render extended later) wrap.
        let u = set[(index % set.len() as u64) as usize];
        let shift = Vec2::new(blue_noise(self.dimension, self.pixel), blue_noise(self.dimension + 1, self.pixel));
        let v = u + shift;
        let wrap = |x: f32| if x >= 1.0 { x - 1.0 } else { x };
        self.dimension += 2;
        Vec2::new(wrap(v.x).min(ONE_MINUS_EPSILON), wrap(v.y).min(ONE_MINUS_EPSILON))
    }
}

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixels_film_positions_are_a_0_2_net_and_the_tile_covers_the_first_sequence() {
        // 16 samples: a 64 × 64 tile of pixels, each holding the 16 points of the first
        // sequence's 65536 that fall in it; scaled to the pixel they are a (0,4,2)-net (the
        // pixel is an elementary interval of the 65536-point net).
        let mut s = Pmj02bn::new(9, 16);
        assert_eq!(s.tables.tile, 64);
        for pixel in [(0, 0), (3, 4), (63, 17)] {
            let mut points = Vec::new();
            for i in 0..16 {
                s.start(pixel, i);
                points.push(s.get_pixel_2d());
            }
            for k in 0..=4 {
                let (nx, ny) = (1usize << k, 16 >> k);
                let mut cells = [0; 16];
                points.iter().for_each(|p| cells[(p.x * nx as f32) as usize * ny + (p.y * ny as f32) as usize] += 1);
                assert!(cells.iter().all(|&c| c == 1), "pixel {pixel:?}, shape {nx}×{ny}: {cells:?}");
            }
            // The tile repeats.
            s.start((pixel.0 + 64, pixel.1 + 128), 5);
            assert_eq!(s.get_pixel_2d(), points[5]);
        }
        // 8 samples (not a power of 4): each pixel keeps the first 8 of its 16.
        let s8 = Pmj02bn::new(9, 8);
        assert_eq!(s8.tables.tile, 64);
    }

    #[test]
    fn the_samplers_2d_draws_keep_the_net_shifted_on_the_torus() {
        // A toroidal shift moves a net's points together: the x projections of 16 points stay
        // one per shifted stratum [k/16 + s, (k+1)/16 + s).
        let mut s = Pmj02bn::new(9, 16);
        let mut xs = Vec::new();
        for i in 0..16 {
            s.start((3, 4), i);
            xs.push(s.get_2d().x);
        }
        let shift = blue_noise(2, (3, 4));
        let mut strata = [0; 16];
        for x in xs {
            strata[(((x - shift).rem_euclid(1.0)) * 16.0) as usize % 16] += 1;
        }
        assert!(strata.iter().all(|&c| c == 1), "{strata:?}");
    }
}

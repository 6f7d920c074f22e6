//! Progressive multi-jittered (0,2) sequences (Christensen, Kensler & Kilpatrick 2018,
//! "Progressive multi-jittered sample sequences", §5) and pbrt-v4's `PMJ02BNSampler` on them.
//!
//! The sequence is built point by point: point m goes where no earlier point is in any
//! elementary interval of area 1/n, n the power of two above m, so every prefix of 2^k points
//! is a (0,k,2)-net (one point per elementary interval of area 2^-k, in every shape) and hence
//! stratified in both 1D projections. Each point is a random pair of unoccupied fine strata
//! (1/n wide in x and y) whose cells of every shape are free, jittered inside.

use super::padded_sobol::{permuted_index, pixel_dimension_hash};
use super::scramble::mix_bits;
use crate::sampling::Rng;
use glam::Vec2;
use std::collections::HashMap;
use std::sync::{Arc, LazyLock, Mutex};

/// Independent sequences a sampler draws its 2D dimensions from (as pbrt-v4).
const SETS: u64 = 5;

/// The first `n` points of a pmj02 sequence drawn with `rng`, as 32-bit fractions; `None`
/// when the random choices leave no free cell (the caller starts again with other choices).
fn try_pmj02(n: usize, rng: &mut Rng) -> Option<Vec<[u32; 2]>> {
    let mut points: Vec<[u32; 2]> = Vec::with_capacity(n);
    let mut level = 0u32;
    // occupied[k][cell]: shape k has 2^k columns and 2^(level-k) rows.
    let mut occupied: Vec<Vec<bool>> = vec![vec![false; 1]];
    let fine = |v: u32, bits: u32| if bits == 0 { 0 } else { (v >> (32 - bits)) as usize };
    while points.len() < n {
        let m = points.len();
        if m == 1 << level {
            // The prefix is a full net: the next points must also keep the 2m-point net.
            level += 1;
            occupied = (0..=level).map(|_| vec![false; 1 << level]).collect();
            for p in &points {
                for (k, occ) in occupied.iter_mut().enumerate() {
                    occ[fine(p[0], k as u32) << (level - k as u32) | fine(p[1], level - k as u32)] = true;
                }
            }
        }
        let size = 1usize << level;
        // Free columns and rows of the finest 1D strata, in random order.
        let shuffled = |free: Vec<usize>, rng: &mut Rng| {
            let mut v = free;
            for i in (1..v.len()).rev() {
                v.swap(i, (rng.next_u32() as usize) % (i + 1));
            }
            v
        };
        let xs = shuffled((0..size).filter(|&x| !occupied[level as usize][x]).collect(), rng);
        let ys = shuffled((0..size).filter(|&y| !occupied[0][y]).collect(), rng);
        let cell = |k: u32, x: usize, y: usize| (x >> (level - k)) << (level - k) | (y >> k);
        let found = xs.iter().find_map(|&x| {
            ys.iter().find(|&&y| (0..=level).all(|k| !occupied[k as usize][cell(k, x, y)])).map(|&y| (x, y))
        })?;
        for (k, occ) in occupied.iter_mut().enumerate() {
            occ[cell(k as u32, found.0, found.1)] = true;
        }
        let jitter = |stratum: usize, rng: &mut Rng| {
            let width = 32 - level;
            let inside = if width == 32 { rng.next_u32() } else { rng.next_u32() >> level };
            ((stratum as u64) << width) as u32 | inside
        };
        let p = [jitter(found.0, rng), jitter(found.1, rng)];
        points.push(p);
    }
    Some(points)
}

/// The first `n` points of the pmj02 sequence for `seed`, in [0, 1)².
pub fn pmj02(n: usize, seed: u64) -> Vec<Vec2> {
    let mut attempt = 0u64;
    loop {
        let mut rng = Rng::new(seed, attempt);
        if let Some(points) = try_pmj02(n, &mut rng) {
            return points.iter().map(|p| Vec2::new(unit(p[0]), unit(p[1]))).collect();
        }
        attempt += 1;
    }
}

fn unit(v: u32) -> f32 {
    super::scramble::unit_from_bits(v)
}

/// The [`SETS`] sequences of one sampler.
type Sets = Arc<Vec<Vec<Vec2>>>;

/// The sequences of each (length, seed), built once per process.
static SEQUENCES: LazyLock<Mutex<HashMap<(u64, u64), Sets>>> = LazyLock::new(Default::default);

/// pbrt-v4's `PMJ02BNSampler`: 2D draws take point `index` of one of [`SETS`] pmj02 sequences
/// shared by all pixels, toroidally shifted per pixel and dimension (Cranley & Patterson 1976);
/// beyond the sets the index is permuted per pixel. 1D draws are jittered strata of a random
/// permutation of the pixel's samples.
#[derive(Clone, Debug)]
pub struct Pmj02bn {
    spp: u32,
    seed: u64,
    sets: Sets,
    pixel: (u32, u32),
    index: u64,
    dimension: u64,
}

impl Pmj02bn {
    /// For `spp` samples per pixel.
    pub fn new(seed: u64, spp: u64) -> Self {
        let spp32 = spp.clamp(1, 1 << 20) as u32;
        let sets = {
            let mut cache = SEQUENCES.lock().unwrap_or_else(|e| e.into_inner());
            let len = (spp32 as usize).next_power_of_two();
            cache
                .entry((len as u64, seed))
                .or_insert_with(|| Arc::new((0..SETS).map(|s| pmj02(len, mix_bits(seed ^ s))).collect()))
                .clone()
        };
        Self { spp: spp32, seed, sets, pixel: (0, 0), index: 0, dimension: 0 }
    }

    /// Positions the sampler at sample `index` of `pixel`; dimensions 0 and 1 are the film
    /// position's, so draws start at 2 (as pbrt-v4).
    pub fn start(&mut self, pixel: (u32, u32), index: u64) {
        (self.pixel, self.index, self.dimension) = (pixel, index, 2);
    }

    /// The film position: point `index` of the first sequence, shifted per pixel.
    pub fn get_pixel_2d(&self) -> Vec2 {
        self.point(0, self.index, 0)
    }

    /// Point `index` of sequence `set`, toroidally shifted by the offsets of dimensions
    /// `dimension` and `dimension` + 1.
    fn point(&self, set: u64, index: u64, dimension: u64) -> Vec2 {
        let set = &self.sets[(set % SETS) as usize];
        // Indices past the sequence (a render extended later) wrap.
        let u = set[(index % set.len() as u64) as usize];
        let v = u + Vec2::new(self.shift(dimension), self.shift(dimension + 1));
        let wrap = |x: f32| if x >= 1.0 { x - 1.0 } else { x };
        Vec2::new(wrap(v.x).min(ONE_MINUS_EPSILON), wrap(v.y).min(ONE_MINUS_EPSILON))
    }

    /// A uniform random offset per pixel and dimension.
    fn shift(&self, dimension: u64) -> f32 {
        let h = pixel_dimension_hash(self.pixel, dimension, self.seed ^ 0x5851_f42d_4c95_7f2d);
        unit((h >> 32) as u32)
    }

    pub fn get_1d(&mut self) -> f32 {
        let hash = pixel_dimension_hash(self.pixel, self.dimension, self.seed);
        let stratum = permuted_index(self.index, self.spp, hash) % u64::from(self.spp);
        let delta = self.shift(self.dimension);
        self.dimension += 1;
        ((stratum as f32 + delta) / self.spp as f32).min(ONE_MINUS_EPSILON)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let instance = self.dimension / 2;
        let mut index = self.index;
        if instance >= SETS {
            index = permuted_index(self.index, self.spp, pixel_dimension_hash(self.pixel, self.dimension, self.seed));
        }
        let u = self.point(instance, index, self.dimension);
        self.dimension += 2;
        u
    }
}

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    /// Every elementary interval of area 1/n (all shapes 2^k × n/2^k) holds exactly one of the
    /// n points.
    fn is_0_m_2_net(points: &[Vec2]) -> bool {
        let n = points.len();
        let m = n.trailing_zeros();
        (0..=m).all(|k| {
            let (nx, ny) = (1usize << k, n >> k);
            let mut cells = vec![0; n];
            for p in points {
                cells[(p.x as f64 * nx as f64) as usize * ny + (p.y as f64 * ny as f64) as usize] += 1;
            }
            cells.iter().all(|&c| c == 1)
        })
    }

    #[test]
    fn every_power_of_two_prefix_is_a_0_m_2_net() {
        for seed in [1u64, 2, 3] {
            let points = pmj02(1024, seed);
            for k in 0..=10 {
                assert!(is_0_m_2_net(&points[..1 << k]), "seed {seed}, prefix 2^{k}");
            }
            assert!(points.iter().all(|p| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)));
        }
        assert_ne!(pmj02(16, 1), pmj02(16, 2));
    }

    #[test]
    fn the_samplers_first_dimensions_keep_the_net_shifted_on_the_torus() {
        // A toroidal shift moves a net's points together; the 1D projections of 16 points stay
        // one per 1/16 stratum after the shift (elementary intervals 1×1/16 and 1/16×1 shift onto
        // intervals that straddle at most two strata, but the x projections remain a shifted
        // lattice of strata: each shifted stratum [k/16 + s, (k+1)/16 + s) holds one point).
        let mut s = Pmj02bn::new(9, 16);
        let mut xs = Vec::new();
        for i in 0..16 {
            s.start((3, 4), i);
            xs.push(s.get_pixel_2d().x);
        }
        let shift = s.shift(0);
        let mut strata = vec![0; 16];
        for x in xs {
            strata[(((x - shift).rem_euclid(1.0)) * 16.0) as usize % 16] += 1;
        }
        assert!(strata.iter().all(|&c| c == 1), "{strata:?}");
    }
}

//! Progressive multi-jittered (0,2) sequences (Christensen, Kensler & Kilpatrick 2018,
//! "Progressive multi-jittered sample sequences", §5), plain and with the blue-noise selection
//! of their pmj02bn (§6: each new point the best of several valid candidates, the one farthest
//! from the points already placed, Mitchell 1991's best-candidate sampling).
//!
//! The sequence is built point by point: point m goes where no earlier point is in any
//! elementary interval of area 1/n, n the power of two above m, so every prefix of 2^k points
//! is a (0,k,2)-net (one point per elementary interval of area 2^-k, in every shape) and hence
//! stratified in both 1D projections. A candidate is a random free column of the finest 1D
//! strata (1/n wide) and a row found by descending the rows' binary tree, each level's half
//! taken only where the elementary interval of that shape is free (the search of Pharr 2019,
//! "Efficient generation of points that satisfy two-dimensional elementary intervals"),
//! jittered inside the cell.

use super::torus_grid::TorusGrid;
use crate::sampling::Rng;

/// Valid candidates compared per point of the blue-noise variant.
pub const BLUE_NOISE_CANDIDATES: usize = 8;

/// The elementary intervals of area 2^-`level` that hold a point: `shapes[k]` has 2^k columns
/// and 2^(level-k) rows, cell (column, row) at column·2^(level-k) + row.
struct Occupied {
    level: u32,
    shapes: Vec<Vec<bool>>,
}

impl Occupied {
    /// The intervals of area 2^-`level` holding `points`.
    fn new(level: u32, points: &[[u32; 2]]) -> Self {
        let mut o = Self { level, shapes: (0..=level).map(|_| vec![false; 1 << level]).collect() };
        for p in points {
            o.insert(fine(p[0], level), fine(p[1], level));
        }
        o
    }

    /// The index in shape `k` of the interval holding fine cell (`x`, `y`).
    fn cell(&self, k: u32, x: usize, y: usize) -> usize {
        (x >> (self.level - k)) << (self.level - k) | y >> k
    }

    fn insert(&mut self, x: usize, y: usize) {
        for k in 0..=self.level {
            let c = self.cell(k, x, y);
            self.shapes[k as usize][c] = true;
        }
    }

    /// A fine row `y` such that (`x`, `y`) lies in no occupied interval, `x` a free column;
    /// `order` picks which half is tried first at each level of the descent.
    fn free_row(&self, x: usize, order: u64) -> Option<usize> {
        self.descend(x, 0, 0, order)
    }

    /// Below `prefix`, the top `depth` bits of the row: shape level−depth−1 decides the next bit.
    fn descend(&self, x: usize, depth: u32, prefix: usize, order: u64) -> Option<usize> {
        if depth == self.level {
            return Some(prefix);
        }
        let k = self.level - depth - 1;
        let first = (order >> (depth % 64)) as usize & 1;
        [first, first ^ 1].into_iter().find_map(|bit| {
            let row = prefix << 1 | bit;
            let free = !self.shapes[k as usize][(x >> (depth + 1)) << (depth + 1) | row];
            if free {
                self.descend(x, depth + 1, row, order.rotate_left(7) ^ row as u64)
            } else {
                None
            }
        })
    }
}

/// The fine stratum (of 2^`bits`) of a 32-bit fraction.
fn fine(v: u32, bits: u32) -> usize {
    if bits == 0 {
        0
    } else {
        (v >> (32 - bits)) as usize
    }
}

/// The first `n` points of a pmj02 sequence drawn with `rng`, as 32-bit fractions, each the
/// farthest (on the torus) of up to `candidates` valid positions from the points before it;
/// `None` when the random choices leave a column with no valid cell (the caller starts again
/// with other choices).
fn try_pmj02(n: usize, candidates: usize, rng: &mut Rng) -> Option<Vec<[u32; 2]>> {
    let mut points: Vec<[u32; 2]> = Vec::with_capacity(n);
    let mut grid = TorusGrid::new();
    let mut occupied = Occupied::new(0, &[]);
    let mut free_columns = vec![0usize];
    while points.len() < n {
        if points.len() == 1 << occupied.level {
            // The prefix is a full net: the next points must also keep the 2m-point net.
            occupied = Occupied::new(occupied.level + 1, &points);
            let last = &occupied.shapes[occupied.level as usize];
            free_columns = (0..last.len()).filter(|&x| !last[x]).collect();
        }
        let level = occupied.level;
        let jitter = |stratum: usize, rng: &mut Rng| {
            let inside = if level == 0 { rng.next_u32() } else { rng.next_u32() >> level };
            ((stratum as u64) << (32 - level)) as u32 | inside
        };
        // (point, its column's place in free_columns, squared distance to the nearest point)
        let mut best: Option<([u32; 2], usize, u64)> = None;
        for tried in 0..free_columns.len().min(candidates) {
            // A column not tried yet, at random (a partial Fisher–Yates shuffle).
            let pick = tried + (rng.next_u32() as usize) % (free_columns.len() - tried);
            free_columns.swap(tried, pick);
            let x = free_columns[tried];
            let order = u64::from(rng.next_u32()) << 32 | u64::from(rng.next_u32());
            // Every column holds a point once the level is complete: one that cannot never will.
            let y = occupied.free_row(x, order)?;
            let p = [jitter(x, rng), jitter(y, rng)];
            let distance = if candidates == 1 { 0 } else { grid.nearest_distance_squared(p) };
            if best.is_none_or(|(_, _, d)| distance > d) {
                best = Some((p, tried, distance));
            }
        }
        let (p, slot, _) = best?;
        occupied.insert(fine(p[0], level), fine(p[1], level));
        free_columns.swap_remove(slot);
        grid.insert(p);
        points.push(p);
    }
    Some(points)
}

/// The first `n` points of the sequence for `seed` comparing `candidates` per point, as 32-bit
/// fractions.
fn sequence(n: usize, candidates: usize, seed: u64) -> Vec<[u32; 2]> {
    (0u64..)
        .find_map(|attempt| try_pmj02(n, candidates, &mut Rng::new(seed, attempt)))
        .expect("some attempt completes the sequence")
}

/// The first `n` points of the blue-noise pmj02bn sequence for `seed`, as 32-bit fractions.
pub fn pmj02bn(n: usize, seed: u64) -> Vec<[u32; 2]> {
    sequence(n, BLUE_NOISE_CANDIDATES, seed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::pattern::scramble::unit_from_bits;
    use glam::Vec2;

    fn to_unit(points: &[[u32; 2]]) -> Vec<Vec2> {
        points.iter().map(|p| Vec2::new(unit_from_bits(p[0]), unit_from_bits(p[1]))).collect()
    }

    /// The plain pmj02 sequence: each point a random valid position.
    fn pmj02(n: usize, seed: u64) -> Vec<Vec2> {
        to_unit(&sequence(n, 1, seed))
    }

    fn pmj02bn(n: usize, seed: u64) -> Vec<Vec2> {
        to_unit(&super::pmj02bn(n, seed))
    }

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
            for points in [pmj02(1024, seed), pmj02bn(4096, seed)] {
                for k in 0..=points.len().trailing_zeros() {
                    assert!(is_0_m_2_net(&points[..1 << k]), "seed {seed}, prefix 2^{k}");
                }
                assert!(points.iter().all(|p| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)));
            }
        }
        assert_ne!(pmj02(16, 1), pmj02(16, 2));
        assert_ne!(pmj02bn(16, 1), pmj02bn(16, 2));
    }

    /// The mean over the points of the toroidal distance to the nearest other point, by brute
    /// force (independent of the generator's grid).
    fn mean_nearest_distance(points: &[Vec2]) -> f64 {
        let d = |a: f32, b: f32| {
            let t = (f64::from(a) - f64::from(b)).abs();
            t.min(1.0 - t)
        };
        let nearest = |i: usize| {
            (0..points.len())
                .filter(|&j| j != i)
                .map(|j| d(points[i].x, points[j].x).hypot(d(points[i].y, points[j].y)))
                .fold(f64::INFINITY, f64::min)
        };
        (0..points.len()).map(nearest).sum::<f64>() / points.len() as f64
    }

    #[test]
    fn blue_noise_prefixes_keep_their_points_farther_apart_than_plain_pmj02() {
        // The mean distance to the nearest other point, in units of 1/√n (the spacing of n
        // points), over prefixes of 384 and 768 points (between powers of two: the full
        // 2^k-point nets of both are equally constrained and about equally spaced, 0.63–0.66).
        // Measured over seeds 1..=10: plain pmj02 0.62–0.66, pmj02bn 0.70–0.74 (the standard
        // deviation over seeds is ≈ 0.012 for either). The bound 0.68 sits between.
        for seed in 11..=14 {
            let (plain, blue) = (pmj02(768, seed), pmj02bn(768, seed));
            for n in [384, 768] {
                let scale = (n as f64).sqrt();
                let plain = mean_nearest_distance(&plain[..n]) * scale;
                let blue = mean_nearest_distance(&blue[..n]) * scale;
                assert!(plain < 0.68, "seed {seed}, {n} points: pmj02 {plain}");
                assert!(blue > 0.68, "seed {seed}, {n} points: pmj02bn {blue}");
            }
        }
    }
}

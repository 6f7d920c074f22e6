//! The grid over stochastic progressive photon mapping's visible points (PBR 3rd ed. §16.2.5):
//! a uniform grid over their search spheres' bounds, cells about one largest radius wide,
//! hashed into as many buckets as there are points (Teschner et al. 2003, "Optimized spatial
//! hashing for collision detection of deformable objects"). Each point is listed in the bucket
//! of every cell its sphere's bounding box overlaps, so a photon meets every point whose sphere
//! may hold it in its own cell's bucket. Built serially, in point order: a bucket lists its
//! points in index order, whatever the thread count.

use glam::{IVec3, Vec3};

/// Largest number of cells along an axis (keeps cell coordinates and their hash in range).
const MAX_RESOLUTION: f32 = (1 << 20) as f32;

/// Visible points by grid cell, in buckets stored back to back.
#[derive(Debug, Default)]
pub struct VisiblePointGrid {
    /// The grid's lower corner [scene units].
    lo: Vec3,
    /// Cells per scene unit along each axis.
    scale: Vec3,
    /// Cells along each axis.
    res: IVec3,
    /// Bucket `b` holds `items[start[b]..start[b + 1]]`.
    start: Vec<u32>,
    /// The points' indices, bucket by bucket.
    items: Vec<u32>,
}

impl VisiblePointGrid {
    /// The grid over `points`: (index, position, search radius) each, radii positive.
    pub fn new(points: &[(u32, Vec3, f32)]) -> Self {
        if points.is_empty() {
            return Self::default();
        }
        let (mut lo, mut hi, mut max_radius) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY), 0f32);
        for &(_, p, r) in points {
            lo = lo.min(p - r);
            hi = hi.max(p + r);
            max_radius = max_radius.max(r);
        }
        let diagonal = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
        let base = (diagonal.max_element() / max_radius).min(MAX_RESOLUTION);
        let res = (diagonal / diagonal.max_element() * base).as_ivec3().max(IVec3::ONE);
        let mut grid = Self { lo, scale: res.as_vec3() / diagonal, res, start: Vec::new(), items: Vec::new() };
        let buckets = points.len();
        // Counting sort of (point, cell) pairs by bucket: count, prefix sums, fill.
        let mut count = vec![0u32; buckets + 1];
        for &(_, p, r) in points {
            for &b in grid.buckets(p, r, buckets).iter() {
                count[b] += 1;
            }
        }
        let mut total = 0u32;
        for c in count.iter_mut() {
            (*c, total) = (total, total + *c);
        }
        let mut cursor = count.clone();
        grid.items = vec![0; total as usize];
        for &(i, p, r) in points {
            for &b in grid.buckets(p, r, buckets).iter() {
                grid.items[cursor[b] as usize] = i;
                cursor[b] += 1;
            }
        }
        grid.start = count;
        grid
    }

    /// The indices of the points whose search sphere may hold `p` (each once; none when `p` is
    /// outside the grid), in index order.
    pub fn candidates(&self, p: Vec3) -> &[u32] {
        let c = ((p - self.lo) * self.scale).floor();
        if self.start.is_empty() || c.cmplt(Vec3::ZERO).any() || c.cmpge(self.res.as_vec3()).any() {
            return &[];
        }
        let b = hash(c.as_ivec3()) % (self.start.len() - 1);
        &self.items[self.start[b] as usize..self.start[b + 1] as usize]
    }

    /// The buckets (of `n`) of the cells the box of half-width `r` about `p` overlaps, each
    /// once. Cells are at least `r` wide, so the box overlaps at most 3 along each axis (4 with
    /// rounding).
    fn buckets(&self, p: Vec3, r: f32, n: usize) -> Buckets {
        let cell = |q: Vec3| ((q - self.lo) * self.scale).floor().as_ivec3().clamp(IVec3::ZERO, self.res - 1);
        let (a, b) = (cell(p - r), cell(p + r).min(cell(p - r) + 3));
        let mut list = Buckets { b: [0; 64], len: 0 };
        for z in a.z..=b.z {
            for y in a.y..=b.y {
                for x in a.x..=b.x {
                    let h = hash(IVec3::new(x, y, z)) % n;
                    // Two cells of one point may share a bucket: the point is listed once.
                    if !list.iter().any(|&o| o == h) {
                        list.b[list.len] = h;
                        list.len += 1;
                    }
                }
            }
        }
        list
    }
}

/// The distinct buckets of one point's cells.
struct Buckets {
    b: [usize; 64],
    len: usize,
}

impl Buckets {
    fn iter(&self) -> std::slice::Iter<'_, usize> {
        self.b[..self.len].iter()
    }
}

/// Teschner et al.'s spatial hash of a cell: its coordinates times three large primes, XORed.
fn hash(c: IVec3) -> usize {
    let h = (c.x as u32).wrapping_mul(73_856_093)
        ^ (c.y as u32).wrapping_mul(19_349_663)
        ^ (c.z as u32).wrapping_mul(83_492_791);
    h as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Every point whose sphere holds a query point is among its candidates, and no candidate
    /// is listed twice.
    #[test]
    fn candidates_hold_every_point_whose_sphere_holds_the_query() {
        let mut rng = Rng::new(0, 7);
        let mut u = || Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
        let points: Vec<(u32, Vec3, f32)> = (0..500).map(|i| (i, u() * 4.0, 0.05 + 0.2 * u().x)).collect();
        let grid = VisiblePointGrid::new(&points);
        for _ in 0..2000 {
            let q = u() * 4.4 - 0.2;
            let c = grid.candidates(q);
            let mut sorted = c.to_vec();
            sorted.dedup();
            assert_eq!(sorted.len(), c.len(), "a point listed twice in one bucket");
            for &(i, p, r) in &points {
                if p.distance_squared(q) <= r * r {
                    assert!(c.contains(&i), "point {i} holds {q} but is not a candidate");
                }
            }
        }
    }

    #[test]
    fn no_points_no_candidates() {
        assert!(VisiblePointGrid::new(&[]).candidates(Vec3::ZERO).is_empty());
    }
}

//! The distance from a point to the nearest of a growing set of points on the unit torus
//! [0, 1)², through a uniform grid of buckets (as in Mitchell 1991's best-candidate sampling):
//! a query visits the rings of cells around its own until no unvisited cell can hold a nearer
//! point, so it costs O(1) cells while the grid keeps about one point per cell.
//!
//! Coordinates are 32-bit fixed point (units of 2^-32); the toroidal difference of two
//! coordinates is their wrapping difference read as a signed number.

/// An empty cell or the end of a cell's list.
const NONE: u32 = u32::MAX;

/// The finest grid: 2^12 cells per side, far more than the point sets here need.
const MAX_BITS: u32 = 12;

/// Points on the unit torus bucketed in a 2^`bits` × 2^`bits` grid, each cell a linked list.
#[derive(Debug, Default)]
pub(super) struct TorusGrid {
    bits: u32,
    points: Vec<[u32; 2]>,
    /// The first point of each cell (row-major), or [`NONE`].
    head: Vec<u32>,
    /// The next point in the same cell, per point.
    next: Vec<u32>,
}

/// The squared toroidal distance between `a` and `b`, in units of 2^-64.
pub(super) fn distance_squared(a: [u32; 2], b: [u32; 2]) -> u64 {
    let d = |u: u32, v: u32| u64::from((u.wrapping_sub(v) as i32).unsigned_abs());
    let (dx, dy) = (d(a[0], b[0]), d(a[1], b[1]));
    dx * dx + dy * dy
}

impl TorusGrid {
    pub fn new() -> Self {
        Self { bits: 0, points: Vec::new(), head: vec![NONE], next: Vec::new() }
    }

    fn cell(&self, c: [u32; 2]) -> usize {
        if self.bits == 0 {
            0
        } else {
            ((c[1] >> (32 - self.bits)) as usize) << self.bits | (c[0] >> (32 - self.bits)) as usize
        }
    }

    /// Adds `p`; the grid is refined (and the points bucketed again) when the points outnumber
    /// the cells, so a cell holds about one point.
    pub fn insert(&mut self, p: [u32; 2]) {
        self.points.push(p);
        self.next.push(NONE);
        if self.points.len() > 1 << (2 * self.bits) && self.bits < MAX_BITS {
            self.bits += 1;
            self.head = vec![NONE; 1 << (2 * self.bits)];
            for i in 0..self.points.len() {
                self.link(i);
            }
        } else {
            self.link(self.points.len() - 1);
        }
    }

    fn link(&mut self, i: usize) {
        let c = self.cell(self.points[i]);
        self.next[i] = self.head[c];
        self.head[c] = i as u32;
    }

    /// The squared toroidal distance from `q` to the nearest point (units of 2^-64);
    /// `u64::MAX` when there is none.
    pub fn nearest_distance_squared(&self, q: [u32; 2]) -> u64 {
        let side = 1i64 << self.bits;
        let mut best = u64::MAX;
        let scan = |cell: usize, best: &mut u64| {
            let mut i = self.head[cell];
            while i != NONE {
                *best = (*best).min(distance_squared(q, self.points[i as usize]));
                i = self.next[i as usize];
            }
        };
        let (cx, cy) = if self.bits == 0 {
            (0, 0)
        } else {
            ((q[0] >> (32 - self.bits)) as i64, (q[1] >> (32 - self.bits)) as i64)
        };
        let width = 1u64 << (32 - self.bits);
        for r in 0..side {
            if 2 * r + 1 >= side {
                // The ring would wrap onto cells already seen: look at every cell.
                (0..self.head.len()).for_each(|c| scan(c, &mut best));
                return best;
            }
            let mut visit = |i: i64, j: i64| {
                let (x, y) = ((cx + i).rem_euclid(side), (cy + j).rem_euclid(side));
                scan((y << self.bits | x) as usize, &mut best);
            };
            if r == 0 {
                visit(0, 0);
            } else {
                for i in -r..=r {
                    visit(i, -r);
                    visit(i, r);
                }
                for j in 1 - r..r {
                    visit(-r, j);
                    visit(r, j);
                }
            }
            // Every point in ring r + 1 or beyond is at least r cells away from q.
            let reach = r as u64 * width;
            if best <= reach * reach {
                return best;
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn the_nearest_distance_is_the_brute_force_minimum_over_the_torus() {
        let mut rng = Rng::new(3, 0);
        let mut grid = TorusGrid::new();
        let mut points = Vec::new();
        assert_eq!(grid.nearest_distance_squared([5, 5]), u64::MAX);
        for n in 0..3000 {
            // Points bunched near the corners too, so distances wrap around the torus.
            let p = if n % 3 == 0 {
                [rng.next_u32() >> 6, rng.next_u32().wrapping_neg() >> 6]
            } else {
                [rng.next_u32(), rng.next_u32()]
            };
            grid.insert(p);
            points.push(p);
            if n % 7 == 0 {
                let q = [rng.next_u32(), rng.next_u32()];
                let brute = points.iter().map(|&p| distance_squared(p, q)).min().unwrap();
                assert_eq!(grid.nearest_distance_squared(q), brute, "{n} points");
            }
        }
        // Across the seam: 0.99 and 0.01 are 0.02 apart.
        let a = (0.99 * 4294967296.0) as u32;
        let b = (0.01 * 4294967296.0) as u32;
        let d = (distance_squared([a, 0], [b, 0]) as f64).sqrt() / 4294967296.0;
        assert!((d - 0.02).abs() < 1e-6, "{d}");
    }
}

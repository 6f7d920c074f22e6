//! Watertight ray–triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1)).
//!
//! The ray is sheared so it runs along +z from the origin; the three 2D edge functions U, V, W of
//! the projected triangle are then evaluated with the same arithmetic for an edge shared by two
//! triangles, so a ray through an edge or vertex hits at least one of them. Edge functions that
//! come out exactly 0 are recomputed in f64 (the paper's fallback) so their sign is exact.

use glam::Vec3;

/// Per-ray constants of the shear transform (paper §3, Fig. 2 setup).
#[derive(Clone, Copy, Debug)]
pub struct ShearedRay {
    /// Ray origin.
    pub o: Vec3,
    /// Axis along which |d| is largest (becomes z).
    kz: usize,
    kx: usize,
    ky: usize,
    /// Shear constants: Sx = dx/dz, Sy = dy/dz, Sz = 1/dz (in the permuted axes).
    sx: f32,
    sy: f32,
    sz: f32,
}

/// A ray–triangle hit: t and the barycentric weights of p1 (`u`) and p2 (`v`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Parametric distance along the ray (units of |d|).
    pub t: f32,
    /// Weight of p1.
    pub u: f32,
    /// Weight of p2.
    pub v: f32,
}

impl ShearedRay {
    /// Precomputes the shear for origin `o`, direction `d`. Returns `None` for a zero or
    /// non-finite direction or a non-finite origin (such rays hit nothing).
    pub fn new(o: Vec3, d: Vec3) -> Option<Self> {
        if !o.is_finite() || !d.is_finite() || d == Vec3::ZERO {
            return None;
        }
        let kz = d.abs().max_position();
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Swapping x and y when dz < 0 keeps the winding (sign of the determinant) consistent.
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Some(Self { o, kz, kx, ky, sx: d[kx] / d[kz], sy: d[ky] / d[kz], sz: 1.0 / d[kz] })
    }

    /// The hit with t in (0, t_max], or `None`. Triangles seen edge-on (det = 0) are missed.
    #[inline]
    pub fn intersect(&self, p0: Vec3, p1: Vec3, p2: Vec3, t_max: f32) -> Option<TriangleHit> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        // Arrays index without glam's per-component match; kx, ky, kz < 3 by construction.
        let a = (p0 - self.o).to_array();
        let b = (p1 - self.o).to_array();
        let c = (p2 - self.o).to_array();
        // Shear and scale the vertices into ray space (paper eq. 1).
        let ax = a[kx] - self.sx * a[kz];
        let ay = a[ky] - self.sy * a[kz];
        let bx = b[kx] - self.sx * b[kz];
        let by = b[ky] - self.sy * b[kz];
        let cx = c[kx] - self.sx * c[kz];
        let cy = c[ky] - self.sy * c[kz];
        // Scaled barycentrics: 2D edge functions.
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let f = |p: f32, q: f32, r: f32, s: f32| (p as f64 * q as f64 - r as f64 * s as f64) as f32;
            u = f(cx, by, cy, bx);
            v = f(ax, cy, ay, cx);
            w = f(bx, ay, by, ax);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let az = self.sz * a[kz];
        let bz = self.sz * b[kz];
        let cz = self.sz * c[kz];
        let t_scaled = u * az + v * bz + w * cz;
        // t = T/det > 0 needs T and det of the same sign (paper's division-free test).
        if (det < 0.0 && t_scaled >= 0.0) || (det > 0.0 && t_scaled <= 0.0) {
            return None;
        }
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;
        // The range test uses the rounded t itself (not T vs t_max·det) so that a hit reported at
        // t is found again when t_max = t; `!(..)` also rejects NaN from non-finite vertices.
        if !(t > 0.0 && t <= t_max) {
            return None;
        }
        Some(TriangleHit { t, u: v * inv_det, v: w * inv_det })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P0: Vec3 = Vec3::new(0.0, 0.0, 0.0);
    const P1: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    const P2: Vec3 = Vec3::new(0.0, 1.0, 0.0);

    #[test]
    fn reports_t_and_barycentrics_of_p1_p2() {
        let r = ShearedRay::new(Vec3::new(0.2, 0.3, 2.0), Vec3::new(0.0, 0.0, -0.5)).unwrap();
        let h = r.intersect(P0, P1, P2, f32::INFINITY).unwrap();
        assert!((h.t - 4.0).abs() < 1e-6);
        assert!((h.u - 0.2).abs() < 1e-6 && (h.v - 0.3).abs() < 1e-6);
        // Back side and reversed winding hit too.
        let r2 = ShearedRay::new(Vec3::new(0.2, 0.3, -2.0), Vec3::Z).unwrap();
        let h2 = r2.intersect(P0, P2, P1, f32::INFINITY).unwrap();
        assert!((h2.u - 0.3).abs() < 1e-6 && (h2.v - 0.2).abs() < 1e-6);
    }

    #[test]
    fn respects_t_range_and_misses_outside() {
        let r = ShearedRay::new(Vec3::new(0.2, 0.3, 2.0), -Vec3::Z).unwrap();
        assert!(r.intersect(P0, P1, P2, 2.0).is_some(), "t == t_max is inside (0, t_max]");
        assert!(r.intersect(P0, P1, P2, 1.999).is_none());
        let behind = ShearedRay::new(Vec3::new(0.2, 0.3, 2.0), Vec3::Z).unwrap();
        assert!(behind.intersect(P0, P1, P2, f32::INFINITY).is_none());
        let outside = ShearedRay::new(Vec3::new(0.6, 0.6, 2.0), -Vec3::Z).unwrap();
        assert!(outside.intersect(P0, P1, P2, f32::INFINITY).is_none());
        assert!(ShearedRay::new(Vec3::ZERO, Vec3::ZERO).is_none());
        assert!(ShearedRay::new(Vec3::NAN, Vec3::Z).is_none());
    }

    #[test]
    fn shared_edge_is_hit_by_exactly_aimed_rays() {
        // Two triangles sharing the diagonal of a skewed quad; rays aimed at points on the shared
        // edge from many origins must hit at least one of the two.
        let (a, b) = (Vec3::new(0.1, 0.2, 0.3), Vec3::new(1.7, 1.3, -0.4));
        let (c, d) = (Vec3::new(1.9, -0.2, 0.1), Vec3::new(-0.3, 1.5, 0.2));
        let mut seed = 7u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..100_000 {
            let target = a + (b - a) * rnd();
            let o = Vec3::new(rnd() - 0.5, rnd() - 0.5, 1.0 + rnd()) * 4.0;
            let r = ShearedRay::new(o, target - o).unwrap();
            let hit1 = r.intersect(a, c, b, f32::INFINITY);
            let hit2 = r.intersect(a, b, d, f32::INFINITY);
            assert!(hit1.is_some() || hit2.is_some(), "leak at {target:?} from {o:?}");
        }
    }
}

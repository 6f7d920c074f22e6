//! Watertight ray–triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1)).
//!
//! The ray is sheared so it runs along +z from the origin; the three 2D edge functions U, V, W of
//! the projected triangle are then evaluated with the same arithmetic for an edge shared by two
//! triangles, so a ray through an edge or vertex hits at least one of them. Edge functions that
//! come out exactly 0 are recomputed in f64 (the paper's fallback) so their sign is exact.
//!
//! [`LaneRay`] runs the same test on a [`TriangleLanes`] (the three vertices in the lanes of
//! SIMD registers) and gives the same values (a zero barycentric may differ in sign):
//! watertightness only needs every vertex to be projected by the same deterministic arithmetic
//! and the 2D edge functions' signs to be exact.

use glam::{Vec3, Vec3A, Vec3Swizzles};

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

/// A triangle stored lane-wise: lane i of `x`, `y`, `z` holds vertex p_i (48 bytes).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct TriangleLanes {
    x: Vec3A,
    y: Vec3A,
    z: Vec3A,
}

impl TriangleLanes {
    /// Packs the vertices p0, p1, p2.
    pub fn new([p0, p1, p2]: [Vec3; 3]) -> Self {
        Self { x: Vec3A::new(p0.x, p1.x, p2.x), y: Vec3A::new(p0.y, p1.y, p2.y), z: Vec3A::new(p0.z, p1.z, p2.z) }
    }

    /// The vertices p0, p1, p2.
    pub fn vertices(&self) -> [Vec3; 3] {
        [0, 1, 2].map(|i| Vec3::new(self.x[i], self.y[i], self.z[i]))
    }
}

/// The per-ray constants of [`ShearedRay`] for [`TriangleLanes`]. The dominant axis `kz` is a
/// const parameter of [`LaneRay::intersect`] so the axis permutation costs nothing per triangle;
/// callers dispatch on [`LaneRay::kz`] once per ray.
///
/// Unlike the scalar test this never swaps x and y when d_kz < 0: without back-face culling the
/// swap only negates U, V, W, T and det together (exactly, in floating point), so t and the
/// barycentrics come out the same, up to the sign of a zero.
#[derive(Clone, Copy, Debug)]
pub struct LaneRay {
    /// Origin, one coordinate per register (all lanes equal).
    o: [Vec3A; 3],
    /// Shear constants d_kx/d_kz, d_ky/d_kz, 1/d_kz (all lanes equal).
    sx: Vec3A,
    sy: Vec3A,
    sz: Vec3A,
    kz: usize,
}

impl LaneRay {
    /// Precomputes the shear for origin `o`, direction `d`; `None` like [`ShearedRay::new`].
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Option<Self> {
        if !o.is_finite() || !d.is_finite() || d == Vec3::ZERO {
            return None;
        }
        let kz = d.abs().max_position();
        let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
        Some(Self {
            o: [Vec3A::splat(o.x), Vec3A::splat(o.y), Vec3A::splat(o.z)],
            sx: Vec3A::splat(d[kx] / d[kz]),
            sy: Vec3A::splat(d[ky] / d[kz]),
            sz: Vec3A::splat(1.0 / d[kz]),
            kz,
        })
    }

    /// The axis along which |d| is largest: the `KZ` to call [`LaneRay::intersect`] with.
    #[inline]
    pub fn kz(&self) -> usize {
        self.kz
    }

    /// As [`ShearedRay::intersect`]: the same values, bit for bit except the sign of a zero
    /// barycentric. `KZ` must equal [`LaneRay::kz`].
    #[inline(always)]
    pub fn intersect<const KZ: usize>(&self, tri: &TriangleLanes, t_max: f32) -> Option<TriangleHit> {
        debug_assert_eq!(KZ, self.kz);
        let (kx, ky) = ((KZ + 1) % 3, (KZ + 2) % 3);
        let p = [tri.x - self.o[0], tri.y - self.o[1], tri.z - self.o[2]];
        // Shear (paper eq. 1) for all three vertices at once: lanes are (a, b, c).
        let xs = p[kx] - self.sx * p[KZ];
        let ys = p[ky] - self.sy * p[KZ];
        // Lanes of U, V, W: c×b, a×c, b×a in 2D (same products and order as the scalar test).
        let mut uvw = xs.zxy() * ys.yzx() - ys.zxy() * xs.yzx();
        if uvw.cmpeq(Vec3A::ZERO).any() {
            let f = |p: f32, q: f32, r: f32, s: f32| (p as f64 * q as f64 - r as f64 * s as f64) as f32;
            uvw = Vec3A::new(f(xs.z, ys.y, ys.z, xs.y), f(xs.x, ys.z, ys.x, xs.z), f(xs.y, ys.x, ys.y, xs.x));
        }
        if uvw.cmplt(Vec3A::ZERO).any() && uvw.cmpgt(Vec3A::ZERO).any() {
            return None;
        }
        let [u, v, w] = uvw.to_array();
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let [az, bz, cz] = (self.sz * p[KZ]).to_array();
        let t_scaled = u * az + v * bz + w * cz;
        if (det < 0.0 && t_scaled >= 0.0) || (det > 0.0 && t_scaled <= 0.0) {
            return None;
        }
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;
        if !(t > 0.0 && t <= t_max) {
            return None;
        }
        Some(TriangleHit { t, u: v * inv_det, v: w * inv_det })
    }

    /// [`LaneRay::intersect`] with the dominant axis chosen at run time (tests, cold paths).
    pub fn intersect_any_axis(&self, tri: &TriangleLanes, t_max: f32) -> Option<TriangleHit> {
        match self.kz {
            0 => self.intersect::<0>(tri, t_max),
            1 => self.intersect::<1>(tri, t_max),
            _ => self.intersect::<2>(tri, t_max),
        }
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

    #[test]
    fn lane_test_gives_the_scalar_tests_values() {
        // Random triangles and rays, half of them aimed exactly at a vertex or an edge point (where
        // the f64 fallback and the sign tests matter), all axes and direction signs.
        let mut seed = 11u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        let (mut hits, mut zero_edge) = (0, 0);
        for k in 0..200_000 {
            let p = [0, 1, 2].map(|_| Vec3::new(rnd(), rnd(), rnd()) * 3.0);
            let o = Vec3::new(rnd(), rnd(), rnd()) * 5.0;
            let target = match k % 4 {
                0 => p[k % 3],
                1 => p[0] + (p[1] - p[0]) * rnd().abs(),
                _ => Vec3::new(rnd(), rnd(), rnd()) * 3.0,
            };
            let d = if k % 7 == 0 { Vec3::new(rnd(), 0.0, -0.0) } else { target - o };
            let t_max = if k % 5 == 0 { rnd().abs() * 2.0 } else { f32::INFINITY };
            let (Some(s), Some(l)) = (ShearedRay::new(o, d), LaneRay::new(o, d)) else {
                continue;
            };
            let tri = TriangleLanes::new(p);
            assert_eq!(tri.vertices(), p);
            let want = s.intersect(p[0], p[1], p[2], t_max);
            let got = l.intersect_any_axis(&tri, t_max);
            // f32 `==`: exact, except that +0 and -0 compare equal (see `LaneRay`).
            assert_eq!(got, want, "{p:?} {o:?} {d:?}");
            hits += want.is_some() as usize;
            zero_edge += (k % 4 == 0 && want.is_some()) as usize;
        }
        // Enough hits, including exact-vertex hits, for the comparison to mean something.
        assert!(hits > 40_000 && zero_edge > 10_000, "{hits} {zero_edge}");
    }
}

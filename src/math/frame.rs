//! Orthonormal frame: the local shading frame in which BSDFs work (z = normal).

use crate::simd::{Real, V3};
use glam::Vec3;

/// An orthonormal basis (s, t, n). Directions in the local frame have `z = cos θ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub s: Vec3,
    /// Second tangent.
    pub t: Vec3,
    /// Normal (local +z).
    pub n: Vec3,
}

impl Frame {
    /// A frame around the unit normal `n`, tangents by Duff et al. 2017
    /// ("Building an Orthonormal Basis, Revisited"), continuous except at n.z = -1 sign flip.
    pub fn from_normal(n: Vec3) -> Self {
        FrameLanes::from_normal(n.into()).into()
    }

    /// A frame with normal `n` whose first tangent follows `dpdu` (Gram–Schmidt); falls back to
    /// [`Frame::from_normal`] when `dpdu` is degenerate or parallel to `n`.
    pub fn from_normal_tangent(n: Vec3, dpdu: Vec3) -> Self {
        FrameLanes::from_normal_tangent(n.into(), dpdu.into()).into()
    }

    /// World → local.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local → world.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// A [`Frame`] per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameLanes<R> {
    /// First tangent.
    pub s: V3<R>,
    /// Second tangent.
    pub t: V3<R>,
    /// Normal (local +z).
    pub n: V3<R>,
}

impl<R: Real> FrameLanes<R> {
    /// [`Frame::from_normal`] for every lane.
    #[inline(always)]
    pub fn from_normal(n: V3<R>) -> Self {
        let one = R::splat(1.0);
        let sign = one.copysign(n.z);
        let a = -one / (sign + n.z);
        let b = n.x * n.y * a;
        let s = V3::new(one + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = V3::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }

    /// [`Frame::from_normal_tangent`] for every lane.
    #[inline(always)]
    pub fn from_normal_tangent(n: V3<R>, dpdu: V3<R>) -> Self {
        let s = dpdu - n * n.dot(dpdu);
        let len2 = s.length_squared();
        // len2 > 1e-12 is false for NaN too.
        let ok = R::splat(1e-12).lt(len2);
        let s = s * (R::splat(1.0) / len2.sqrt());
        let fallback = Self::from_normal(n);
        Self { s: V3::select(ok, s, fallback.s), t: V3::select(ok, n.cross(s), fallback.t), n }
    }

    /// World → local.
    #[inline(always)]
    pub fn to_local(&self, v: V3<R>) -> V3<R> {
        V3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local → world.
    #[inline(always)]
    pub fn to_world(&self, v: V3<R>) -> V3<R> {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

impl From<FrameLanes<f32>> for Frame {
    #[inline(always)]
    fn from(f: FrameLanes<f32>) -> Self {
        Self { s: f.s.into(), t: f.t.into(), n: f.n.into() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_for_many_normals() {
        let mut seed = 1u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        let mut normals = vec![Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::Y, Vec3::new(0.0, 1e-8, -1.0).normalize()];
        for _ in 0..1000 {
            normals.push(Vec3::new(rnd(), rnd(), rnd()).normalize());
        }
        for n in normals {
            let f = Frame::from_normal(n);
            for (a, b) in [(f.s, f.t), (f.t, f.n), (f.s, f.n)] {
                assert!(a.dot(b).abs() < 1e-5, "{n:?}");
            }
            for v in [f.s, f.t, f.n] {
                assert!((v.length() - 1.0).abs() < 1e-5);
            }
            let w = Vec3::new(0.3, -0.5, 0.8);
            assert!((f.to_world(f.to_local(w)) - w).length() < 1e-5);
        }
    }
}

//! Where a texture is evaluated: the surface point, its normal and (u, v), with their changes
//! per pixel step on the image, ∂/∂x and ∂/∂y, which filtered textures use as the footprint to
//! average over (pbrt-v4 `TextureEvalContext`, §10.1).

use glam::{Vec2, Vec3};

/// A shading point as textures see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureEvalContext {
    /// Point [world units].
    pub p: Vec3,
    /// Change of `p` per pixel step along the image's x [world units]; zero: no footprint
    /// (the finest detail is used).
    pub dpdx: Vec3,
    /// Change of `p` per pixel step along the image's y [world units].
    pub dpdy: Vec3,
    /// Unit surface normal (the shading normal, which on prism's tessellated analytic shapes
    /// is the analytic normal).
    pub n: Vec3,
    /// Surface texture coordinates.
    pub uv: Vec2,
    /// ∂u/∂x.
    pub dudx: f32,
    /// ∂u/∂y.
    pub dudy: f32,
    /// ∂v/∂x.
    pub dvdx: f32,
    /// ∂v/∂y.
    pub dvdy: f32,
}

impl TextureEvalContext {
    /// The point `p` with normal `n` and coordinates `uv`, without a footprint.
    pub fn at(p: Vec3, n: Vec3, uv: Vec2) -> Self {
        Self { p, dpdx: Vec3::ZERO, dpdy: Vec3::ZERO, n, uv, dudx: 0.0, dudy: 0.0, dvdx: 0.0, dvdy: 0.0 }
    }

    /// Only texture coordinates (at the origin, normal +z), without a footprint.
    pub fn uv(uv: Vec2) -> Self {
        Self::at(Vec3::ZERO, Vec3::Z, uv)
    }

    /// The same point with footprint `dpdx`, `dpdy`; the (u, v) derivatives follow from the
    /// surface's ∂p/∂u and ∂p/∂v by least squares, since dp = ∂p/∂u du + ∂p/∂v dv holds only
    /// approximately for a footprint off the tangent plane (pbrt-v4 §10.1.1):
    /// [a₀₀ a₀₁; a₀₁ a₁₁] (du, dv)ᵀ = (∂p/∂u · dp, ∂p/∂v · dp)ᵀ with aᵢⱼ the dot products of
    /// ∂p/∂u and ∂p/∂v. Degenerate parameterisations give zero derivatives.
    pub fn with_footprint(self, dpdx: Vec3, dpdy: Vec3, dpdu: Vec3, dpdv: Vec3) -> Self {
        let (a00, a01, a11) = (dpdu.dot(dpdu), dpdu.dot(dpdv), dpdv.dot(dpdv));
        let det = a00 * a11 - a01 * a01;
        let inv = if det != 0.0 && (1.0 / det).is_finite() { 1.0 / det } else { 0.0 };
        let solve = |d: Vec3| {
            let (b0, b1) = (dpdu.dot(d), dpdv.dot(d));
            let clean = |x: f32| if x.is_finite() { x.clamp(-1e8, 1e8) } else { 0.0 };
            (clean((a11 * b0 - a01 * b1) * inv), clean((a00 * b1 - a01 * b0) * inv))
        };
        let ((dudx, dvdx), (dudy, dvdy)) = (solve(dpdx), solve(dpdy));
        Self { dpdx, dpdy, dudx, dudy, dvdx, dvdy, ..self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_derivatives_invert_the_parameterisation() {
        // p = (2u + v, 3v, 0): a sheared, scaled plane. A step dp = ∂p/∂u du + ∂p/∂v dv
        // must give back (du, dv).
        let (dpdu, dpdv) = (Vec3::new(2.0, 0.0, 0.0), Vec3::new(1.0, 3.0, 0.0));
        let (dx, dy) = ((0.1, -0.02), (0.03, 0.05));
        let dpdx = dpdu * dx.0 + dpdv * dx.1;
        let dpdy = dpdu * dy.0 + dpdv * dy.1;
        let c = TextureEvalContext::uv(Vec2::ZERO).with_footprint(dpdx, dpdy, dpdu, dpdv);
        for (got, want) in [(c.dudx, dx.0), (c.dvdx, dx.1), (c.dudy, dy.0), (c.dvdy, dy.1)] {
            assert!((got - want).abs() < 1e-6, "{got} vs {want}");
        }
        // A component along the normal is not part of (u, v) and is ignored.
        let lifted = c.with_footprint(dpdx + Vec3::Z, dpdy, dpdu, dpdv);
        assert!((lifted.dudx - dx.0).abs() < 1e-6 && (lifted.dvdx - dx.1).abs() < 1e-6);
    }

    #[test]
    fn a_degenerate_parameterisation_gives_zero_derivatives() {
        let c = TextureEvalContext::uv(Vec2::ZERO).with_footprint(Vec3::X, Vec3::Y, Vec3::X, Vec3::X * 2.0);
        assert_eq!((c.dudx, c.dudy, c.dvdx, c.dvdy), (0.0, 0.0, 0.0, 0.0));
    }
}

//! Texture mappings (pbrt-v4 §10.2): from a shading point to 2D texture coordinates (s, t)
//! with their screen-space derivatives, or to a point in a texture's own 3D space. Mappings
//! that use the point work in texture space, the space in effect at the Texture directive.

use super::context::TextureEvalContext;
use crate::math::PI;
use glam::{Mat4, Vec2, Vec3};

/// 2D texture coordinates and their changes per pixel step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexCoord2D {
    /// (s, t).
    pub st: Vec2,
    /// ∂(s, t)/∂x.
    pub dst_dx: Vec2,
    /// ∂(s, t)/∂y.
    pub dst_dy: Vec2,
}

/// A 2D mapping (pbrt-v4's "mapping" parameter).
#[derive(Clone, Debug, PartialEq)]
pub enum Mapping2D {
    /// "uv": s = su·u + du, t = sv·v + dv.
    Uv {
        /// (su, sv): "uscale", "vscale".
        scale: Vec2,
        /// (du, dv): "udelta", "vdelta".
        delta: Vec2,
    },
    /// "spherical": s = θ/π, t = φ/2π of the point's direction from the texture-space origin.
    Spherical {
        /// Texture space from world space.
        texture_from_world: Mat4,
    },
    /// "cylindrical": s = (π + φ)/2π about the texture-space z axis, t = z.
    Cylindrical {
        /// Texture space from world space.
        texture_from_world: Mat4,
    },
    /// "planar": s = ds + p·v₁, t = dt + p·v₂ for the texture-space point p.
    Planar {
        /// Texture space from world space.
        texture_from_world: Mat4,
        /// v₁ ("v1").
        vs: Vec3,
        /// v₂ ("v2").
        vt: Vec3,
        /// (ds, dt): "udelta", "vdelta".
        delta: Vec2,
    },
}

impl Mapping2D {
    /// The identity "uv" mapping.
    pub const UV: Mapping2D = Mapping2D::Uv { scale: Vec2::ONE, delta: Vec2::ZERO };

    /// (s, t) and its derivatives at `ctx`.
    pub fn map(&self, ctx: &TextureEvalContext) -> TexCoord2D {
        match self {
            Mapping2D::Uv { scale, delta } => TexCoord2D {
                st: *scale * ctx.uv + *delta,
                dst_dx: *scale * Vec2::new(ctx.dudx, ctx.dvdx),
                dst_dy: *scale * Vec2::new(ctx.dudy, ctx.dvdy),
            },
            Mapping2D::Spherical { texture_from_world } => {
                let p = texture_from_world.transform_point3(ctx.p);
                let (rho2, r2) = (p.x * p.x + p.y * p.y, p.length_squared());
                let rho = rho2.sqrt();
                // θ = acos(z/r): ∂θ/∂p = (xz/ρ, yz/ρ, −ρ)/r²; φ = atan2(y, x): ∂φ/∂p = (−y, x, 0)/ρ².
                let ds_dp = Vec3::new(p.x * p.z / rho, p.y * p.z / rho, -rho) / (PI * r2);
                let dt_dp = Vec3::new(-p.y, p.x, 0.0) / (2.0 * PI * rho2);
                let d = p.normalize_or_zero();
                let st = Vec2::new(d.z.clamp(-1.0, 1.0).acos() / PI, azimuth(d.y, d.x) / (2.0 * PI));
                gradients(st, ds_dp, dt_dp, texture_from_world, ctx)
            }
            Mapping2D::Cylindrical { texture_from_world } => {
                let p = texture_from_world.transform_point3(ctx.p);
                let ds_dp = Vec3::new(-p.y, p.x, 0.0) / (2.0 * PI * (p.x * p.x + p.y * p.y));
                let st = Vec2::new((PI + p.y.atan2(p.x)) / (2.0 * PI), p.z);
                gradients(st, ds_dp, Vec3::Z, texture_from_world, ctx)
            }
            Mapping2D::Planar { texture_from_world, vs, vt, delta } => {
                let p = texture_from_world.transform_point3(ctx.p);
                let st = *delta + Vec2::new(p.dot(*vs), p.dot(*vt));
                gradients(st, *vs, *vt, texture_from_world, ctx)
            }
        }
    }
}

/// φ = atan2(y, x) in [0, 2π).
fn azimuth(y: f32, x: f32) -> f32 {
    let phi = y.atan2(x);
    if phi < 0.0 {
        phi + 2.0 * PI
    } else {
        phi
    }
}

/// (s, t) with derivatives from its texture-space gradients and the footprint carried into
/// texture space. Non-finite gradients (on the axis of a spherical or cylindrical mapping)
/// give no footprint.
fn gradients(st: Vec2, ds_dp: Vec3, dt_dp: Vec3, texture_from_world: &Mat4, ctx: &TextureEvalContext) -> TexCoord2D {
    let dpdx = texture_from_world.transform_vector3(ctx.dpdx);
    let dpdy = texture_from_world.transform_vector3(ctx.dpdy);
    let finite = |v: Vec2| if v.is_finite() { v } else { Vec2::ZERO };
    TexCoord2D {
        st,
        dst_dx: finite(Vec2::new(ds_dp.dot(dpdx), dt_dp.dot(dpdx))),
        dst_dy: finite(Vec2::new(ds_dp.dot(dpdy), dt_dp.dot(dpdy))),
    }
}

/// A point in a texture's 3D space and its changes per pixel step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexCoord3D {
    /// The point.
    pub p: Vec3,
    /// ∂p/∂x.
    pub dpdx: Vec3,
    /// ∂p/∂y.
    pub dpdy: Vec3,
}

/// The 3D mapping of solid textures: the shading point in texture space.
#[derive(Clone, Debug, PartialEq)]
pub struct Mapping3D {
    /// Texture space from world space.
    pub texture_from_world: Mat4,
}

impl Mapping3D {
    /// The texture-space point of `ctx` and its footprint.
    pub fn map(&self, ctx: &TextureEvalContext) -> TexCoord3D {
        let m = &self.texture_from_world;
        TexCoord3D {
            p: m.transform_point3(ctx.p),
            dpdx: m.transform_vector3(ctx.dpdx),
            dpdy: m.transform_vector3(ctx.dpdy),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(p: Vec3) -> TextureEvalContext {
        TextureEvalContext::at(p, Vec3::Z, Vec2::ZERO)
    }

    #[test]
    fn uv_mapping_scales_and_offsets() {
        let m = Mapping2D::Uv { scale: Vec2::new(2.0, 3.0), delta: Vec2::new(0.25, 0.1) };
        let mut ctx = TextureEvalContext::uv(Vec2::new(0.5, 0.5));
        (ctx.dudx, ctx.dvdy) = (0.01, 0.02);
        let c = m.map(&ctx);
        assert_eq!(c.st, Vec2::new(1.25, 1.6));
        assert_eq!(c.dst_dx, Vec2::new(0.02, 0.0));
        assert_eq!(c.dst_dy, Vec2::new(0.0, 0.06));
    }

    #[test]
    fn spherical_mapping_of_known_directions() {
        // Texture space centred at (1, 2, 3).
        let m = Mapping2D::Spherical { texture_from_world: Mat4::from_translation(Vec3::new(-1.0, -2.0, -3.0)) };
        let c = Vec3::new(1.0, 2.0, 3.0);
        let st = |d: Vec3| m.map(&at(c + 0.5 * d)).st;
        // North pole θ = 0; equator θ = π/2 at φ = 0, π/2, π; south pole θ = π.
        assert!((st(Vec3::Z).x).abs() < 1e-6);
        let e = st(Vec3::X);
        assert!((e.x - 0.5).abs() < 1e-6 && e.y.abs() < 1e-6, "{e}");
        let e = st(Vec3::Y);
        assert!((e.x - 0.5).abs() < 1e-6 && (e.y - 0.25).abs() < 1e-6, "{e}");
        let e = st(-Vec3::X);
        assert!((e.x - 0.5).abs() < 1e-6 && (e.y - 0.5).abs() < 1e-6, "{e}");
        let e = st(-Vec3::Y);
        assert!((e.y - 0.75).abs() < 1e-6, "{e}");
        assert!((st(-Vec3::Z).x - 1.0).abs() < 1e-6);
        // 45° above the equator towards +y: θ = π/4.
        let e = st(Vec3::new(0.0, 1.0, 1.0).normalize());
        assert!((e.x - 0.25).abs() < 1e-6 && (e.y - 0.25).abs() < 1e-6, "{e}");
    }

    #[test]
    fn mapping_derivatives_match_finite_differences() {
        let tf = Mat4::from_rotation_z(0.3) * Mat4::from_scale(Vec3::splat(1.7)) * Mat4::from_translation(-Vec3::ONE);
        let maps = [
            Mapping2D::Spherical { texture_from_world: tf },
            Mapping2D::Cylindrical { texture_from_world: tf },
            Mapping2D::Planar {
                texture_from_world: tf,
                vs: Vec3::new(-1.2, 0.0, 0.6),
                vt: Vec3::new(0.6, 0.0, 1.2),
                delta: Vec2::new(0.1, 0.3),
            },
        ];
        let p = Vec3::new(1.4, 1.3, 1.2);
        let (dx, dy) = (Vec3::new(1e-3, 0.0, 2e-4), Vec3::new(0.0, -1e-3, 5e-4));
        for m in &maps {
            let mut ctx = at(p);
            (ctx.dpdx, ctx.dpdy) = (dx, dy);
            let c = m.map(&ctx);
            let fx = (m.map(&at(p + dx)).st - m.map(&at(p - dx)).st) / 2.0;
            let fy = (m.map(&at(p + dy)).st - m.map(&at(p - dy)).st) / 2.0;
            assert!((c.dst_dx - fx).length() < 2e-5, "{m:?}: {} vs {fx}", c.dst_dx);
            assert!((c.dst_dy - fy).length() < 2e-5, "{m:?}: {} vs {fy}", c.dst_dy);
        }
    }

    #[test]
    fn cylindrical_and_planar_mappings_of_known_points() {
        let cyl = Mapping2D::Cylindrical { texture_from_world: Mat4::IDENTITY };
        // φ = atan2(y, x): +x is s = ½, +y is s = ¾, −x is s = 0 or 1; t = z.
        let c = cyl.map(&at(Vec3::new(1.0, 0.0, 0.7))).st;
        assert!((c.x - 0.5).abs() < 1e-6 && (c.y - 0.7).abs() < 1e-6, "{c}");
        assert!((cyl.map(&at(Vec3::new(0.0, 2.0, 0.0))).st.x - 0.75).abs() < 1e-6);
        let planar = Mapping2D::Planar {
            texture_from_world: Mat4::from_translation(Vec3::new(1.05, 0.01, -2.25)),
            vs: Vec3::new(-1.2, 0.0, 0.6),
            vt: Vec3::new(0.6, 0.0, 1.2),
            delta: Vec2::new(0.1, 0.3),
        };
        // The texture-space origin maps to (ds, dt); one unit along x to (ds − 1.2, dt + 0.6).
        let o = planar.map(&at(Vec3::new(-1.05, -0.01, 2.25))).st;
        assert!((o - Vec2::new(0.1, 0.3)).length() < 1e-6, "{o}");
        let x = planar.map(&at(Vec3::new(-0.05, -0.01, 2.25))).st;
        assert!((x - Vec2::new(-1.1, 0.9)).length() < 1e-5, "{x}");
    }

    #[test]
    fn the_3d_mapping_carries_point_and_footprint_into_texture_space() {
        let m = Mapping3D { texture_from_world: Mat4::from_scale(Vec3::splat(5.0)) * Mat4::from_translation(-Vec3::X) };
        let mut ctx = at(Vec3::new(1.5, 0.0, 0.2));
        ctx.dpdx = Vec3::new(0.01, 0.0, 0.0);
        let c = m.map(&ctx);
        assert!((c.p - Vec3::new(2.5, 0.0, 1.0)).length() < 1e-6);
        assert!((c.dpdx - Vec3::new(0.05, 0.0, 0.0)).length() < 1e-7);
    }
}

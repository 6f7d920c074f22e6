//! Shading normals perturbed before a material's BSDF is built: by a displacement texture
//! (bump mapping, Blinn 1978) or by a tangent-space normal map, as pbrt-v4 does for every
//! material (pbrt-v4 §10.5.1, `BumpMap` and `NormalMap`; a normal map wins over a
//! displacement when a material has both).

use super::{FloatTexture, Material, ShadingPoint};
use crate::texture::WrapMode;
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// A material whose shading normal is perturbed.
#[derive(Clone, Debug)]
pub struct BumpedMaterial {
    /// The material whose BSDF is built in the perturbed frame (never a mix or an interface).
    pub base: Material,
    /// How the normal is perturbed.
    pub perturbation: NormalPerturbation,
}

/// The two ways pbrt-v4 perturbs shading normals.
#[derive(Clone, Debug)]
pub enum NormalPerturbation {
    /// A height field d(u, v) [scene units] along the shading normal.
    Displacement(FloatTexture),
    /// Unit normals in the tangent frame (∂p/∂u, n × ∂p/∂u, n), stored as (n + 1)/2 in RGB.
    NormalMap(Arc<NormalMap>),
}

/// The surface's shading derivatives as pbrt-v4's shading geometry holds them: ∂p/∂u made
/// perpendicular to the shading normal, ∂p/∂v (n × ∂p/∂u when the mesh has normals), and the
/// change of the shading normal along u and v.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShadingDerivatives {
    /// ∂p/∂u of the shading frame.
    pub dpdu: Vec3,
    /// ∂p/∂v of the shading frame.
    pub dpdv: Vec3,
    /// ∂n/∂u.
    pub dndu: Vec3,
    /// ∂n/∂v.
    pub dndv: Vec3,
}

/// A tangent-space normal map: RGB texels, row 0 at the top of the picture (v = 1), looked up
/// bilinearly with repeat wrapping, as pbrt-v4 reads them (linear encoding).
#[derive(Clone, Debug)]
pub struct NormalMap {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
}

impl NormalMap {
    /// A `width` × `height` map of RGB texels (row-major, top row first), or `None` when the
    /// sizes do not match.
    pub fn new(width: usize, height: usize, texels: Vec<[f32; 3]>) -> Option<Self> {
        (width > 0 && height > 0 && texels.len() == width * height).then(|| Self {
            width,
            height,
            texels: texels.into_iter().map(Vec3::from_array).collect(),
        })
    }

    /// The bilinearly interpolated RGB at (s, t) ∈ [0, 1]² with t = 0 the top row (texel
    /// centres at (i + ½)/width), wrapping around the edges.
    fn bilerp(&self, st: Vec2) -> Vec3 {
        let (x, y) = (st.x * self.width as f32 - 0.5, st.y * self.height as f32 - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |dx: i64, dy: i64| {
            WrapMode::Repeat
                .texel(x0 as i64 + dx, y0 as i64 + dy, self.width, self.height)
                .map_or(Vec3::ZERO, |(i, j)| self.texels[j * self.width + i])
        };
        texel(0, 0) * ((1.0 - fx) * (1.0 - fy))
            + texel(1, 0) * (fx * (1.0 - fy))
            + texel(0, 1) * ((1.0 - fx) * fy)
            + texel(1, 1) * (fx * fy)
    }

    /// The map's unit normal at surface coordinates `uv`, in the tangent frame.
    pub fn tangent_normal(&self, uv: Vec2) -> Vec3 {
        (self.bilerp(Vec2::new(uv.x, 1.0 - uv.y)) * 2.0 - Vec3::ONE).normalize_or_zero()
    }
}

/// pbrt-v4's step in u or v for the finite difference of a displacement: half the footprint's
/// extent in that coordinate, or 0.0005 without one.
fn bump_step(dx: f32, dy: f32) -> f32 {
    let d = 0.5 * (dx.abs() + dy.abs());
    if d == 0.0 {
        0.0005
    } else {
        d
    }
}

impl NormalPerturbation {
    /// `sp` with its shading normal and ∂p/∂u perturbed, given the surface's shading
    /// derivatives `d`. The new normal is n′ = (∂p′/∂u × ∂p′/∂v)/|…| on the side of the
    /// geometric normal; a degenerate result leaves `sp` as it was.
    pub fn apply(&self, sp: &ShadingPoint, d: &ShadingDerivatives) -> ShadingPoint {
        let (dpdu, dpdv) = match self {
            NormalPerturbation::Displacement(height) => {
                // Forward differences of the height field along u and v (pbrt-v4 `BumpMap`):
                // p′ = p + h n, so ∂p′/∂u ≈ ∂p/∂u + (∂h/∂u) n + h ∂n/∂u.
                let t = &sp.tex;
                let du = bump_step(t.dudx, t.dudy);
                let dv = bump_step(t.dvdx, t.dvdy);
                let shifted = |dp: Vec3, duv: Vec2| {
                    let mut c = *t;
                    c.p += dp;
                    c.uv += duv;
                    height.eval(&c)
                };
                let h_u = shifted(d.dpdu * du, Vec2::new(du, 0.0));
                let h_v = shifted(d.dpdv * dv, Vec2::new(0.0, dv));
                let h = height.eval(t);
                (d.dpdu + sp.ns * ((h_u - h) / du) + d.dndu * h, d.dpdv + sp.ns * ((h_v - h) / dv) + d.dndv * h)
            }
            NormalPerturbation::NormalMap(map) => {
                // The map's normal in the frame (x = ∂p/∂u/|∂p/∂u|, y = n × x, z = n), then
                // ∂p/∂u and ∂p/∂v rebuilt around it with their lengths kept (pbrt-v4 `NormalMap`).
                let Some(x) = d.dpdu.try_normalize() else { return *sp };
                let nt = map.tangent_normal(sp.tex.uv);
                let n = x * nt.x + sp.ns.cross(x) * nt.y + sp.ns * nt.z;
                let Some(u_dir) = (d.dpdu - n * d.dpdu.dot(n)).try_normalize() else { return *sp };
                let dpdu = u_dir * d.dpdu.length();
                (dpdu, n.cross(dpdu).normalize_or_zero() * d.dpdv.length())
            }
        };
        let Some(n) = dpdu.cross(dpdv).try_normalize() else { return *sp };
        let ns = if n.dot(sp.ng) < 0.0 { -n } else { n };
        if !(ns.is_finite() && dpdu.is_finite()) {
            return *sp;
        }
        ShadingPoint { ns, dpdu, ..*sp }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Mapping2D, Texture, TextureEvalContext};

    fn flat_point(uv: Vec2) -> (ShadingPoint, ShadingDerivatives) {
        let sp = ShadingPoint {
            ns: Vec3::Z,
            ng: Vec3::Z,
            dpdu: Vec3::X,
            tex: TextureEvalContext::at(Vec3::new(uv.x, uv.y, 0.0), Vec3::Z, uv),
        };
        (sp, ShadingDerivatives { dpdu: Vec3::X, dpdv: Vec3::Y, ..Default::default() })
    }

    /// A height field h(u, v) = a u + b v as a bilerp texture over the unit square.
    fn plane(a: f32, b: f32) -> FloatTexture {
        Texture::Bilerp { mapping: Mapping2D::UV, corners: Box::new([0.0, a, b, a + b]) }
    }

    #[test]
    fn a_sloped_height_field_tilts_the_normal_by_its_gradient() {
        // h = a u + b v over the plane z = 0 with p = (u, v, 0): the displaced surface
        // z = a x + b y has the normal (−a, −b, 1)/√(1 + a² + b²).
        let (a, b) = (0.3, -0.2);
        let (sp, d) = flat_point(Vec2::new(0.4, 0.6));
        let bumped = NormalPerturbation::Displacement(plane(a, b)).apply(&sp, &d);
        let want = Vec3::new(-a, -b, 1.0).normalize();
        assert!((bumped.ns - want).length() < 1e-3, "{} vs {want}", bumped.ns);
        assert!(bumped.dpdu.dot(bumped.ns).abs() < 1e-5, "∂p/∂u stays in the tangent plane");
    }

    #[test]
    fn a_constant_height_leaves_a_flat_surface_alone() {
        let (sp, d) = flat_point(Vec2::new(0.2, 0.9));
        let bumped = NormalPerturbation::Displacement(FloatTexture::Constant(0.7)).apply(&sp, &d);
        assert!((bumped.ns - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn the_normal_stays_on_the_geometric_side() {
        // A steep slope along −u of a surface whose ∂p/∂u × ∂p/∂v points away from n_g.
        let (mut sp, mut d) = flat_point(Vec2::new(0.5, 0.5));
        d.dpdv = -Vec3::Y;
        sp.ns = Vec3::Z;
        let bumped = NormalPerturbation::Displacement(plane(2.0, 0.0)).apply(&sp, &d);
        assert!(bumped.ns.dot(sp.ng) > 0.0, "{}", bumped.ns);
    }

    #[test]
    fn a_normal_map_texel_is_read_in_the_tangent_frame() {
        // One texel encoding the tangent-space normal (0.6, 0, 0.8): with ∂p/∂u = x and n = z the
        // shading normal is (0.6, 0, 0.8); encoded (0.8, 0.5, 0.9).
        let map = NormalMap::new(1, 1, vec![[0.8, 0.5, 0.9]]).expect("1 × 1 map");
        let (sp, d) = flat_point(Vec2::new(0.3, 0.3));
        let mapped = NormalPerturbation::NormalMap(Arc::new(map)).apply(&sp, &d);
        let want = Vec3::new(0.6, 0.0, 0.8);
        assert!((mapped.ns - want).length() < 1e-5, "{}", mapped.ns);
        // A neutral texel (0.5, 0.5, 1) leaves the normal alone.
        let neutral = NormalMap::new(1, 1, vec![[0.5, 0.5, 1.0]]).expect("1 × 1 map");
        let same = NormalPerturbation::NormalMap(Arc::new(neutral)).apply(&sp, &d);
        assert!((same.ns - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn a_normal_map_is_read_with_v_up_and_repeats() {
        // Two rows: the top row (v near 1) tilts toward +y, the bottom one toward −y.
        let up = [0.5, 0.8, 0.9];
        let down = [0.5, 0.2, 0.9];
        let map = NormalMap::new(1, 2, vec![up, down]).expect("1 × 2 map");
        assert!(map.tangent_normal(Vec2::new(0.5, 0.75)).y > 0.5);
        assert!(map.tangent_normal(Vec2::new(0.5, 0.25)).y < -0.5);
        // One period up is the same lookup.
        let (a, b) = (map.tangent_normal(Vec2::new(0.3, 0.6)), map.tangent_normal(Vec2::new(1.3, 1.6)));
        assert!((a - b).length() < 1e-5);
        assert!(NormalMap::new(2, 2, vec![up]).is_none());
    }
}

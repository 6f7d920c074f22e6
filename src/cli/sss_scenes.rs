//! The scenes × media of the subsurface report (docs/subsurface.md), built in code so the report
//! needs no files. Units are millimetres (the media's coefficients are per mm).

use crate::camera::Camera;
use crate::geometry::shapes::{axis_box, icosphere, quad};
use crate::geometry::Mesh;
use crate::light::{Light, SpotFalloff, SpotLight, UniformInfiniteLight};
use crate::material::{Material, Roughness, ScatteringSpec, SubsurfaceMaterial};
use crate::math::PI;
use crate::scene::SceneBuilder;
use crate::spectrum::{ColorSpace, RgbKind, Spectrum};
use glam::Vec3;
use std::sync::Arc;

/// A homogeneous medium with RGB coefficients [1/mm].
#[derive(Clone, Copy, Debug)]
pub struct Medium {
    /// Name in the report.
    pub name: &'static str,
    /// Absorption σ_a (RGB) [1/mm].
    pub sigma_a: [f32; 3],
    /// Scattering σ_s (RGB) [1/mm].
    pub sigma_s: [f32; 3],
    /// Boundary index.
    pub eta: f32,
}

/// Skin (Jensen et al. 2001, Skin1: reduced σ′_s and σ_a), marble (same source), and a thin,
/// nearly white medium whose mean free path is comparable to the objects (2–4 mm).
pub const MEDIA: [Medium; 3] = [
    Medium { name: "skin", sigma_a: [0.032, 0.17, 0.48], sigma_s: [0.74, 0.88, 1.01], eta: 1.3 },
    Medium { name: "marble", sigma_a: [0.0021, 0.0041, 0.0071], sigma_s: [2.19, 2.62, 3.00], eta: 1.5 },
    Medium { name: "thin-white", sigma_a: [0.002, 0.003, 0.004], sigma_s: [0.25, 0.3, 0.35], eta: 1.33 },
];

/// The report's geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// A 12 × 12 × 3 mm slab lit by a narrow beam from above.
    Slab,
    /// A sphere of radius 3 mm.
    Sphere,
    /// A torus (radii 3 and 1.2 mm): curved, closed, with thin parts.
    Torus,
}

/// All shapes, in report order.
pub const SHAPES: [Shape; 3] = [Shape::Slab, Shape::Sphere, Shape::Torus];

impl Shape {
    /// Name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Slab => "slab",
            Shape::Sphere => "sphere",
            Shape::Torus => "torus",
        }
    }
}

/// The scene for `shape` made of `medium`.
pub fn build(shape: Shape, medium: &Medium) -> SceneBuilder {
    let space = ColorSpace::srgb();
    let unbounded = |rgb: [f32; 3]| Spectrum::from_rgb(rgb, RgbKind::Unbounded, space);
    let mut b = SceneBuilder::new();
    let spec = ScatteringSpec::Coefficients {
        sigma_a: unbounded(medium.sigma_a),
        sigma_s: unbounded(medium.sigma_s),
        scale: 1.0,
    };
    let sss = b.add_material(Material::Subsurface(Box::new(SubsurfaceMaterial::new(
        spec,
        medium.eta,
        0.0,
        // Rough (GGX α = 0.3) so the random walk can sample the delta lights through the boundary.
        Roughness::alpha(0.3),
    ))));
    let floor = b.add_material(Material::diffuse(Spectrum::constant(0.4)));
    let white = Arc::new(Spectrum::constant(1.0));
    let (object, eye, target, fov) = match shape {
        Shape::Slab => (
            axis_box(Vec3::new(-6.0, -6.0, -3.0), Vec3::new(6.0, 6.0, 0.0)),
            Vec3::new(0.0, -9.0, 9.0),
            Vec3::ZERO,
            40.0,
        ),
        Shape::Sphere => {
            (icosphere(Vec3::new(0.0, 0.0, 3.0), 3.0, 4), Vec3::new(0.0, -12.0, 8.0), Vec3::new(0.0, 0.0, 2.5), 35.0)
        }
        Shape::Torus => (
            torus(Vec3::new(0.0, 0.0, 1.2), 3.0, 1.2, 96, 32),
            Vec3::new(0.0, -10.0, 9.0),
            Vec3::new(0.0, 0.0, 1.0),
            40.0,
        ),
    };
    b.add_mesh(object, sss, None);
    match shape {
        Shape::Slab => {
            // A narrow beam (3° half-angle, ≈2 mm wide on the slab) straight down; flux in W over
            // 360–830 nm.
            let cone =
                SpotFalloff::Cone { cos_start: (2.0f32).to_radians().cos(), cos_end: (3.0f32).to_radians().cos() };
            b.add_light(Light::Spot(SpotLight::with_flux(
                Vec3::new(0.0, 0.0, 20.0),
                -Vec3::Z,
                white.clone(),
                2e4,
                cone,
            )));
        }
        _ => {
            b.add_mesh(quad(Vec3::new(-20.0, -20.0, 0.0), Vec3::X * 40.0, Vec3::Y * 40.0), floor, None);
            let cone =
                SpotFalloff::Cone { cos_start: (20.0f32).to_radians().cos(), cos_end: (25.0f32).to_radians().cos() };
            let pos = Vec3::new(-8.0, 6.0, 14.0);
            b.add_light(Light::Spot(SpotLight::with_flux(pos, -pos.normalize(), white.clone(), 5e5, cone)));
            b.add_light(Light::UniformInfinite(UniformInfiniteLight { spectrum: white.clone(), scale: 0.03 }));
        }
    }
    b.set_camera(Camera::look_at(eye, target, Vec3::Z), fov);
    b
}

/// A torus around the z axis through `center`: major radius `big_r`, minor `r`, wound outward.
pub fn torus(center: Vec3, big_r: f32, r: f32, n_u: u32, n_v: u32) -> Mesh {
    let mut positions = Vec::with_capacity((n_u * n_v) as usize);
    for i in 0..n_u {
        let u = 2.0 * PI * i as f32 / n_u as f32;
        for j in 0..n_v {
            let v = 2.0 * PI * j as f32 / n_v as f32;
            let ring = big_r + r * v.cos();
            positions.push(center + Vec3::new(ring * u.cos(), ring * u.sin(), r * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n_u) * n_v + (j % n_v);
    let mut indices = Vec::with_capacity((2 * n_u * n_v) as usize);
    for i in 0..n_u {
        for j in 0..n_v {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            indices.push([a, b, c]);
            indices.push([a, c, d]);
        }
    }
    Mesh::new(positions, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn torus_is_closed_and_wound_outward() {
        let m = torus(Vec3::ZERO, 3.0, 1.0, 48, 24);
        // Outward winding: the signed volume Σ p0·(p1×p2)/6 is positive and close to 2π²Rr².
        let vol: f32 = (0..m.len())
            .map(|i| {
                let [a, b, c] = m.triangle(i);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        let exact = 2.0 * PI * PI * 3.0;
        assert!((vol - exact).abs() < 0.02 * exact, "volume {vol} vs {exact}");
    }
}

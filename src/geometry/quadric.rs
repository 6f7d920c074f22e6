//! pbrt-v4's quadrics — sphere, disk and cylinder with their partial ranges — in object space,
//! and their tessellation into triangle meshes whose vertices lie on the surface and carry the
//! analytic normal and pbrt-v4's (u, v) (PBR 4th ed. §6.2–6.4).
//!
//! The mesh is inscribed: a triangle's corners are on the surface, its interior at most the
//! sagitta of its longest chord inside it. With angular steps Δφ, Δθ ≤ 2π/96, that distance is
//! below r·(1 − cos(Δ/2))·2 ≈ 1.1·10⁻³ r for the sphere and r·(1 − cos(Δφ/2)) ≈ 5.4·10⁻⁴ r for
//! the cylinder and the disk's rims; the area deficit is of the same relative order.

use glam::{Mat3, Mat4, Vec2, Vec3};

use super::Mesh;

/// Longitude segments per full turn; latitude bands of a full sphere are half as many.
pub const SEGMENTS_PER_TURN: u32 = 96;

/// A quadric in its object space, with pbrt-v4's parameters (lengths in scene units, `phi_max`
/// in degrees, (0, 360]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Quadric {
    /// Sphere of `radius` about the origin, clipped to z ∈ [z_min, z_max] and φ ∈ [0, φmax].
    Sphere {
        /// Radius.
        radius: f32,
        /// Lower z clip.
        z_min: f32,
        /// Upper z clip.
        z_max: f32,
        /// Largest azimuth [degrees].
        phi_max: f32,
    },
    /// Annulus in the plane z = `height` between `inner_radius` and `radius`, φ ∈ [0, φmax].
    Disk {
        /// Plane offset along z.
        height: f32,
        /// Outer radius.
        radius: f32,
        /// Inner radius (0: a full disk).
        inner_radius: f32,
        /// Largest azimuth [degrees].
        phi_max: f32,
    },
    /// Open cylinder of `radius` about the z axis, z ∈ [z_min, z_max], φ ∈ [0, φmax].
    Cylinder {
        /// Radius.
        radius: f32,
        /// Lower end.
        z_min: f32,
        /// Upper end.
        z_max: f32,
        /// Largest azimuth [degrees].
        phi_max: f32,
    },
}

/// A surface point of a quadric at parameters (u, v): position and unit normal, object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricPoint {
    /// Position.
    pub p: Vec3,
    /// Unit normal, the direction of ∂p/∂u × ∂p/∂v (outward for the sphere and cylinder, +z
    /// for the disk).
    pub n: Vec3,
}

impl Quadric {
    /// True for a sphere with no clipping in z or φ (the shape pbrt-v4 samples by solid angle).
    pub fn is_full_sphere(&self) -> bool {
        matches!(*self, Quadric::Sphere { radius, z_min, z_max, phi_max }
            if z_min <= -radius && z_max >= radius && phi_max >= 360.0)
    }

    /// Surface area [scene units²] (pbrt-v4 `Area()`): φmax·r·(zmax − zmin) for the sphere and
    /// cylinder, φmax/2·(r² − rᵢ²) for the disk.
    pub fn area(&self) -> f32 {
        match *self {
            Quadric::Sphere { radius, z_min, z_max, phi_max } | Quadric::Cylinder { radius, z_min, z_max, phi_max } => {
                phi_max.to_radians() * radius * (z_max - z_min)
            }
            Quadric::Disk { radius, inner_radius, phi_max, .. } => {
                0.5 * phi_max.to_radians() * (radius * radius - inner_radius * inner_radius)
            }
        }
    }

    /// The point at pbrt-v4's (u, v): u = φ/φmax for all three; v = (θ − θ(z_min))/(θ(z_max) −
    /// θ(z_min)) with θ = acos(z/r) for the sphere, (z − z_min)/(z_max − z_min) for the cylinder,
    /// (r − ρ)/(r − rᵢ) for the disk (ρ the distance from the axis).
    pub fn point(&self, u: f32, v: f32) -> QuadricPoint {
        // A full turn closes on the very vertices it started from (f32 sin 2π is not 0).
        let phi = |phi_max: f32| if u >= 1.0 && phi_max >= 360.0 { 0.0 } else { u * phi_max.to_radians() };
        match *self {
            Quadric::Sphere { radius, z_min, z_max, phi_max } => {
                let theta_min = (z_min / radius).clamp(-1.0, 1.0).acos();
                let theta_max = (z_max / radius).clamp(-1.0, 1.0).acos();
                let theta = theta_min + v * (theta_max - theta_min);
                // sin θ from cos θ keeps the poles exact (f32 sin(π) is not 0).
                let z = theta.cos();
                let s = (1.0 - z * z).max(0.0).sqrt();
                let (sin_phi, cos_phi) = phi(phi_max).sin_cos();
                let d = Vec3::new(s * cos_phi, s * sin_phi, z);
                QuadricPoint { p: radius * d, n: d }
            }
            Quadric::Cylinder { radius, z_min, z_max, phi_max } => {
                let (sin_phi, cos_phi) = phi(phi_max).sin_cos();
                let z = z_min + v * (z_max - z_min);
                QuadricPoint {
                    p: Vec3::new(radius * cos_phi, radius * sin_phi, z),
                    n: Vec3::new(cos_phi, sin_phi, 0.0),
                }
            }
            Quadric::Disk { height, radius, inner_radius, phi_max } => {
                let (sin_phi, cos_phi) = phi(phi_max).sin_cos();
                let rho = radius - v * (radius - inner_radius);
                QuadricPoint { p: Vec3::new(rho * cos_phi, rho * sin_phi, height), n: Vec3::Z }
            }
        }
    }

    /// pbrt-v4's (u, v) of the point drawn uniformly by area from `u` ∈ [0, 1)² (its `Sample`:
    /// φ uniform; z uniform on a sphere's zone or a cylinder; r² uniform on a disk's annulus).
    pub fn uniform_area_uv(&self, u: Vec2) -> Vec2 {
        let v = match *self {
            Quadric::Sphere { radius, z_min, z_max, .. } => {
                let z = z_min + u.x * (z_max - z_min);
                let theta = (z / radius).clamp(-1.0, 1.0).acos();
                let (t_min, t_max) =
                    ((z_min / radius).clamp(-1.0, 1.0).acos(), (z_max / radius).clamp(-1.0, 1.0).acos());
                (theta - t_min) / (t_max - t_min)
            }
            Quadric::Cylinder { .. } => u.x,
            Quadric::Disk { radius, inner_radius, .. } => {
                let rho = (inner_radius * inner_radius + u.x * (radius * radius - inner_radius * inner_radius)).sqrt();
                (radius - rho) / (radius - inner_radius)
            }
        };
        Vec2::new(u.y, v.clamp(0.0, 1.0))
    }

    /// True when every point has the same normal (a disk), so the normals are one direction; the
    /// other quadrics' normals span every direction.
    pub fn is_planar(&self) -> bool {
        matches!(self, Quadric::Disk { .. })
    }

    /// Grid resolution (segments in u, bands in v) of [`Quadric::tessellate`].
    pub fn grid_size(&self) -> (u32, u32) {
        let turn = |phi_max: f32| ((SEGMENTS_PER_TURN as f32 * phi_max / 360.0).ceil() as u32).max(3);
        match *self {
            Quadric::Sphere { radius, z_min, z_max, phi_max } => {
                let span = (z_min / radius).clamp(-1.0, 1.0).acos() - (z_max / radius).clamp(-1.0, 1.0).acos();
                let bands = (SEGMENTS_PER_TURN as f32 / 2.0 * span / std::f32::consts::PI).ceil() as u32;
                (turn(phi_max), bands.max(2))
            }
            // Straight along v: one band is exact.
            Quadric::Cylinder { phi_max, .. } | Quadric::Disk { phi_max, .. } => (turn(phi_max), 1),
        }
    }

    /// The quadric as an inscribed triangle mesh at the default resolution ([`Quadric::grid_size`]).
    pub fn tessellate(&self) -> Mesh {
        let (n_u, n_v) = self.grid_size();
        self.tessellate_n(n_u, n_v)
    }

    /// The quadric as an `n_u` × `n_v` grid of quads, two triangles each, wound so that their
    /// geometric normals follow the analytic ones; vertices carry the analytic normal and (u, v).
    /// Zero-area triangles (at the sphere's poles, the full disk's centre) are left out.
    pub fn tessellate_n(&self, n_u: u32, n_v: u32) -> Mesh {
        let (n_u, n_v) = (n_u.max(1), n_v.max(1));
        let row = n_u + 1;
        let mut positions = Vec::with_capacity(((n_v + 1) * row) as usize);
        let mut normals = Vec::with_capacity(positions.capacity());
        let mut uvs = Vec::with_capacity(positions.capacity());
        for i in 0..=n_v {
            let v = i as f32 / n_v as f32;
            for j in 0..=n_u {
                let u = j as f32 / n_u as f32;
                let q = self.point(u, v);
                positions.push(q.p);
                normals.push(q.n);
                uvs.push(Vec2::new(u, v));
            }
        }
        let mut indices = Vec::with_capacity((2 * n_u * n_v) as usize);
        for i in 0..n_v {
            for j in 0..n_u {
                let (a, b, c, d) = (i * row + j, i * row + j + 1, (i + 1) * row + j, (i + 1) * row + j + 1);
                for mut t in [[a, b, d], [a, d, c]] {
                    let [p0, p1, p2] = t.map(|k| positions[k as usize]);
                    let ng = (p1 - p0).cross(p2 - p0);
                    if ng.length_squared() == 0.0 {
                        continue;
                    }
                    let n = t.iter().map(|&k| normals[k as usize]).sum::<Vec3>();
                    if ng.dot(n) < 0.0 {
                        t.swap(1, 2);
                    }
                    indices.push(t);
                }
            }
        }
        Mesh { positions, indices, normals: Some(normals), uvs: Some(uvs), faces: None }
    }
}

/// The uniform scale k of `m` when its linear part is k times a rotation or reflection (to a
/// relative 10⁻⁴), so that it maps a quadric to the same quadric k times larger.
pub fn similarity_scale(m: &Mat4) -> Option<f32> {
    let l = Mat3::from_mat4(*m);
    let gram = l.transpose() * l;
    let k2 = gram.x_axis.x;
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * k2;
    let diagonal = close(gram.y_axis.y, k2) && close(gram.z_axis.z, k2);
    let orthogonal = close(gram.x_axis.y, 0.0) && close(gram.x_axis.z, 0.0) && close(gram.y_axis.z, 0.0);
    (k2 > 0.0 && k2.is_finite() && diagonal && orthogonal).then(|| k2.sqrt())
}

/// The smallest distance from `center` to the plane of any triangle of `mesh`, each triangle's
/// corners lying on the sphere of `radius` about `center`: √(r² − R²) with R the triangle's
/// circumradius (abc / 4A). The mesh lies in the shell between this radius and `radius`.
pub fn inscribed_inner_radius(mesh: &Mesh, center: Vec3, radius: f32) -> f32 {
    (0..mesh.len())
        .map(|i| {
            let [p0, p1, p2] = mesh.triangle(i).map(|p| p - center);
            let (a, b, c) = ((p1 - p0).length(), (p2 - p1).length(), (p0 - p2).length());
            let twice_area = (p1 - p0).cross(p2 - p0).length();
            let circum = a * b * c / (2.0 * twice_area);
            (radius * radius - circum * circum).max(0.0).sqrt()
        })
        .fold(radius, f32::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    fn sphere(radius: f32, z_min: f32, z_max: f32, phi_max: f32) -> Quadric {
        Quadric::Sphere { radius, z_min, z_max, phi_max }
    }

    #[test]
    fn tessellated_areas_converge_to_the_analytic_areas_from_below() {
        // Zone of a sphere: 2πr·(zmax − zmin)·φmax/360; cylinder the same; annulus sector
        // φmax/2·(r² − rᵢ²). Inscribed polygons miss O(Δ²) ≈ (2π/96)²/6 ≈ 7·10⁻⁴ of it.
        let cases = [
            (sphere(2.0, -2.0, 2.0, 360.0), 4.0 * PI * 4.0),
            (sphere(1.0, -0.5, 0.5, 180.0), PI),
            (
                Quadric::Cylinder { radius: 0.7, z_min: 0.0, z_max: 1.3, phi_max: 240.0 },
                2.0 * PI * 0.7 * 1.3 * 240.0 / 360.0,
            ),
            (
                Quadric::Disk { height: 0.1, radius: 1.0, inner_radius: 0.45, phi_max: 270.0 },
                PI * (1.0 - 0.45 * 0.45) * 270.0 / 360.0,
            ),
            (Quadric::Disk { height: 0.0, radius: 2.0, inner_radius: 0.0, phi_max: 360.0 }, 4.0 * PI),
        ];
        for (q, exact) in cases {
            let m = q.tessellate();
            assert!((q.area() - exact).abs() < 1e-5 * exact, "{q:?}: area() {} vs {exact}", q.area());
            let rel = (exact - m.area()) / exact;
            assert!((0.0..1e-3).contains(&rel), "{q:?}: relative deficit {rel}");
            for i in 0..m.len() {
                let [a, b, c] = m.triangle(i);
                let ng = (b - a).cross(c - a);
                let t = m.indices[i];
                let n: Vec3 = t.iter().map(|&k| m.normals.as_ref().unwrap()[k as usize]).sum();
                assert!(ng.dot(n) > 0.0, "{q:?}: triangle {i} winds against its normals");
            }
        }
    }

    #[test]
    fn vertices_lie_on_the_surface_with_pbrt_v4_uv_and_normals() {
        // Each vertex checked against the implicit surface, the normal against ∂p/∂u × ∂p/∂v
        // by central differences of the parameterisation written out here, and (u, v) against
        // pbrt-v4's inverse mapping from the position.
        let (r, z_min, z_max, phi_max) = (2.0f32, -1.0f32, 1.5f32, 270.0f32);
        let phi_of = |p: Vec3| {
            let phi = p.y.atan2(p.x);
            if phi < 0.0 {
                phi + 2.0 * PI
            } else {
                phi
            }
        };
        let s = sphere(r, z_min, z_max, phi_max);
        let m = s.tessellate();
        let (t_min, t_max) = ((z_min / r).acos(), (z_max / r).acos());
        for ((p, uv), n) in m.positions.iter().zip(m.uvs.as_ref().unwrap()).zip(m.normals.as_ref().unwrap()) {
            assert!((p.length() - r).abs() < 1e-5);
            assert!((*n - *p / r).length() < 1e-5);
            let v = ((p.z / r).clamp(-1.0, 1.0).acos() - t_min) / (t_max - t_min);
            assert!((uv.y - v).abs() < 1e-4, "{p}: v {} vs {v}", uv.y);
            if p.x * p.x + p.y * p.y > 1e-6 && uv.x > 1e-6 && uv.x < 0.999 {
                assert!((uv.x - phi_of(*p) / phi_max.to_radians()).abs() < 1e-4, "{p}: u {}", uv.x);
            }
        }
        let c = Quadric::Cylinder { radius: 0.7, z_min: -0.2, z_max: 1.3, phi_max: 240.0 };
        let d = Quadric::Disk { height: 0.1, radius: 1.0, inner_radius: 0.45, phi_max: 270.0 };
        for (u, v) in [(0.0, 0.0), (0.3, 0.6), (1.0, 1.0), (0.77, 0.1)] {
            let q = c.point(u, v);
            assert!(((q.p.x * q.p.x + q.p.y * q.p.y).sqrt() - 0.7).abs() < 1e-5);
            assert!((q.p.z - (-0.2 + 1.5 * v)).abs() < 1e-5);
            if u < 1.0 {
                assert!((phi_of(q.p) / 240f32.to_radians() - u).abs() < 1e-4);
            }
            let h = 1e-3;
            let dpdu = (c.point(u + h, v).p - c.point(u - h, v).p) / (2.0 * h);
            let dpdv = (c.point(u, v + h).p - c.point(u, v - h).p) / (2.0 * h);
            assert!((dpdu.cross(dpdv).normalize() - q.n).length() < 1e-3, "cylinder n {}", q.n);
            let q = d.point(u, v);
            let rho = (q.p.x * q.p.x + q.p.y * q.p.y).sqrt();
            assert!(((1.0 - rho) / (1.0 - 0.45) - v).abs() < 1e-5 && q.p.z == 0.1);
            let dpdu = (d.point(u + h, v).p - d.point(u - h, v).p) / (2.0 * h);
            let dpdv = (d.point(u, v + h).p - d.point(u, v - h).p) / (2.0 * h);
            assert!((dpdu.cross(dpdv).normalize() - q.n).length() < 1e-3, "disk n {}", q.n);
        }
    }

    #[test]
    fn the_inscribed_mesh_stays_within_its_stated_shell() {
        let s = sphere(1.5, -1.5, 1.5, 360.0);
        assert!(s.is_full_sphere() && !sphere(1.5, -1.0, 1.5, 360.0).is_full_sphere());
        let m = s.tessellate();
        let inner = inscribed_inner_radius(&m, Vec3::ZERO, 1.5);
        // Bound of the module doc: 1.1·10⁻³ r.
        assert!(inner < 1.5 && inner > 1.5 * (1.0 - 1.1e-3), "inner radius {inner}");
        // Points spread over every triangle are in the shell [inner, r].
        for i in 0..m.len() {
            let [a, b, c] = m.triangle(i);
            for (x, y) in [(1.0 / 3.0, 1.0 / 3.0), (0.5, 0.5), (0.5, 0.0), (0.1, 0.2)] {
                let d = (a + (b - a) * x + (c - a) * y).length();
                assert!(d >= inner * (1.0 - 1e-6) && d <= 1.5 * (1.0 + 1e-6), "triangle {i}: |p| = {d}");
            }
        }
    }
}

//! Mesh generators for tests and benchmarks (spheres, boxes, terrain, random soups, quads), a
//! bundle of hair curves and a grid of twisted ribbons with rays aimed at them, and
//! [`Mesh::transformed`].
//!
//! Closed shapes share vertices between neighbouring triangles, so a watertight ray–triangle test
//! over them must never let a ray through an edge or a vertex.

use std::collections::HashMap;

use glam::{Mat3, Mat4, Vec3};

use super::curve::{bezier_segments, CurveBasis};
use super::{CurveKind, CurveSegment, Curves, Mesh, Ray};
use crate::sampling::Rng;

impl Mesh {
    /// This mesh with positions transformed by the affine `m` and normals by its inverse transpose
    /// (renormalised). Triangle winding is flipped when `m` mirrors (det < 0), so geometric normals
    /// keep pointing the same way relative to the surface.
    pub fn transformed(&self, m: &Mat4) -> Mesh {
        // One spare slot: Embree reads the positions in place only with room for its 16-byte
        // load at the last vertex (`accel::build_scene_shared`).
        let mut positions = Vec::with_capacity(self.positions.len() + 1);
        positions.extend_from_slice(&self.positions);
        let copy = Mesh {
            positions,
            indices: self.indices.clone(),
            normals: self.normals.clone(),
            uvs: self.uvs.clone(),
            faces: self.faces.clone(),
        };
        copy.into_transformed(m)
    }

    /// [`Self::transformed`], in place: no copy of a mesh whose transform is the identity.
    pub fn into_transformed(mut self, m: &Mat4) -> Mesh {
        use crate::geometry::MIN_ELEMENTS_PER_THREAD;
        use rayon::prelude::*;
        if self.positions.capacity() == self.positions.len() {
            self.positions.reserve_exact(1);
        }
        if *m != Mat4::IDENTITY {
            self.positions
                .par_iter_mut()
                .with_min_len(MIN_ELEMENTS_PER_THREAD)
                .for_each(|p| *p = m.transform_point3(*p));
        }
        let linear = Mat3::from_mat4(*m);
        if let Some(normals) = &mut self.normals {
            let normal_matrix = linear.inverse().transpose();
            normals
                .par_iter_mut()
                .with_min_len(MIN_ELEMENTS_PER_THREAD)
                .for_each(|n| *n = (normal_matrix * *n).normalize_or_zero());
        }
        if linear.determinant() < 0.0 {
            self.indices.par_iter_mut().with_min_len(MIN_ELEMENTS_PER_THREAD).for_each(|t| t.swap(1, 2));
        }
        self
    }
}

/// An icosphere: a regular icosahedron subdivided `subdivisions` times (20·4^s triangles), vertices
/// projected onto the sphere. Closed, outward winding, shared vertices, unit normals.
pub fn icosphere(center: Vec3, radius: f32, subdivisions: u32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut dirs: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&a| Vec3::from_array(a).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        // Each edge's midpoint is created once, so neighbours share it (no T-junctions).
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, dirs: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *midpoints.entry(key).or_insert_with(|| {
                dirs.push((dirs[a as usize] + dirs[b as usize]).normalize());
                dirs.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for &[a, b, c] in &tris {
            let ab = midpoint(a, b, &mut dirs);
            let bc = midpoint(b, c, &mut dirs);
            let ca = midpoint(c, a, &mut dirs);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    let positions = dirs.iter().map(|&d| center + radius * d).collect();
    Mesh { positions, indices: tris, normals: Some(dirs), uvs: None, faces: None }
}

/// A UV sphere with `n_theta` ≥ 2 latitude bands and `n_phi` ≥ 3 longitude segments (z is the polar
/// axis). Closed: one shared vertex per pole, the seam at φ = 0 reuses the first column.
/// Counts below the minimum are raised to it.
pub fn uv_sphere(center: Vec3, radius: f32, n_theta: u32, n_phi: u32) -> Mesh {
    let (n_theta, n_phi) = (n_theta.max(2), n_phi.max(3));
    let mut dirs = vec![Vec3::Z];
    for i in 1..n_theta {
        let theta = std::f32::consts::PI * i as f32 / n_theta as f32;
        for j in 0..n_phi {
            let phi = std::f32::consts::TAU * j as f32 / n_phi as f32;
            dirs.push(Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()));
        }
    }
    dirs.push(-Vec3::Z);
    let south = dirs.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * n_phi + j % n_phi;
    let mut indices = Vec::new();
    for j in 0..n_phi {
        indices.push([0, ring(1, j), ring(1, j + 1)]);
        indices.push([south, ring(n_theta - 1, j + 1), ring(n_theta - 1, j)]);
    }
    for i in 1..n_theta - 1 {
        for j in 0..n_phi {
            let (a, b, c, d) = (ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1));
            indices.push([a, c, d]);
            indices.push([a, d, b]);
        }
    }
    let positions = dirs.iter().map(|&d| center + radius * d).collect();
    Mesh { positions, indices, normals: Some(dirs), uvs: None, faces: None }
}

/// A closed axis-aligned box from `min` to `max`: 8 shared corners, 12 triangles wound outward.
pub fn axis_box(min: Vec3, max: Vec3) -> Mesh {
    let corner = |i: u32| {
        Vec3::new(
            if i & 1 != 0 { max.x } else { min.x },
            if i & 2 != 0 { max.y } else { min.y },
            if i & 4 != 0 { max.z } else { min.z },
        )
    };
    let positions = (0..8).map(corner).collect();
    // Faces as corner quads (counter-clockwise seen from outside).
    let faces: [[u32; 4]; 6] = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
    let indices = faces.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    Mesh::new(positions, indices)
}

/// A quad with corner `p0` and edges `e1`, `e2` (two triangles, normal along e1 × e2), with uvs.
pub fn quad(p0: Vec3, e1: Vec3, e2: Vec3) -> Mesh {
    let positions = vec![p0, p0 + e1, p0 + e1 + e2, p0 + e2];
    let mut m = Mesh::new(positions, vec![[0, 1, 2], [0, 2, 3]]);
    m.uvs = Some(vec![glam::Vec2::ZERO, glam::Vec2::X, glam::Vec2::ONE, glam::Vec2::Y]);
    m
}

/// A heightfield over [-size/2, size/2]² in the xz-plane with `resolution`² cells (2·resolution²
/// triangles; resolution 708 gives ≈1M). Heights are a few sine octaves of amplitude `amplitude`
/// with phases from `seed`, so the surface is smooth but not axis-aligned.
pub fn terrain(size: f32, resolution: u32, amplitude: f32, seed: u64) -> Mesh {
    let n = resolution.max(1);
    let mut rng = Rng::new(seed, 0);
    let waves: Vec<(f32, f32, f32)> = (0..4)
        .map(|k| {
            let freq = (k + 1) as f32 * std::f32::consts::TAU / size;
            (freq, rng.uniform() * 6.3, rng.uniform() * 6.3)
        })
        .collect();
    let height = |x: f32, z: f32| {
        waves
            .iter()
            .enumerate()
            .map(|(k, &(f, px, pz))| amplitude / (k + 1) as f32 * (f * x + px).sin() * (f * z + pz).cos())
            .sum::<f32>()
    };
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for i in 0..=n {
        for j in 0..=n {
            let x = size * (j as f32 / n as f32 - 0.5);
            let z = size * (i as f32 / n as f32 - 0.5);
            positions.push(Vec3::new(x, height(x, z), z));
        }
    }
    let id = |i: u32, j: u32| i * (n + 1) + j;
    let mut indices = Vec::with_capacity((2 * n * n) as usize);
    for i in 0..n {
        for j in 0..n {
            // Wound so the normal points up (+y).
            indices.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            indices.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::new(positions, indices)
}

/// `count` independent random triangles: centres uniform in the box `[min, max]`, vertices within
/// `size` of their centre. Unshared vertices (3 per triangle).
pub fn triangle_soup(count: usize, min: Vec3, max: Vec3, size: f32, seed: u64) -> Mesh {
    let mut rng = Rng::new(seed, 1);
    let mut positions = Vec::with_capacity(3 * count);
    for _ in 0..count {
        let c = min + (max - min) * Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
        for _ in 0..3 {
            let off = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - 1.0;
            positions.push(c + size * off);
        }
    }
    let indices = (0..count as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    Mesh::new(positions, indices)
}

/// `count` strands of `kind` rising along +y from a disc of radius 0.5 at the origin to a height
/// of 1.2, each one cubic B-spline of 5 control points (2 Bézier segments) bent at random, 0.02
/// wide at the root and 0.008 at the tip. A ribbon's normal, radial, is the same at both ends of
/// each strand.
pub fn hair_bundle(count: usize, kind: CurveKind, seed: u64) -> Curves {
    let mut rng = Rng::new(seed, 1);
    let width = |u: f32| 0.02 + (0.008 - 0.02) * u;
    let mut segments = Vec::with_capacity(2 * count);
    for _ in 0..count {
        let r = 0.5 * rng.uniform().sqrt();
        let phi = std::f32::consts::TAU * rng.uniform();
        let root = Vec3::new(r * phi.cos(), 0.0, r * phi.sin());
        let lean = Vec3::new(rng.uniform() - 0.5, 0.0, rng.uniform() - 0.5) * 0.6;
        let p: Vec<Vec3> = (0..5).map(|k| root + Vec3::Y * (0.3 * k as f32) + lean * (k * k) as f32 / 16.0).collect();
        let normal = Vec3::new(phi.cos(), 0.0, phi.sin());
        let cps = bezier_segments(&p, CurveBasis::BSpline, 3).expect("5 points make 2 cubic B-spline segments");
        let n = cps.len() as f32;
        for (i, cp) in cps.into_iter().enumerate() {
            let w = [width(i as f32 / n), width((i + 1) as f32 / n)];
            segments.push(CurveSegment::new(cp, w, kind, [normal; 2]));
        }
    }
    Curves { segments, split_depth: 2, flip_normal: false }
}

/// `count` rays from a sphere of radius 4 about [`hair_bundle`] toward random points inside its
/// box.
pub fn rays_into_hair_bundle(count: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 3);
    (0..count)
        .map(|_| {
            let z = 1.0 - 2.0 * rng.uniform();
            let s = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f32::consts::TAU * rng.uniform();
            let o = Vec3::new(0.0, 0.6, 0.0) + 4.0 * Vec3::new(s * phi.cos(), z, s * phi.sin());
            let target = Vec3::new(rng.uniform() - 0.5, 1.2 * rng.uniform(), rng.uniform() - 0.5);
            Ray::new(o, (target - o).normalize())
        })
        .collect()
}

/// 100 one-segment ribbons standing on a 10 × 10 grid over [−0.5, 0.5]², from y = 0 to 1 with a
/// slight lean, `width` wide at the root and 0.6 `width` at the tip, each turning its normal by
/// `twist` [radians] about the vertical from root to tip.
pub fn ribbon_grid(twist: f32, width: f32) -> Curves {
    let mut rng = Rng::new(5, 9);
    let segments = (0..100)
        .map(|i| {
            let root = Vec3::new((i % 10) as f32 / 9.0 - 0.5, 0.0, (i / 10) as f32 / 9.0 - 0.5);
            let lean = Vec3::new(rng.uniform() - 0.5, 0.0, rng.uniform() - 0.5) * 0.1;
            let cp = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0].map(|y: f32| root + Vec3::Y * y + lean * y * y);
            let phi = std::f32::consts::TAU * rng.uniform();
            let n = |a: f32| Vec3::new(a.cos(), 0.0, a.sin());
            CurveSegment::new(cp, [width, 0.6 * width], CurveKind::Ribbon, [n(phi), n(phi + twist)])
        })
        .collect();
    Curves { segments, split_depth: 3, flip_normal: false }
}

/// A horizontal ray from 3 units away at a random azimuth toward a random point among the
/// strands of [`ribbon_grid`]: across them, where a ribbon's seen width w·|n·d̂| is its
/// projected width.
pub fn level_ray_into_ribbon_grid(rng: &mut Rng) -> Ray {
    let target = Vec3::new(rng.uniform() - 0.5, rng.uniform(), rng.uniform() - 0.5);
    let phi = std::f32::consts::TAU * rng.uniform();
    let o = target + 3.0 * Vec3::new(phi.cos(), 0.0, phi.sin());
    Ray::new(o, (target - o).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edge of a closed, consistently wound mesh is used once in each direction.
    fn assert_closed_manifold(m: &Mesh) {
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for &[a, b, c] in &m.indices {
            for (p, q) in [(a, b), (b, c), (c, a)] {
                *edges.entry((p, q)).or_default() += 1;
            }
        }
        for (&(p, q), &n) in &edges {
            assert_eq!(n, 1, "edge {p}-{q} used {n} times");
            assert_eq!(edges.get(&(q, p)), Some(&1), "edge {p}-{q} has no twin");
        }
    }

    /// Signed volume by the divergence theorem: Σ p0·(p1×p2)/6.
    fn volume(m: &Mesh) -> f32 {
        (0..m.len())
            .map(|i| {
                let [a, b, c] = m.triangle(i);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn closed_shapes_are_manifold_with_outward_winding() {
        let ico = icosphere(Vec3::ZERO, 2.0, 3);
        assert_eq!(ico.len(), 20 * 64);
        assert_closed_manifold(&ico);
        let sphere_volume = 4.0 / 3.0 * std::f32::consts::PI * 8.0;
        // An inscribed polyhedron is slightly smaller than the sphere.
        assert!(volume(&ico) > 0.97 * sphere_volume && volume(&ico) < sphere_volume);

        let uv = uv_sphere(Vec3::ZERO, 2.0, 32, 64);
        assert_closed_manifold(&uv);
        assert!(volume(&uv) > 0.97 * sphere_volume && volume(&uv) < sphere_volume);

        let b = axis_box(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(2.0, 1.0, 4.0));
        assert_closed_manifold(&b);
        assert!((volume(&b) - 6.0).abs() < 1e-5);
        assert!((b.area() - 2.0 * (3.0 + 6.0 + 2.0)).abs() < 1e-5);
    }

    #[test]
    fn transformed_scales_volume_and_keeps_orientation_under_mirroring() {
        let b = axis_box(Vec3::ZERO, Vec3::ONE);
        let m = Mat4::from_scale(Vec3::new(2.0, 3.0, 1.0)) * Mat4::from_rotation_y(0.3);
        assert!((volume(&b.transformed(&m)) - 6.0).abs() < 1e-4);
        let mirrored = b.transformed(&Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        assert!((volume(&mirrored) - 1.0).abs() < 1e-5);
        let s = icosphere(Vec3::ZERO, 1.0, 1).transformed(&Mat4::from_translation(Vec3::X));
        for (p, n) in s.positions.iter().zip(s.normals.unwrap()) {
            assert!((*p - Vec3::X - n).length() < 1e-5);
        }
    }

    #[test]
    fn terrain_and_soup_have_requested_sizes() {
        let t = terrain(10.0, 20, 0.5, 3);
        assert_eq!(t.len(), 800);
        assert!((t.bounds().max.x - 5.0).abs() < 1e-6);
        // Up-facing: every geometric normal has positive y.
        assert!((0..t.len()).all(|i| {
            let [a, b, c] = t.triangle(i);
            (b - a).cross(c - a).y > 0.0
        }));
        let s = triangle_soup(100, Vec3::ZERO, Vec3::ONE, 0.1, 9);
        assert_eq!(s.len(), 100);
        assert!(s.bounds().min.cmpge(Vec3::splat(-0.1)).all());
        let q = quad(Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!((q.area() - 1.0).abs() < 1e-6);
    }
}

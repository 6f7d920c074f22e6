//! pbrt-v4's bilinear patches as triangles (PBR 4th ed. §6.6): the patch
//! p(u, v) = (1−u)(1−v) p00 + u(1−v) p10 + (1−u) v p01 + u v p11 is sampled on an n × n grid of
//! its own (u, v), each vertex carrying the patch's (u, v) — or the bilinear blend of the
//! corners' `uv` — and the blend of the corners' normals.
//!
//! Error bound: on the triangle (p00, p10, p11) of a cell the patch departs from the triangle's
//! affine interpolant by −v(1−u)·d with d = p00 − p10 − p01 + p11 (the other triangle alike), at
//! most |d|/4; on an n × n grid each cell's d is d/n², so positions and (u, v) are within
//! |d|/(4n²) of the patch's. A parallelogram (d = 0) is exact with one cell; otherwise n is the
//! smallest that brings the bound under [`RELATIVE_ERROR`] of the patch's diagonal.

use glam::{Vec2, Vec3};

use super::Mesh;

/// Largest distance between the triangles and the patch, relative to the patch's diagonal.
pub const RELATIVE_ERROR: f32 = 1e-4;

/// Most cells along each side of a patch.
pub const MAX_CELLS: u32 = 64;

/// Cells along each side for the patch with corners `p` = [p00, p10, p01, p11].
pub fn cells(p: [Vec3; 4]) -> u32 {
    let d = (p[0] - p[1] - p[2] + p[3]).length();
    let diag = (p[3] - p[0]).length().max((p[2] - p[1]).length());
    if !(d > 0.0 && diag > 0.0) || d <= 4.0 * RELATIVE_ERROR * diag {
        return 1;
    }
    ((d / (4.0 * RELATIVE_ERROR * diag)).sqrt().ceil() as u32).clamp(1, MAX_CELLS)
}

fn blend<T>(c: [T; 4], u: f32, v: f32) -> T
where
    T: std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T> + Copy,
{
    c[0] * ((1.0 - u) * (1.0 - v)) + c[1] * (u * (1.0 - v)) + c[2] * ((1.0 - u) * v) + c[3] * (u * v)
}

/// Triangles for the bilinear patches `patches` (vertex indices p00, p10, p01, p11 into
/// `positions`, already checked), with optional per-vertex `normals` and `uvs`. Each patch gets
/// vertices of its own, so that (u, v) never has to be shared between patches, and its triangles
/// carry its index as their face.
pub fn triangulate(positions: &[Vec3], patches: &[[u32; 4]], normals: Option<&[Vec3]>, uvs: Option<&[Vec2]>) -> Mesh {
    let mut mesh = Mesh {
        positions: Vec::new(),
        indices: Vec::new(),
        normals: normals.map(|_| Vec::new()),
        uvs: Some(Vec::new()),
        faces: Some(Vec::new()),
    };
    for (face, patch) in patches.iter().enumerate() {
        let p = patch.map(|i| positions[i as usize]);
        let corner_uv = match uvs {
            Some(uv) => patch.map(|i| uv[i as usize]),
            None => [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE],
        };
        let n = cells(p);
        let first = mesh.positions.len() as u32;
        for i in 0..=n {
            let v = i as f32 / n as f32;
            for j in 0..=n {
                let u = j as f32 / n as f32;
                mesh.positions.push(blend(p, u, v));
                if let Some(uv) = mesh.uvs.as_mut() {
                    uv.push(blend(corner_uv, u, v));
                }
                if let (Some(out), Some(ns)) = (mesh.normals.as_mut(), normals) {
                    out.push(blend(patch.map(|k| ns[k as usize]), u, v).normalize_or_zero());
                }
            }
        }
        let row = n + 1;
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (i * row + j, i * row + j + 1, (i + 1) * row + j, (i + 1) * row + j + 1);
                // p00, p10, p11 and p00, p11, p01 of each cell, as a single patch splits.
                mesh.indices.push([first + a, first + b, first + d]);
                mesh.indices.push([first + a, first + d, first + c]);
            }
        }
        if let Some(faces) = mesh.faces.as_mut() {
            faces.resize(mesh.indices.len(), face as u32);
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bilinear(p: [Vec3; 4], u: f32, v: f32) -> Vec3 {
        p[0] * (1.0 - u) * (1.0 - v) + p[1] * u * (1.0 - v) + p[2] * (1.0 - u) * v + p[3] * u * v
    }

    /// Barycentric coordinates of `x` in triangle `t` (least squares, for points on its plane).
    fn barycentric(t: [Vec3; 3], x: Vec3) -> [f32; 3] {
        let (e1, e2, r) = (t[1] - t[0], t[2] - t[0], x - t[0]);
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (r1, r2) = (r.dot(e1), r.dot(e2));
        let det = d11 * d22 - d12 * d12;
        let b1 = (d22 * r1 - d12 * r2) / det;
        let b2 = (d11 * r2 - d12 * r1) / det;
        [1.0 - b1 - b2, b1, b2]
    }

    #[test]
    fn a_parallelogram_without_uv_gets_the_patch_uv_on_both_triangles() {
        // u along p00→p10 and v along p00→p01 everywhere: the sheared half of the quad had
        // (0,0), (1,0), (1,1) for (p00, p11, p01) before.
        let p = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.5, 0.0, 1.0), Vec3::new(2.5, 0.0, 1.0)];
        let m = triangulate(&p, &[[0, 1, 2, 3]], None, None);
        assert_eq!(m.len(), 2);
        let uvs = m.uvs.as_ref().unwrap();
        for (u, v) in [(0.25, 0.75), (0.8, 0.1), (0.5, 0.5), (0.1, 0.9)] {
            let x = bilinear(p, u, v);
            let hit = (0..m.len())
                .find_map(|i| {
                    let b = barycentric(m.triangle(i), x);
                    b.iter().all(|&w| w >= -1e-6).then_some((i, b))
                })
                .expect("the point is on the quad");
            let t = m.indices[hit.0];
            let uv = uvs[t[0] as usize] * hit.1[0] + uvs[t[1] as usize] * hit.1[1] + uvs[t[2] as usize] * hit.1[2];
            assert!((uv - Vec2::new(u, v)).length() < 1e-5, "({u}, {v}) → {uv}");
        }
    }

    #[test]
    fn a_saddle_is_refined_until_its_triangles_are_within_the_bound() {
        // d = (0, −3.6, 0): |d|/4 = 0.9 from two triangles. The departure −v(1−u)d/n² of a cell
        // peaks at its centre, the midpoint of the shared diagonal: there the grid must be within
        // 10⁻⁴ of the diagonal of the patch.
        let p = [
            Vec3::new(-1.1, 0.1, -0.2),
            Vec3::new(1.1, 1.9, -0.2),
            Vec3::new(-1.1, 1.9, 0.2),
            Vec3::new(1.1, 0.1, 0.2),
        ];
        let n = cells(p);
        assert!(n > 1 && n <= MAX_CELLS, "{n} cells");
        let m = triangulate(&p, &[[0, 1, 2, 3]], None, None);
        assert_eq!(m.len() as u32, 2 * n * n);
        let diag = (p[3] - p[0]).length().max((p[2] - p[1]).length());
        let mut worst = 0.0f32;
        for i in 0..n {
            for j in 0..n {
                let (u, v) = ((j as f32 + 0.5) / n as f32, (i as f32 + 0.5) / n as f32);
                let t = m.triangle((2 * (i * n + j)) as usize);
                worst = worst.max((0.5 * (t[0] + t[2]) - bilinear(p, u, v)).length());
            }
        }
        let bound = RELATIVE_ERROR * diag;
        assert!(worst > 0.5 * bound && worst <= bound * 1.001, "worst {worst} vs bound {bound}");
        // Two triangles: the diagonal's midpoint misses the patch's centre by |d|/4.
        let two = 0.5 * (p[0] + p[3]) - bilinear(p, 0.5, 0.5);
        assert!((two.length() - 0.9).abs() < 1e-5);
    }

    /// Every triangle of a patch, however finely it is cut, carries the patch's index as its
    /// face, so the faces' areas are the patches' (a parallelogram's |e₁ × e₂|).
    #[test]
    fn the_triangles_of_each_patch_make_one_face() {
        let saddle = [
            Vec3::new(-1.1, 0.1, -0.2),
            Vec3::new(1.1, 1.9, -0.2),
            Vec3::new(-1.1, 1.9, 0.2),
            Vec3::new(1.1, 0.1, 0.2),
        ];
        let flat =
            [Vec3::new(5.0, 0.0, 0.0), Vec3::new(7.0, 0.0, 0.0), Vec3::new(5.5, 3.0, 0.0), Vec3::new(7.5, 3.0, 0.0)];
        let positions: Vec<Vec3> = saddle.iter().chain(&flat).copied().collect();
        let m = triangulate(&positions, &[[0, 1, 2, 3], [4, 5, 6, 7]], None, None);
        let n = cells(saddle) as usize;
        let faces = m.faces.as_ref().unwrap();
        assert_eq!(faces.len(), m.len());
        assert!(faces[..2 * n * n].iter().all(|&f| f == 0) && faces[2 * n * n..] == [1, 1]);
        let areas = m.face_areas();
        assert!((areas[m.len() - 1] - 6.0).abs() < 1e-5, "{}", areas[m.len() - 1]);
        let saddle_area: f32 = (0..2 * n * n).map(|i| m.triangle_area(i)).sum();
        assert!(areas[..2 * n * n].iter().all(|&a| a == saddle_area));
    }
}

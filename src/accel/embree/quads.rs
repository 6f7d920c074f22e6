//! A mesh's triangles paired into Embree quads, and quad hits mapped back to triangles.
//!
//! Embree intersects a quad (v0, v1, v2, v3) as the two triangles (v0, v1, v3) and
//! (v2, v3, v1), and reports a hit on the second at (u, v) = (1 − u′, 1 − v′) of its own
//! barycentrics (u′, v′); a triangle alone is the quad (v0, v1, v2, v2), whose second half is a
//! line that is never hit (Embree's `RTC_GEOMETRY_TYPE_QUAD`). Two triangles t and t + 1 of a
//! mesh that share an edge, walked in opposite directions (the same orientation), make one
//! quad: half as many primitives for Embree's BVH build, which is what its time and memory go
//! by. Meshes written from quads or grids (heightfields, subdivided and modelled surfaces)
//! list the two halves of each quad one after the other; other meshes pair fewer triangles and
//! lose nothing but the pairing pass.

use rayon::prelude::*;

/// Triangles a parallel pairing task takes at once (even, so that pairs never straddle two).
const CHUNK: usize = 1 << 16;

/// The quads of one mesh and, for each, the triangles it holds.
pub(super) struct QuadPairs {
    /// Embree's index buffer: four vertex indices per quad.
    pub(super) indices: Vec<[u32; 4]>,
    /// Per quad, the mesh's triangle behind the first half (v0, v1, v3); the second half, if
    /// any, is the next triangle.
    first: Vec<u32>,
    /// Per quad: bits 0–1, how far the first half's vertex order is rotated from its
    /// triangle's ((v0, v1, v3) starts at the triangle's vertex `r`); bits 2–3, the same for the
    /// second half (v2, v3, v1); bit 4, set when the quad holds two triangles.
    layout: Vec<u8>,
}

const PAIRED: u8 = 1 << 4;

/// The quad of triangle `a` and the next one, `b`, if they share an edge with opposite
/// directions: its vertices and layout bits.
fn pair(a: [u32; 3], b: [u32; 3]) -> Option<([u32; 4], u8)> {
    for i in 0..3 {
        let (a0, a1) = (a[i], a[(i + 1) % 3]);
        for j in 0..3 {
            if b[j] == a1 && b[(j + 1) % 3] == a0 {
                // (v0, v1, v3) = a from vertex i + 2: v1 = a0, v3 = a1. (v2, v3, v1) = b from
                // its vertex opposite the edge, j + 2.
                let (ra, rb) = ((i + 2) % 3, (j + 2) % 3);
                let quad = [a[ra], a0, b[rb], a1];
                return Some((quad, ra as u8 | (rb as u8) << 2 | PAIRED));
            }
        }
    }
    None
}

impl QuadPairs {
    /// Pairs each triangle with the next one where they make a quad (`pair`), in order.
    pub(super) fn new(triangles: &[[u32; 3]]) -> Self {
        let chunks: Vec<_> = triangles.par_chunks(CHUNK).map(pair_run).collect();
        let n: usize = chunks.iter().map(|c| c.0.len()).sum();
        let mut q =
            Self { indices: Vec::with_capacity(n), first: Vec::with_capacity(n), layout: Vec::with_capacity(n) };
        for (k, (indices, first, layout)) in chunks.into_iter().enumerate() {
            let offset = (k * CHUNK) as u32;
            q.indices.extend_from_slice(&indices);
            q.first.extend(first.iter().map(|&f| f + offset));
            q.layout.extend_from_slice(&layout);
        }
        q
    }

    /// Quads.
    pub(super) fn len(&self) -> usize {
        self.indices.len()
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        self.indices.capacity() * 16 + self.first.capacity() * 4 + self.layout.capacity()
    }

    /// The triangle, and its barycentrics (u, v) in its own vertex order (as Embree's triangle
    /// geometry reports them), of a hit on `quad` at Embree's quad coordinates (u, v).
    #[inline]
    pub(super) fn triangle_hit(&self, quad: u32, u: f32, v: f32) -> (u32, f32, f32) {
        let (first, layout) = (self.first[quad as usize], self.layout[quad as usize]);
        // On the diagonal both halves give the same point; past it (u + v > 1) the hit is on
        // the second half, whose own barycentrics are (1 − u, 1 − v).
        let (triangle, rotation, u, v) = if layout & PAIRED != 0 && u + v > 1.0 {
            (first + 1, (layout >> 2) & 3, 1.0 - u, 1.0 - v)
        } else {
            (first, layout & 3, u, v)
        };
        // Weights of the half's vertices (p0, p1, p2) = the triangle's (r, r + 1, r + 2).
        let w = [1.0 - u - v, u, v];
        let at = |k: usize| w[(k + 3 - rotation as usize) % 3];
        (triangle, at(1), at(2))
    }
}

/// [`QuadPairs::new`] over one run of triangles (indices relative to the run).
fn pair_run(triangles: &[[u32; 3]]) -> (Vec<[u32; 4]>, Vec<u32>, Vec<u8>) {
    let cap = triangles.len() / 2 + 1;
    let (mut indices, mut first, mut layout) =
        (Vec::with_capacity(cap), Vec::with_capacity(cap), Vec::with_capacity(cap));
    let mut t = 0;
    while t < triangles.len() {
        let a = triangles[t];
        match triangles.get(t + 1).and_then(|&b| pair(a, b)) {
            Some((quad, bits)) => {
                indices.push(quad);
                layout.push(bits);
                first.push(t as u32);
                t += 2;
            }
            None => {
                indices.push([a[0], a[1], a[2], a[2]]);
                layout.push(0);
                first.push(t as u32);
                t += 1;
            }
        }
    }
    (indices, first, layout)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The point at barycentrics (u, v) of triangle `t` in its own order.
    fn point(p: &[[f64; 2]], t: [u32; 3], u: f64, v: f64) -> [f64; 2] {
        let w = [1.0 - u - v, u, v];
        let mut out = [0.0; 2];
        for (k, &i) in t.iter().enumerate() {
            for (o, c) in out.iter_mut().zip(p[i as usize]) {
                *o += w[k] * c;
            }
        }
        out
    }

    /// The point at Embree's quad coordinates (u, v), from its definition: the first half
    /// (v0, v1, v3) below the diagonal, the second (v2, v3, v1) at (1 − u, 1 − v) above it.
    fn quad_point(p: &[[f64; 2]], q: [u32; 4], u: f64, v: f64) -> [f64; 2] {
        if u + v <= 1.0 {
            point(p, [q[0], q[1], q[3]], u, v)
        } else {
            point(p, [q[2], q[3], q[1]], 1.0 - u, 1.0 - v)
        }
    }

    #[test]
    fn every_rotation_of_two_triangles_maps_quad_hits_to_the_same_points() {
        // A convex quadrilateral split along 0–2, both halves counter-clockwise.
        let p = [[0.0, 0.0], [1.0, 0.1], [1.2, 1.0], [-0.1, 0.9]];
        let rot = |t: [u32; 3], r: usize| [t[r], t[(r + 1) % 3], t[(r + 2) % 3]];
        for ra in 0..3 {
            for rb in 0..3 {
                let tris = [rot([0, 1, 2], ra), rot([0, 2, 3], rb)];
                let q = QuadPairs::new(&tris);
                assert_eq!(q.len(), 1, "{tris:?}");
                for (u, v) in [(0.2, 0.3), (0.7, 0.6), (0.05, 0.9), (0.9, 0.05), (0.5, 0.5), (0.99, 0.98)] {
                    let (t, bu, bv) = q.triangle_hit(0, u as f32, v as f32);
                    let want = quad_point(&p, q.indices[0], u, v);
                    let got = point(&p, tris[t as usize], bu as f64, bv as f64);
                    assert!(bu >= -1e-6 && bv >= -1e-6 && bu + bv <= 1.0 + 1e-6, "{tris:?} {u} {v}");
                    for c in 0..2 {
                        assert!((got[c] - want[c]).abs() < 1e-6, "{tris:?} at ({u}, {v}): {got:?} vs {want:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn triangles_that_make_no_quad_stay_alone_with_their_own_coordinates() {
        // Same edge walked in the same direction (flipped winding), no shared edge, a lone last.
        let tris = [[0, 1, 2], [1, 2, 3], [4, 5, 6], [7, 8, 9], [10, 11, 12]];
        let q = QuadPairs::new(&tris);
        assert_eq!(q.len(), 5);
        for (k, t) in tris.iter().enumerate() {
            assert_eq!(q.indices[k], [t[0], t[1], t[2], t[2]]);
            assert_eq!(q.triangle_hit(k as u32, 0.25, 0.5), (k as u32, 0.25, 0.5));
        }
    }

    #[test]
    fn a_grid_pairs_every_cell_also_across_parallel_runs() {
        // A heightfield's cells, two triangles each, more than one pairing run long.
        let side = 400u32;
        let id = |i: u32, j: u32| j * (side + 1) + i;
        let mut tris = Vec::new();
        for j in 0..side {
            for i in 0..side {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        assert!(tris.len() > 2 * CHUNK);
        let q = QuadPairs::new(&tris);
        assert_eq!(q.len(), tris.len() / 2);
        assert!(q.first.iter().enumerate().all(|(k, &f)| f == 2 * k as u32));
    }
}

//! Loop subdivision surfaces (Loop 1987) as pbrt-v4's `loopsubdiv` shape builds them (pbrt-v3
//! §3.8): the control mesh refined `levels` times, its vertices pushed to the limit surface,
//! with normals from the limit tangents.
//!
//! Refinement rules (Loop 1987 with Warren's β):
//! - interior vertex of valence n: (1 − nβ)·v + β·Σ ring, β = 3/16 for n = 3, else 3/(8n);
//! - boundary vertex: ¾·v + ⅛·(both boundary neighbours) (the cubic B-spline rule);
//! - interior edge: ⅜·(ends) + ⅛·(the two opposite vertices); boundary edge: its midpoint.
//!
//! Limit positions: interior (1 − nχ)·v + χ·Σ ring with χ = 1/(3/(8β) + n); boundary
//! ⅔·v + ⅙·(boundary neighbours), the uniform cubic B-spline's point (pbrt-v4 uses ⅗ and ⅕
//! there, which is not the limit of its own boundary rule). Limit tangents: the cos/sin masks
//! of the ring for interior vertices, and for boundary vertices the boundary direction with
//! the cross-boundary masks of Hoppe et al. (1994), "Piecewise smooth surface reconstruction".
//! Applied to the control points they give the exact limit normal ([`Level::limit_normal`]);
//! the mesh handed to rendering applies them to the limit points of the ring instead, as
//! pbrt-v4 does ([`Level::limit_mesh`]), so its shading matches pbrt-v4's.

mod topology;

#[cfg(test)]
mod tests;

use glam::Vec3;

pub use topology::{Edge, Topology, TopologyError, NONE};

use crate::geometry::Mesh;

/// Most triangles a subdivision may produce (about 2.5 GB of mesh and connectivity).
pub const MAX_TRIANGLES: usize = 1 << 25;

/// Why a control mesh cannot be subdivided.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SubdivisionError {
    /// The control mesh is not a consistently wound 2-manifold.
    #[error(transparent)]
    Topology(#[from] TopologyError),
    /// A triangle index is not below the vertex count.
    #[error("index {index} is out of range: the mesh has {vertices} vertices")]
    IndexOutOfRange {
        /// The index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// The refined mesh would be too large.
    #[error("{levels} levels of subdivision turn each of the {triangles} triangles into 4^{levels}, more than {MAX_TRIANGLES} in all")]
    TooLarge {
        /// Requested levels.
        levels: u32,
        /// Control triangles.
        triangles: usize,
    },
}

/// Warren's weight β of the ring of an interior vertex of valence `n` (Loop's rule simplified:
/// 3/16 for n = 3, 3/(8n) otherwise, so 1/16 at the regular valence 6).
pub fn beta(n: usize) -> f32 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f32)
    }
}

/// Weight χ of each ring vertex in the limit position of an interior vertex of valence `n`:
/// 1/(3/(8β) + n) (1/12 at valence 6, where the limit mask is ½ centre, 1/12 ring).
pub fn limit_weight(n: usize) -> f32 {
    1.0 / (3.0 / (8.0 * beta(n)) + n as f32)
}

/// A triangle mesh at one level of refinement, with its connectivity.
#[derive(Clone, Debug)]
pub struct Level {
    /// Control points of this level [scene units].
    pub positions: Vec<Vec3>,
    /// Triangles, wound as the control mesh.
    pub triangles: Vec<[u32; 3]>,
    /// Edges and one-rings of `triangles`.
    pub topology: Topology,
}

impl Level {
    /// The control mesh, checked: every index in range and the triangles a consistently wound
    /// 2-manifold.
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Self, SubdivisionError> {
        if let Some(&index) = triangles.iter().flatten().find(|&&i| i as usize >= positions.len()) {
            return Err(SubdivisionError::IndexOutOfRange { index, vertices: positions.len() });
        }
        let topology = Topology::new(positions.len(), &triangles)?;
        Ok(Self { positions, triangles, topology })
    }

    /// One step of Loop refinement: each triangle becomes four. Vertex `v` of this level keeps
    /// index `v`; the vertex inserted on edge `e` gets index `vertex count + e`.
    pub fn refine(&self) -> Self {
        let t = &self.topology;
        let p = &self.positions;
        let mut positions = Vec::with_capacity(p.len() + t.edges.len());
        positions.extend((0..p.len()).map(|v| self.even_point(v)));
        positions.extend(t.edges.iter().map(|e| {
            let [a, b] = e.ends.map(|i| p[i as usize]);
            if e.is_boundary() {
                0.5 * (a + b)
            } else {
                let [c, d] = e.opposite.map(|i| p[i as usize]);
                0.375 * (a + b) + 0.125 * (c + d)
            }
        }));
        let base = p.len() as u32;
        let mut triangles = Vec::with_capacity(self.triangles.len() * 4);
        for (&[a, b, c], fe) in self.triangles.iter().zip(&t.face_edges) {
            let [ab, bc, ca] = fe.map(|e| base + e);
            triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        let topology =
            Topology::new(positions.len(), &triangles).expect("Loop refinement of a 2-manifold is a 2-manifold");
        Self { positions, triangles, topology }
    }

    /// The refined position of vertex `v` (even-vertex rules).
    fn even_point(&self, v: usize) -> Vec3 {
        let ring = self.topology.ring(v);
        let p = self.positions[v];
        if ring.is_empty() {
            p
        } else if self.topology.is_boundary(v) {
            0.75 * p + 0.125 * (self.pos(ring[0]) + self.pos(ring[ring.len() - 1]))
        } else {
            let b = beta(ring.len());
            (1.0 - ring.len() as f32 * b) * p + b * self.ring_sum(ring)
        }
    }

    /// The point of the limit surface that vertex `v` converges to.
    pub fn limit_point(&self, v: usize) -> Vec3 {
        let ring = self.topology.ring(v);
        let p = self.positions[v];
        if ring.is_empty() {
            p
        } else if self.topology.is_boundary(v) {
            (2.0 / 3.0) * p + (1.0 / 6.0) * (self.pos(ring[0]) + self.pos(ring[ring.len() - 1]))
        } else {
            let chi = limit_weight(ring.len());
            (1.0 - ring.len() as f32 * chi) * p + chi * self.ring_sum(ring)
        }
    }

    /// The limit surface's unit normal at the limit point of vertex `v`, on the side the
    /// triangles' counter-clockwise winding faces (zero where the tangents are degenerate).
    pub fn limit_normal(&self, v: usize) -> Vec3 {
        let (s, t) = self.limit_tangents(v);
        s.cross(t).normalize_or_zero()
    }

    /// Two limit tangents (s, t) at vertex `v` with s × t on the winding's side. Interior:
    /// s = Σ cos(2πj/n)·r_j, t = Σ sin(2πj/n)·r_j. Boundary with ring r_0 … r_m (r_0 and r_m on
    /// the boundary): s = r_0 − r_m along the boundary; t across it by Hoppe et al.'s masks.
    pub fn limit_tangents(&self, v: usize) -> (Vec3, Vec3) {
        self.tangent_masks(&self.positions, v)
    }

    /// The tangent masks of [`Level::limit_tangents`] applied to `points` (one per vertex).
    fn tangent_masks(&self, points: &[Vec3], v: usize) -> (Vec3, Vec3) {
        let ring = self.topology.ring(v);
        let r = |j: usize| points[ring[j] as usize];
        let n = ring.len();
        if n == 0 {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        if !self.topology.is_boundary(v) {
            let (mut s, mut t) = (Vec3::ZERO, Vec3::ZERO);
            for j in 0..n {
                let phi = std::f32::consts::TAU * j as f32 / n as f32;
                s += phi.cos() * r(j);
                t += phi.sin() * r(j);
            }
            return (s, t);
        }
        let p = points[v];
        let s = r(0) - r(n - 1);
        let t = match n {
            2 => r(0) + r(1) - 2.0 * p,
            3 => r(1) - p,
            4 => -r(0) + 2.0 * r(1) + 2.0 * r(2) - r(3) - 2.0 * p,
            _ => {
                let theta = std::f32::consts::PI / (n - 1) as f32;
                let mut t = theta.sin() * (r(0) + r(n - 1));
                for k in 1..n - 1 {
                    t += (2.0 * theta.cos() - 2.0) * (k as f32 * theta).sin() * r(k);
                }
                -t
            }
        };
        (s, t)
    }

    fn pos(&self, i: u32) -> Vec3 {
        self.positions[i as usize]
    }

    fn ring_sum(&self, ring: &[u32]) -> Vec3 {
        ring.iter().map(|&i| self.pos(i)).sum()
    }

    /// The limit surface sampled at this level's vertices: limit positions, this level's
    /// triangles, and as shading normals the tangent masks applied to the limit points of each
    /// ring, as pbrt-v4 does. (The exact [`Level::limit_normal`] applies them to the control
    /// points; the two differ by 2.3° on average on pbrt-v4's killeroo at level 1, and by
    /// about a quarter of that per further level.)
    pub fn limit_mesh(&self) -> Mesh {
        let n = self.positions.len();
        let positions: Vec<Vec3> = (0..n).map(|v| self.limit_point(v)).collect();
        let normals = (0..n)
            .map(|v| {
                let (s, t) = self.tangent_masks(&positions, v);
                s.cross(t).normalize_or_zero()
            })
            .collect();
        Mesh { positions, indices: self.triangles.clone(), normals: Some(normals), uvs: None, faces: None }
    }
}

/// The Loop subdivision surface of a control mesh, refined `levels` times and pushed to the
/// limit (`levels` = 0: the control triangles with limit positions and normals, as pbrt-v4).
/// Vertices no triangle uses keep their position and get a zero normal.
pub fn subdivide(positions: &[Vec3], triangles: &[[u32; 3]], levels: u32) -> Result<Mesh, SubdivisionError> {
    let count = 4usize.checked_pow(levels).and_then(|f| f.checked_mul(triangles.len()));
    if !triangles.is_empty() && count.is_none_or(|n| n > MAX_TRIANGLES) {
        return Err(SubdivisionError::TooLarge { levels, triangles: triangles.len() });
    }
    let mut level = Level::new(positions.to_vec(), triangles.to_vec())?;
    for _ in 0..if triangles.is_empty() { 0 } else { levels } {
        level = level.refine();
    }
    Ok(level.limit_mesh())
}

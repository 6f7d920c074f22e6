//! Triangle meshes (indexed, structure of arrays) and axis-aligned bounds.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::math::offset::gamma;

/// Meshes of at least this many triangles are checked and bounded on every thread.
const PARALLEL_TRIANGLES: usize = 1 << 16;

/// The fewest elements (vertices, normals, triangles) one thread takes on in a mesh's
/// element-wise parallel passes: a small mesh is done on the calling thread alone.
pub(crate) const MIN_ELEMENTS_PER_THREAD: usize = 1 << 14;

/// An indexed triangle mesh in world space.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions [scene units].
    pub positions: Vec<Vec3>,
    /// Triangles as indices into `positions`.
    pub indices: Vec<[u32; 3]>,
    /// Optional per-vertex shading normals (unit).
    pub normals: Option<Vec<Vec3>>,
    /// Optional per-vertex texture coordinates.
    pub uvs: Option<Vec<Vec2>>,
    /// The face each triangle was cut from, when a face is more than one triangle (a bilinear
    /// patch or a polygon of a mesh file): triangles with the same id make one face. `None`:
    /// every triangle is a face of its own.
    pub faces: Option<Vec<u32>>,
}

impl Mesh {
    /// A mesh from positions and triangles.
    pub fn new(positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> Self {
        Self { positions, indices, normals: None, uvs: None, faces: None }
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// True when the mesh has no triangles.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// Bytes its arrays hold (positions, indices, normals, texture coordinates, faces).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.positions[..])
            + size_of_val(&self.indices[..])
            + self.normals.as_deref().map_or(0, size_of_val)
            + self.uvs.as_deref().map_or(0, size_of_val)
            + self.faces.as_deref().map_or(0, size_of_val)
    }

    /// The three vertices of triangle `i`.
    #[inline]
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[i];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }

    /// Area of triangle `i` [scene units²].
    pub fn triangle_area(&self, i: usize) -> f32 {
        let [a, b, c] = self.triangle(i);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Total surface area.
    pub fn area(&self) -> f32 {
        (0..self.len()).map(|i| self.triangle_area(i)).sum()
    }

    /// For each triangle, the area of the face it belongs to [scene units²]: its own area, or
    /// the summed area of the triangles that share its face id.
    pub fn face_areas(&self) -> Vec<f32> {
        let own = (0..self.len()).map(|i| self.triangle_area(i));
        let Some(faces) = &self.faces else { return own.collect() };
        let mut sums = vec![0.0f32; faces.iter().max().map_or(0, |&f| f as usize + 1)];
        for (&f, a) in faces.iter().zip(own) {
            sums[f as usize] += a;
        }
        faces.iter().map(|&f| sums[f as usize]).collect()
    }

    /// Drops triangles with out-of-range indices, vertices that are not finite or lie beyond
    /// [`Bounds3::MAX_COORDINATE`], or an edge cross product whose squared length is 0 or
    /// overflows (the geometric normal could not be found from it); returns how many were
    /// dropped. Vertices are kept, so per-vertex data stays aligned; face ids go with their
    /// triangles.
    pub fn remove_degenerate(&mut self) -> usize {
        let before = self.indices.len();
        let pos = &self.positions;
        let sound = |t: &[u32; 3]| {
            if t.iter().any(|&i| i as usize >= pos.len()) {
                return false;
            }
            let [a, b, c] = t.map(|i| pos[i as usize]);
            let within = |p: Vec3| Bounds3 { min: p, max: p }.fits_bvh();
            let area2 = (b - a).cross(c - a).length_squared();
            within(a) && within(b) && within(c) && area2 > 0.0 && area2.is_finite()
        };
        let all_sound = if before >= PARALLEL_TRIANGLES {
            self.indices.par_iter().all(sound)
        } else {
            self.indices.iter().all(sound)
        };
        if all_sound {
            return 0;
        }
        if let Some(faces) = self.faces.as_mut() {
            let mut triangles = self.indices.iter();
            faces.retain(|_| triangles.next().is_some_and(sound));
        }
        self.indices.retain(sound);
        before - self.indices.len()
    }

    /// Bounds of all vertices of triangles (indices out of range are ignored).
    pub fn bounds(&self) -> Bounds3 {
        let add = |b: Bounds3, t: &[u32; 3]| {
            t.iter().filter_map(|&i| self.positions.get(i as usize)).fold(b, |b, &p| b.union_point(p))
        };
        if self.indices.len() >= PARALLEL_TRIANGLES {
            self.indices.par_iter().fold(|| Bounds3::EMPTY, add).reduce(|| Bounds3::EMPTY, Bounds3::union)
        } else {
            self.indices.iter().fold(Bounds3::EMPTY, add)
        }
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds3 {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Bounds3 {
    /// The empty box (union identity).
    pub const EMPTY: Self = Self { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// The largest coordinate of a box a BVH takes ([`Self::fits_bvh`]): its surface area stays
    /// within f32 (at most about 2.4·10³⁷) for the build's cost function.
    pub const MAX_COORDINATE: f32 = 1e18;

    /// True when every coordinate is finite and within ±[`Self::MAX_COORDINATE`].
    pub fn fits_bvh(&self) -> bool {
        let within = |p: Vec3| p.is_finite() && p.abs().max_element() <= Self::MAX_COORDINATE;
        within(self.min) && within(self.max)
    }

    /// Grows the box to contain `p`.
    pub fn union_point(self, p: Vec3) -> Self {
        Self { min: self.min.min(p), max: self.max.max(p) }
    }

    /// Smallest box containing both.
    pub fn union(self, o: Self) -> Self {
        Self { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// Centre.
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the diagonal length (radius of the bounding sphere around the centre).
    pub fn radius(&self) -> f32 {
        0.5 * (self.max - self.min).length()
    }

    /// True when nothing was added.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// The box grown on every side by `relative` times its largest coordinate (and at least the
    /// smallest normal f32), so that slab tests that round cannot miss what it bounds.
    pub fn padded(self, relative: f32) -> Self {
        let pad = self.min.abs().max(self.max.abs()).max_element() * relative + f32::MIN_POSITIVE;
        Self { min: self.min - pad, max: self.max + pad }
    }

    /// False only when the ray o + t d with t in [0, `t_max`] certainly misses the box: the
    /// slab test with the far distance of each slab grown by 2γ₃ against its rounding (PBR 4th
    /// ed. §6.8.2, after Williams et al. 2005). A zero component of d is taken as ±1/f32::MAX
    /// (its sign), so that no 0·∞ arises: a ray parallel to a slab is ruled out from outside it
    /// and not from inside, but one lying in the plane of a face may be ruled out either way
    /// (the callers' boxes are padded beyond what they bound).
    #[inline]
    pub fn may_hit(&self, o: Vec3, d: Vec3, t_max: f32) -> bool {
        self.may_hit_inv(o, slab_inverse(d), t_max)
    }

    /// [`Bounds3::may_hit`] with `inv_d` = [`slab_inverse`]`(d)`, for one ray tested against
    /// several boxes.
    #[inline]
    pub fn may_hit_inv(&self, o: Vec3, inv_d: Vec3, t_max: f32) -> bool {
        let near = (self.min - o) * inv_d;
        let far = (self.max - o) * inv_d;
        let t0 = near.min(far).max_element().max(0.0);
        let t1 = (near.max(far).min_element() * (1.0 + 2.0 * gamma(3))).min(t_max);
        t0 <= t1
    }
}

/// 1/d per axis with a zero component's ±∞ taken as ±f32::MAX, as [`Bounds3::may_hit`] uses it.
#[inline]
pub fn slab_inverse(d: Vec3) -> Vec3 {
    d.recip().clamp(Vec3::splat(-f32::MAX), Vec3::splat(f32::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_big_mesh_is_checked_and_bounded_on_all_threads_as_one_by_one() {
        // A strip of 2¹⁷ triangles zigzagging in y and z (no three consecutive vertices in a
        // line), every 1000th of zero area (two equal vertices) and every 777th naming a vertex
        // past the end.
        let n = 1 << 17;
        let positions: Vec<Vec3> = (0..n + 2).map(|i| Vec3::new(i as f32, (i % 2) as f32, (i % 3) as f32)).collect();
        let indices: Vec<[u32; 3]> = (0..n as u32)
            .map(|i| match i {
                i if i % 1000 == 0 => [i, i, i + 1],
                i if i % 777 == 0 => [i, i + 1, u32::MAX],
                i => [i, i + 1, i + 2],
            })
            .collect();
        assert!(indices.len() >= PARALLEL_TRIANGLES);
        let bad = indices.iter().filter(|t| t[0] == t[1] || t[2] == u32::MAX).count();
        let mut mesh = Mesh::new(positions.clone(), indices.clone());
        // Bounds of the referenced vertices, one by one (indices past the end are ignored).
        let mut want = Bounds3::EMPTY;
        for &i in indices.iter().flatten().filter(|&&i| (i as usize) < positions.len()) {
            want = want.union_point(positions[i as usize]);
        }
        assert_eq!(mesh.bounds(), want);
        assert_eq!(mesh.remove_degenerate(), bad);
        assert_eq!(mesh.indices.len(), indices.len() - bad);
        assert_eq!(mesh.remove_degenerate(), 0);
    }

    /// The slab test never rules out a ray that meets the box, and rules out one that misses
    /// it by more than rounding: checked against the same test in double precision on random
    /// boxes and rays (some with zero direction components), and on rays parallel to two slabs.
    #[test]
    fn a_ray_that_meets_a_box_may_hit_it_and_one_that_misses_does_not() {
        use crate::sampling::rng::Rng;
        let mut rng = Rng::new(3, 9);
        let v = |rng: &mut Rng| Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0 - 2.0;
        let (mut hits, mut misses) = (0, 0);
        for k in 0..20_000 {
            let (a, c) = (v(&mut rng), v(&mut rng));
            let b = Bounds3 { min: a.min(c), max: a.max(c) };
            // From anywhere towards a point near the box (about half the rays meet it).
            let o = v(&mut rng) * 2.0;
            let target = b.center() + (b.max - b.min) * 0.8 * (v(&mut rng) * 0.5);
            let mut d = (target - o) * (0.5 + rng.uniform());
            if k % 4 == 0 {
                d[k / 4 % 3] = 0.0;
            }
            let t_max = if k % 3 == 0 { f32::INFINITY } else { 3.0 * rng.uniform() };
            // In double precision: [t0, t1] is the overlap of [0, t_max] with the ray's interval
            // in every slab (empty when t1 < t0).
            let (od, dd) = (o.as_dvec3(), d.as_dvec3());
            let (mut t0, mut t1) = (0.0f64, t_max as f64);
            for axis in 0..3 {
                let (lo, hi) = (b.min.as_dvec3()[axis], b.max.as_dvec3()[axis]);
                if dd[axis] == 0.0 {
                    if od[axis] < lo || od[axis] > hi {
                        t1 = -1.0;
                    }
                    continue;
                }
                let (n, f) = ((lo - od[axis]) / dd[axis], (hi - od[axis]) / dd[axis]);
                t0 = t0.max(n.min(f));
                t1 = t1.min(n.max(f));
            }
            let got = b.may_hit(o, d, t_max);
            let scale = o.abs().max(b.min.abs()).max(b.max.abs()).max_element() as f64;
            let margin = 1e-5 * (1.0 + scale / dd.length());
            if t1 - t0 > margin {
                assert!(got, "ray {o} + t {d}, t ≤ {t_max}, meets {b:?} over [{t0}, {t1}]");
                hits += 1;
            } else if t1 - t0 < -margin {
                assert!(!got, "ray {o} + t {d}, t ≤ {t_max}, misses {b:?}");
                misses += 1;
            }
        }
        assert!(hits > 2000 && misses > 2000, "{hits} hits, {misses} misses");
        // Parallel to two slabs: inside both it may hit, outside either it does not.
        let b = Bounds3 { min: Vec3::ZERO, max: Vec3::ONE };
        let along = |o: Vec3| b.may_hit(o, Vec3::X, f32::INFINITY);
        assert!(along(Vec3::new(-1.0, 0.5, 0.5)) && along(Vec3::new(-1.0, 1e-3, 1.0 - 1e-3)));
        assert!(!along(Vec3::new(-1.0, -1e-3, 0.5)) && !along(Vec3::new(-1.0, 0.5, 1.0 + 1e-3)));
        assert!(!along(Vec3::new(2.0, 0.5, 0.5)));
    }

    /// Dropping a degenerate triangle drops its face id with it, and a face's area is the sum
    /// over the triangles left in it.
    #[test]
    fn face_ids_follow_their_triangles_when_degenerate_ones_are_dropped() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 0.0, 0.0)];
        let mut m = Mesh::new(p, vec![[0, 1, 2], [0, 1, 4], [1, 3, 2], [1, 4, 3]]);
        m.faces = Some(vec![0, 0, 0, 3]);
        assert_eq!(m.remove_degenerate(), 1);
        assert_eq!(m.indices, vec![[0, 1, 2], [1, 3, 2], [1, 4, 3]]);
        assert_eq!(m.faces, Some(vec![0, 0, 3]));
        assert_eq!(m.face_areas(), vec![1.0, 1.0, 0.5]);
        m.faces = None;
        assert_eq!(m.face_areas(), vec![0.5, 0.5, 0.5]);
    }
}

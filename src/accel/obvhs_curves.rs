//! Curves in the obvhs backend: a CWBVH of their own over curve pieces (each segment split into
//! 2^splitdepth u ranges, as pbrt-v4 splits them into shapes), traversed by the same loop as the
//! triangles' and tested with pbrt-v4's recursive ray–curve intersector
//! ([`crate::geometry::curve_hit`]). [`crate::accel::WithExtra`] puts it beside any triangle
//! accelerator, so a scene without curves never meets it.

use super::box_tree::BoxTree;
use crate::geometry::curve_hit::intersect_curve;
use crate::geometry::{Bounds3, CurveSegment, Curves, Hit, Ray};

/// One BVH primitive: a u range of a segment.
#[derive(Clone, Copy, Debug)]
struct Piece {
    /// Index into `CurveBvh::segments`.
    segment: u32,
    u: [f32; 2],
}

/// A segment with the [geom_id, prim_id] its hits report.
#[derive(Clone, Copy, Debug)]
struct Segment {
    curve: CurveSegment,
    ids: [u32; 2],
}

/// A BVH over the pieces of every curve of a scene.
pub struct CurveBvh {
    tree: BoxTree,
    /// In BVH leaf order.
    pieces: Vec<Piece>,
    segments: Vec<Segment>,
    bounds: Bounds3,
}

impl CurveBvh {
    /// Builds over `curves`: (geom_id, its curves). Segments with a non-finite control point or
    /// width are skipped.
    pub fn new(curves: &[(u32, &Curves)]) -> Self {
        let mut segments = Vec::new();
        let mut pieces = Vec::new();
        let mut boxes = Vec::new();
        let mut bounds = Bounds3::EMPTY;
        for &(geom, c) in curves {
            let finite = |s: &CurveSegment| s.cp.iter().all(|p| p.is_finite()) && s.width.iter().all(|w| w.is_finite());
            let mut index = vec![u32::MAX; c.segments.len()];
            for (prim, s) in c.segments.iter().enumerate().filter(|(_, s)| finite(s)) {
                index[prim] = segments.len() as u32;
                segments.push(Segment { curve: *s, ids: [geom, prim as u32] });
            }
            for (prim, u) in c.pieces() {
                let segment = index[prim as usize];
                if segment == u32::MAX {
                    continue;
                }
                let b = c.segments[prim as usize].bounds(u[0], u[1]);
                bounds = bounds.union(b);
                boxes.push(b);
                pieces.push(Piece { segment, u });
            }
        }
        let (tree, order) = BoxTree::new(&boxes);
        let pieces = order.iter().map(|&k| pieces[k as usize]).collect();
        Self { tree, pieces, segments, bounds }
    }

    /// Bounds of all curves.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Bytes of nodes, pieces and segments.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of_val;
        self.tree.memory_bytes() + size_of_val(&self.pieces[..]) + size_of_val(&self.segments[..])
    }

    #[inline]
    fn visit(&self, ray: &Ray, visit: impl FnMut(usize, &mut f32) -> bool) {
        self.tree.visit(ray, visit)
    }

    /// The hit of `ray` on piece `k` with t ≤ `t_max` (with `any`, the first the search finds).
    #[inline]
    fn test(&self, k: usize, ray: &Ray, t_max: f32, any: bool) -> Option<Hit> {
        let p = self.pieces[k];
        let s = &self.segments[p.segment as usize];
        let h = intersect_curve(&s.curve, p.u[0], p.u[1], ray, t_max, any)?;
        Some(Hit {
            t: h.t,
            geom_id: s.ids[0],
            prim_id: s.ids[1],
            u: h.u,
            v: 0.0,
            ng: glam::Vec3::ZERO,
            inst_id: Hit::NO_INSTANCE,
        })
    }

    /// Closest hit with t in (0, t_max].
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.visit(ray, |k, t_max| {
            if let Some(h) = self.test(k, ray, *t_max, false) {
                if best.is_none_or(|b| h.t < b.t) {
                    *t_max = h.t;
                    best = Some(h);
                }
            }
            false
        });
        best
    }

    /// Any hit with t in (0, t_max).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut hit = false;
        self.visit(ray, |k, t_max| {
            hit = self.test(k, ray, *t_max, true).is_some_and(|h| h.t < ray.t_max);
            hit
        });
        hit
    }

    /// Appends every piece's hit with t in (0, t_max).
    pub fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        self.visit(ray, |k, t_max| {
            hits.extend(self.test(k, ray, *t_max, false).filter(|h| h.t < ray.t_max));
            false
        });
    }
}

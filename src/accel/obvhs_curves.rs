//! Curves in the obvhs backend: a CWBVH of their own over curve pieces (each segment split into
//! 2^splitdepth u ranges, as pbrt-v4 splits them into shapes), traversed by the same loop as the
//! triangles' and tested with pbrt-v4's recursive ray–curve intersector
//! ([`crate::geometry::curve_hit`]). [`WithCurves`] puts it beside any triangle accelerator, so a
//! scene without curves never meets it.

use std::time::Duration;

use ::obvhs::{aabb::Aabb, cwbvh::builder::build_cwbvh, cwbvh::node::CwBvhNode};
use glam::Vec3A;

use super::traverse::{self, BoxRay};
use super::BuildQuality;
use crate::accel::Accel;
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
    nodes: Vec<CwBvhNode>,
    /// In BVH leaf order.
    pieces: Vec<Piece>,
    segments: Vec<Segment>,
    bounds: Bounds3,
    /// The tree is deeper than the traversal stack: test every piece.
    linear: bool,
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
                boxes.push(Aabb::new(Vec3A::from(b.min), Vec3A::from(b.max)));
                pieces.push(Piece { segment, u });
            }
        }
        if pieces.is_empty() {
            return Self { nodes: Vec::new(), pieces, segments, bounds, linear: false };
        }
        let bvh = build_cwbvh(&boxes, BuildQuality::default().params(), &mut Duration::default());
        let pieces = bvh.primitive_indices.iter().map(|&k| pieces[k as usize]).collect();
        let linear = super::max_depth(&bvh.nodes) as usize + 1 >= traverse::STACK_SIZE;
        Self { nodes: bvh.nodes, pieces, segments, bounds, linear }
    }

    /// Bounds of all curves.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Bytes of nodes, pieces and segments.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.nodes[..]) + size_of_val(&self.pieces[..]) + size_of_val(&self.segments[..])
    }

    /// Calls `visit(piece index, &mut t_max)` for every piece whose box the ray reaches.
    #[inline]
    fn visit(&self, ray: &Ray, mut visit: impl FnMut(usize, &mut f32) -> bool) {
        if self.pieces.is_empty() || ray.t_max.is_nan() || ray.t_max <= 0.0 || !ray.d.is_finite() || !ray.o.is_finite()
        {
            return;
        }
        if self.linear {
            let mut t_max = ray.t_max;
            for k in 0..self.pieces.len() {
                if visit(k, &mut t_max) {
                    return;
                }
            }
            return;
        }
        traverse::traverse(&self.nodes, &BoxRay::new(ray.o, ray.d), ray.t_max, |_| {}, |k, t| visit(k as usize, t));
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

/// A triangle accelerator and the scene's curves: closest hit of the two, occlusion by either.
pub struct WithCurves {
    triangles: Box<dyn Accel>,
    curves: CurveBvh,
}

impl WithCurves {
    /// `triangles` with `curves` beside it.
    pub fn new(triangles: Box<dyn Accel>, curves: CurveBvh) -> Self {
        Self { triangles, curves }
    }
}

impl Accel for WithCurves {
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let tri = self.triangles.intersect(ray);
        let limited = Ray { t_max: tri.map_or(ray.t_max, |h| h.t), ..*ray };
        match self.curves.intersect(&limited) {
            Some(c) if tri.is_none_or(|t| c.t < t.t) => Some(c),
            _ => tri,
        }
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.triangles.occluded(ray) || self.curves.occluded(ray)
    }

    fn bounds(&self) -> Bounds3 {
        self.triangles.bounds().union(self.curves.bounds())
    }

    fn memory_bytes(&self) -> usize {
        self.triangles.memory_bytes() + self.curves.memory_bytes()
    }

    fn name(&self) -> &'static str {
        self.triangles.name()
    }

    fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        self.triangles.intersect_all(ray, hits);
        self.curves.intersect_all(ray, hits);
    }
}

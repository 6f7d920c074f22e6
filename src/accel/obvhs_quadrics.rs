//! Quadrics in the obvhs backend: a CWBVH over their world boxes, each tested exactly in its
//! object space ([`PlacedQuadric::intersect`]). Hits report the quadric's primitive as
//! `geom_id` and only t: the surface is recomputed from the ray and t
//! (`scene::quadric_interaction`), as on Embree. Moving quadrics are boxed over their motion and
//! intersected where they are at the ray's time.

use super::box_tree::BoxTree;
use crate::geometry::{Bounds3, Hit, PlacedQuadric, Ray};
use crate::math::offset::next_float_up;

/// A BVH over the quadrics of a scene.
pub struct QuadricBvh {
    tree: BoxTree,
    /// (geom_id, quadric) in BVH leaf order.
    quadrics: Vec<(u32, PlacedQuadric)>,
    bounds: Bounds3,
}

impl QuadricBvh {
    /// Builds over `quadrics`: (geom_id, its quadric).
    pub fn new(quadrics: &[(u32, &PlacedQuadric)]) -> Self {
        let boxes: Vec<Bounds3> = quadrics.iter().map(|(_, q)| q.bounds()).collect();
        let bounds = boxes.iter().fold(Bounds3::EMPTY, |a, &b| a.union(b));
        let (tree, order) = BoxTree::new(&boxes);
        let quadrics = order.iter().map(|&k| (quadrics[k as usize].0, quadrics[k as usize].1.clone())).collect();
        Self { tree, quadrics, bounds }
    }

    /// Bounds of all quadrics.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Bytes of nodes and quadrics.
    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes() + std::mem::size_of_val(&self.quadrics[..])
    }

    /// False when `ray` certainly misses the box around all the quadrics: a few quadrics are
    /// usually a small part of the scene, and one slab test spares most rays the traversal.
    #[inline]
    fn may_hit(&self, ray: &Ray) -> bool {
        self.bounds.may_hit(ray.o, ray.d, ray.t_max)
    }

    /// The hit of `ray` on leaf `k` with t < `t_max`.
    #[inline]
    fn test(&self, k: usize, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (geom_id, q) = &self.quadrics[k];
        let t = q.intersect(ray, t_max)?;
        Some(Hit { t, geom_id: *geom_id, prim_id: 0, u: 0.0, v: 0.0, ng: glam::Vec3::ZERO, inst_id: Hit::NO_INSTANCE })
    }

    /// Closest hit with t in (0, t_max]; equally distant hits resolve to the smaller geom_id.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if !self.may_hit(ray) {
            return None;
        }
        let mut best: Option<Hit> = None;
        self.tree.visit(ray, |k, t_max| {
            // Quadric::intersect excludes its limit; the Accel contract includes t_max.
            let limit = next_float_up(best.map_or(ray.t_max, |b| b.t));
            if let Some(h) = self.test(k, ray, limit) {
                if best.is_none_or(|b| h.t < b.t || h.geom_id < b.geom_id) {
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
        if !self.may_hit(ray) {
            return false;
        }
        let mut hit = false;
        self.tree.visit(ray, |k, _| {
            hit = self.test(k, ray, ray.t_max).is_some();
            hit
        });
        hit
    }

    /// Appends every hit with t in (0, t_max) — both of a sphere's or cylinder's, each found
    /// from just beyond the one before, as [`crate::accel::Accel::intersect_all`] steps.
    pub fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        self.tree.visit(ray, |k, _| {
            let mut base = 0.0f32;
            for _ in 0..2 {
                let rest = Ray { o: ray.at(base), t_max: ray.t_max - base, ..*ray };
                let Some(mut h) = self.test(k, &rest, rest.t_max) else { break };
                h.t += base;
                if h.t >= ray.t_max {
                    break;
                }
                hits.push(h);
                base = h.t + (h.t.abs() + ray.o.abs().max_element() / ray.d.length().max(f32::MIN_POSITIVE)) * 2e-6;
            }
            false
        });
    }
}

//! A CWBVH over boxes of primitives that are not triangles (curve pieces, quadrics), traversed
//! by the triangles' loop ([`super::traverse`]); the primitive test is the caller's. Trees
//! deeper than the traversal stack fall back to visiting every primitive.

use std::time::Duration;

use ::obvhs::{aabb::Aabb, cwbvh::builder::build_cwbvh, cwbvh::node::CwBvhNode};
use glam::Vec3A;

use super::traverse::{self, BoxRay};
use super::BuildQuality;
use crate::geometry::{slab_inverse, Bounds3, Ray};

/// The nodes over `len` primitives, in the leaf order [`BoxTree::new`] returns.
pub struct BoxTree {
    nodes: Vec<CwBvhNode>,
    len: usize,
    /// The tree is deeper than the traversal stack: visit every primitive.
    linear: bool,
    /// For a few primitives (at most [`FEW`]), their boxes in leaf order: one slab test each
    /// costs less than a traversal of the tree.
    few: Vec<Bounds3>,
}

/// Up to this many primitives, [`BoxTree::visit`] tests their boxes one by one.
const FEW: usize = 4;

/// Relative growth of those boxes (2⁻¹⁸ of their largest coordinate).
const FEW_PAD: f32 = 1.0 / (1u32 << 18) as f32;

impl BoxTree {
    /// Builds over `boxes`; returns the tree and, for each leaf slot, the index of its box. A
    /// box the tree cannot hold ([`Bounds3::fits_bvh`]: a shape scaled or sized to ±∞, NaN or
    /// beyond ±10¹⁸) gets no slot: nothing hits it.
    pub fn new(boxes: &[Bounds3]) -> (Self, Vec<u32>) {
        let finite: Vec<u32> = (0..boxes.len() as u32).filter(|&k| boxes[k as usize].fits_bvh()).collect();
        if finite.is_empty() {
            return (Self { nodes: Vec::new(), len: 0, linear: false, few: Vec::new() }, Vec::new());
        }
        let aabbs: Vec<Aabb> = finite
            .iter()
            .map(|&k| Aabb::new(Vec3A::from(boxes[k as usize].min), Vec3A::from(boxes[k as usize].max)))
            .collect();
        let bvh = build_cwbvh(&aabbs, BuildQuality::default().params(), &mut Duration::default());
        let order: Vec<u32> = bvh.primitive_indices.iter().map(|&i| finite[i as usize]).collect();
        if order.len() <= FEW {
            // Grown as the quantised boxes of the tree are rounded outwards: `Bounds3::may_hit`
            // may rule out a ray lying in the plane of a face. (The tree is built for its leaf
            // order only.)
            let few = order.iter().map(|&k| boxes[k as usize].padded(FEW_PAD)).collect();
            return (Self { nodes: Vec::new(), len: order.len(), linear: false, few }, order);
        }
        let linear = super::max_depth(&bvh.nodes) as usize + 1 >= traverse::STACK_SIZE;
        (Self { nodes: bvh.nodes, len: order.len(), linear, few: Vec::new() }, order)
    }

    /// Bytes of nodes.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(&self.nodes[..])
    }

    /// Calls `visit(leaf slot, &mut t_max)` for every primitive whose box the ray reaches,
    /// until it returns true.
    #[inline]
    pub fn visit(&self, ray: &Ray, mut visit: impl FnMut(usize, &mut f32) -> bool) {
        if self.len == 0 || ray.t_max.is_nan() || ray.t_max <= 0.0 || !ray.d.is_finite() || !ray.o.is_finite() {
            return;
        }
        if !self.few.is_empty() {
            let (mut t_max, inv_d) = (ray.t_max, slab_inverse(ray.d));
            for (k, b) in self.few.iter().enumerate() {
                if b.may_hit_inv(ray.o, inv_d, t_max) && visit(k, &mut t_max) {
                    return;
                }
            }
            return;
        }
        if self.linear {
            let mut t_max = ray.t_max;
            for k in 0..self.len {
                if visit(k, &mut t_max) {
                    return;
                }
            }
            return;
        }
        traverse::traverse(&self.nodes, &BoxRay::new(ray.o, ray.d), ray.t_max, |_| {}, |k, t| visit(k as usize, t));
    }
}

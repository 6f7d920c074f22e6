//! Pure-Rust backend: an obvhs compressed wide BVH8 (Ylitie, Karras, Laine 2017, "Efficient
//! Incoherent Ray Traversal on GPUs Using Compressed Wide BVHs") built with PLOC, traversed by our
//! own loop ([`traverse`]) with our own watertight triangle test ([`super::watertight`]).
//!
//! Three details make the traversal agree with a brute-force loop over the same triangle test:
//! - Leaf boxes are the triangle boxes grown by a relative 2⁻²⁰ margin, so a ray through a
//!   triangle's edge or vertex (which lies on its box's face) is never culled by slab rounding.
//! - The traversal stack holds [`traverse::STACK_SIZE`] entries; a tree deeper than that falls
//!   back to a linear scan (reported in [`BuildStats::linear_fallback`]).
//! - Triangles whose centroids share a cell of a 2²⁰-per-axis grid become one BVH primitive
//!   (see `group_by_centroid_cell`): PLOC builds chains from equal Morton codes.
//!
//! Speed: triangles are stored lane-wise ([`TriangleLanes`]) in BVH leaf order, the triangle
//! test is specialised per dominant ray axis, and when every group holds one triangle (the usual
//! case) a BVH primitive index is a triangle index with no indirection. Nodes and triangles
//! live in huge-page-advised memory ([`HugeArray`]): over a million triangles, incoherent rays
//! would otherwise pay a TLB miss on most loads. The queries are compiled for AVX2+FMA as well
//! as for baseline x86-64, and the CPU's best variant is chosen at run time (`obvhs_isa.rs`).

use std::time::Duration;

use ::obvhs::{aabb::Aabb, cwbvh::builder::build_cwbvh, cwbvh::node::CwBvhNode, BvhBuildParams};
use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::huge_array::HugeArray;
use super::watertight::{LaneRay, TriangleHit, TriangleLanes};
use super::Accel;
use crate::geometry::{Bounds3, Hit, Mesh, Ray};

#[path = "obvhs_box_tree.rs"]
mod box_tree;
#[path = "obvhs_curves.rs"]
pub mod curves;
#[path = "obvhs_isa.rs"]
mod isa;
#[path = "obvhs_leaves.rs"]
mod leaves;
#[path = "obvhs_quadrics.rs"]
pub mod quadrics;
#[path = "obvhs_traverse.rs"]
mod traverse;

use leaves::{ExactLen, Leaves, Triangle};

/// Relative margin by which leaf boxes are grown (a power of two).
const BOX_PAD: f32 = 1.0 / (1u32 << 20) as f32;

/// BVH build effort: faster builds trace slower. Maps to obvhs' `BvhBuildParams` presets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    /// PLOC with the smallest search radius, no reinsertion, one triangle per leaf.
    Fastest,
    /// Small search radius, light reinsertion.
    Fast,
    /// obvhs' balanced preset (about Embree's build time).
    #[default]
    Medium,
    /// Wide search radius and more reinsertion (no triangle splitting).
    Slow,
}

impl BuildQuality {
    fn params(self) -> BvhBuildParams {
        match self {
            Self::Fastest => BvhBuildParams::fastest_build(),
            Self::Fast => BvhBuildParams::fast_build(),
            Self::Medium => BvhBuildParams::medium_build(),
            Self::Slow => BvhBuildParams::slow_build(),
        }
    }
}

/// What the build did with its input.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildStats {
    /// Triangles in the BVH.
    pub triangles: usize,
    /// Skipped: zero area, or a NaN/infinite vertex.
    pub skipped_degenerate: usize,
    /// Skipped: a vertex index out of range.
    pub skipped_bad_index: usize,
    /// Depth of the BVH8 (root = 0).
    pub max_depth: u32,
    /// True when the tree is too deep for the traversal stack and rays use a linear scan.
    pub linear_fallback: bool,
}

/// The obvhs CWBVH accelerator over a list of meshes (`geom_id` = index in that list).
pub struct ObvhsAccel {
    /// obvhs' CWBVH nodes (the rest of its `CwBvh` is not needed after the build).
    nodes: HugeArray<CwBvhNode>,
    /// Triangles in BVH leaf order (the CWBVH's `primitive_indices` order), so a leaf's
    /// triangles are contiguous in memory.
    triangles: HugeArray<Triangle>,
    /// BVH primitive `k` is `triangles[group_start[k]..group_start[k + 1]]`; empty when every
    /// group is a single triangle (then primitive `k` is triangle `k`).
    group_start: HugeArray<u32>,
    bounds: Bounds3,
    stats: BuildStats,
}

impl ObvhsAccel {
    /// Builds with [`BuildQuality::Medium`].
    pub fn new(meshes: &[Mesh]) -> Self {
        Self::with_quality(meshes, BuildQuality::default())
    }

    /// Builds with the given quality. Degenerate triangles and bad indices are skipped and
    /// counted in [`ObvhsAccel::stats`].
    pub fn with_quality(meshes: &[Mesh], quality: BuildQuality) -> Self {
        let mut stats = BuildStats::default();
        let mut tris = Vec::new();
        let mut ids = Vec::new();
        let mut bounds = Bounds3::EMPTY;
        for (g, mesh) in meshes.iter().enumerate() {
            for (p, idx) in mesh.indices.iter().enumerate() {
                let Some(tri) =
                    idx.map(|i| mesh.positions.get(i as usize).copied()).into_iter().collect::<Option<Vec<_>>>()
                else {
                    stats.skipped_bad_index += 1;
                    continue;
                };
                let tri = [tri[0], tri[1], tri[2]];
                let finite = tri.iter().all(|v| v.is_finite());
                if !finite || (tri[1] - tri[0]).cross(tri[2] - tri[0]) == Vec3::ZERO {
                    stats.skipped_degenerate += 1;
                    continue;
                }
                bounds = tri.iter().fold(bounds, |b, &v| b.union_point(v));
                tris.push(tri);
                ids.push([g as u32, p as u32]);
            }
        }
        stats.triangles = tris.len();
        if tris.is_empty() {
            let (nodes, triangles, group_start) = Default::default();
            return Self { nodes, triangles, group_start, bounds, stats };
        }
        let (members, starts) = group_by_centroid_cell(&tris, bounds);
        let groups: Vec<&[u32]> = starts.windows(2).map(|w| &members[w[0] as usize..w[1] as usize]).collect();
        let boxes: Vec<Aabb> = groups
            .par_iter()
            .map(|g| g.iter().fold(Aabb::empty(), |b, &i| b.union(&padded_box(&tris[i as usize]))))
            .collect();
        let bvh = build_cwbvh(&boxes, quality.params(), &mut Duration::default());
        let leaf_order = bvh.primitive_indices.iter().flat_map(|&g| groups[g as usize]);
        let triangles = HugeArray::from_exact_iter(ExactLen(
            tris.len(),
            leaf_order.map(|&i| Triangle {
                lanes: TriangleLanes::new(tris[i as usize]),
                ids: ids[i as usize],
                _pad: [0; 2],
            }),
        ));
        let mut group_start = Vec::new();
        if groups.len() < tris.len() {
            group_start.reserve(groups.len() + 1);
            group_start.push(0);
            for &g in &bvh.primitive_indices {
                group_start.push(group_start[group_start.len() - 1] + groups[g as usize].len() as u32);
            }
        }
        stats.max_depth = max_depth(&bvh.nodes);
        stats.linear_fallback = stats.max_depth as usize + 1 >= traverse::STACK_SIZE;
        let nodes = HugeArray::new(&bvh.nodes);
        Self { nodes, triangles, group_start: HugeArray::new(&group_start), bounds, stats }
    }

    /// The same accelerator with its arrays in ordinary heap memory (no huge pages): the
    /// baseline that benchmarks compare against.
    pub fn without_huge_pages(self) -> Self {
        Self {
            nodes: self.nodes.to_heap(),
            triangles: self.triangles.to_heap(),
            group_start: self.group_start.to_heap(),
            ..self
        }
    }

    /// Bytes of nodes and triangles the kernel currently backs with transparent huge pages
    /// (from `/proc/self/smaps`; Linux only).
    pub fn huge_page_bytes(&self) -> std::io::Result<usize> {
        Ok(self.nodes.huge_page_bytes()? + self.triangles.huge_page_bytes()? + self.group_start.huge_page_bytes()?)
    }

    /// Build statistics (skipped triangles, depth).
    pub fn stats(&self) -> BuildStats {
        self.stats
    }

    /// The arrays a ray reads, dereferenced once per ray.
    #[inline(always)]
    fn leaves(&self) -> Leaves<'_> {
        Leaves { triangles: &self.triangles, group_start: &self.group_start }
    }

    /// The ray set up for the triangle test; None when it can hit nothing (no triangles, an
    /// empty or NaN range, or a non-finite or zero ray).
    #[inline(always)]
    fn lane_ray(&self, ray: &Ray) -> Option<LaneRay> {
        if self.triangles.is_empty() || ray.t_max.is_nan() || ray.t_max <= 0.0 {
            return None;
        }
        LaneRay::new(ray.o, ray.d)
    }

    /// [`Accel::intersect`] compiled for the caller's target features (the trait method calls it
    /// through [`isa::closest_hit`], which picks the CPU's best variant).
    #[inline(always)]
    fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let r = self.lane_ray(ray)?;
        let best = match r.kz() {
            0 => self.closest::<0>(ray, &r),
            1 => self.closest::<1>(ray, &r),
            _ => self.closest::<2>(ray, &r),
        };
        best.map(|b| self.leaves().hit_record(b))
    }

    /// [`Accel::occluded`] compiled for the caller's target features (see [`isa::any_hit`]).
    #[inline(always)]
    fn any_hit(&self, ray: &Ray) -> bool {
        let Some(r) = self.lane_ray(ray) else { return false };
        match r.kz() {
            0 => self.any::<0>(ray, &r),
            1 => self.any::<1>(ray, &r),
            _ => self.any::<2>(ray, &r),
        }
    }

    /// [`Accel::intersect_all`] compiled for the caller's target features (see [`isa::every_hit`]).
    #[inline(always)]
    fn every_hit(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        let Some(r) = self.lane_ray(ray) else { return };
        match r.kz() {
            0 => self.all::<0>(ray, &r, hits),
            1 => self.all::<1>(ray, &r, hits),
            _ => self.all::<2>(ray, &r, hits),
        }
    }

    /// Closest hit with the triangle test specialised for dominant axis `KZ`.
    #[inline(always)]
    fn closest<const KZ: usize>(&self, ray: &Ray, r: &LaneRay) -> Option<(TriangleHit, usize)> {
        let mut best = None;
        let l = self.leaves();
        if self.stats.linear_fallback {
            for i in 0..l.triangles.len() {
                l.closer::<KZ>(r, i, &mut best, ray.t_max);
            }
            return best;
        }
        let br = traverse::BoxRay::new(ray.o, ray.d);
        traverse::traverse(
            &self.nodes,
            &br,
            ray.t_max,
            #[inline(always)]
            |k| l.touch(k),
            #[inline(always)]
            |k, t_max| {
                let mut found = false;
                for i in l.group(k as usize) {
                    found |= l.closer::<KZ>(r, i, &mut best, ray.t_max);
                }
                if let (true, Some((h, _))) = (found, best) {
                    *t_max = h.t;
                }
                false
            },
        );
        best
    }

    /// Every hit with t in (0, t_max), in traversal order; the ray's range never shrinks.
    #[inline(always)]
    fn all<const KZ: usize>(&self, ray: &Ray, r: &LaneRay, hits: &mut Vec<Hit>) {
        let l = self.leaves();
        if self.stats.linear_fallback {
            for i in 0..l.triangles.len() {
                hits.extend(l.blocks::<KZ>(r, i, ray.t_max).map(|h| l.hit_record((h, i))));
            }
            return;
        }
        let br = traverse::BoxRay::new(ray.o, ray.d);
        traverse::traverse(
            &self.nodes,
            &br,
            ray.t_max,
            #[inline(always)]
            |k| l.touch(k),
            #[inline(always)]
            |k, _| {
                for i in l.group(k as usize) {
                    hits.extend(l.blocks::<KZ>(r, i, ray.t_max).map(|h| l.hit_record((h, i))));
                }
                false
            },
        );
    }

    /// Any hit with t in (0, t_max), the triangle test specialised for dominant axis `KZ`.
    #[inline(always)]
    fn any<const KZ: usize>(&self, ray: &Ray, r: &LaneRay) -> bool {
        let l = self.leaves();
        if self.stats.linear_fallback {
            return (0..l.triangles.len()).any(|i| l.blocks::<KZ>(r, i, ray.t_max).is_some());
        }
        let mut hit = false;
        let br = traverse::BoxRay::new(ray.o, ray.d);
        traverse::traverse(
            &self.nodes,
            &br,
            ray.t_max,
            #[inline(always)]
            |k| l.touch(k),
            #[inline(always)]
            |k, _| {
                for i in l.group(k as usize) {
                    if l.blocks::<KZ>(r, i, ray.t_max).is_some() {
                        hit = true;
                        break;
                    }
                }
                hit
            },
        );
        hit
    }
}

/// Triangle box grown by 2⁻²⁰ of its largest coordinate magnitude (plus the smallest normal f32),
/// far more than slab-test rounding and far less than any visible size.
fn padded_box(t: &[Vec3; 3]) -> Aabb {
    let b = Bounds3 { min: t[0].min(t[1]).min(t[2]), max: t[0].max(t[1]).max(t[2]) }.padded(BOX_PAD);
    Aabb::new(Vec3A::from(b.min), Vec3A::from(b.max))
}

/// Triangles grouped by centroid cell on a 2²⁰-per-axis grid over the scene bounds (about the
/// resolution of obvhs' 64-bit Morton codes). PLOC turns a run of equal Morton codes into a chain
/// (coincident copies of a triangle made a tree deep enough to overflow the thread stack), so
/// each cell becomes one BVH primitive whose triangles are tested in a loop. In ordinary meshes
/// nearly every cell holds one triangle. Returns triangle indices sorted by cell, and where each
/// cell's run starts (plus a final end).
fn group_by_centroid_cell(tris: &[[Vec3; 3]], bounds: Bounds3) -> (Vec<u32>, Vec<u32>) {
    let extent = (bounds.max - bounds.min).max(Vec3::splat(f32::MIN_POSITIVE));
    let cells = ((1u32 << 20) - 1) as f32;
    let key = |t: &[Vec3; 3]| {
        let c = ((t[0] + t[1] + t[2]) / 3.0 - bounds.min) / extent * cells;
        let q = c.clamp(Vec3::ZERO, Vec3::splat(cells)).as_uvec3();
        ((q.x as u64) << 40) | ((q.y as u64) << 20) | q.z as u64
    };
    let mut order: Vec<(u64, u32)> = tris.par_iter().enumerate().map(|(i, t)| (key(t), i as u32)).collect();
    // Keys with indices are unique, so the order (and the BVH) is deterministic.
    order.par_sort_unstable();
    let mut starts: Vec<u32> =
        (0..order.len()).filter(|&k| k == 0 || order[k - 1].0 != order[k].0).map(|k| k as u32).collect();
    starts.push(order.len() as u32);
    (order.into_iter().map(|(_, i)| i).collect(), starts)
}

/// Depth of the deepest internal node (root = 0).
pub(super) fn max_depth(nodes: &[CwBvhNode]) -> u32 {
    let mut deepest = 0;
    let mut stack = vec![(0usize, 0u32)];
    while let Some((n, depth)) = stack.pop() {
        deepest = deepest.max(depth);
        let node = &nodes[n];
        for ch in 0..8 {
            if !node.is_child_empty(ch) && !node.is_leaf(ch) {
                stack.push((node.child_node_index(ch) as usize, depth + 1));
            }
        }
    }
    deepest
}

impl Accel for ObvhsAccel {
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        isa::closest_hit(self, ray)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        isa::any_hit(self, ray)
    }

    fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    fn memory_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.nodes[..]) + size_of_val(&self.triangles[..]) + size_of_val(&self.group_start[..])
    }

    fn name(&self) -> &'static str {
        "obvhs"
    }

    /// One traversal that records every hit and never shrinks the ray's t range.
    fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        isa::every_hit(self, ray, hits)
    }
}

#[cfg(test)]
#[path = "obvhs_tests.rs"]
mod tests;

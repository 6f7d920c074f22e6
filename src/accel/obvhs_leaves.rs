//! The obvhs backend's leaves: triangle records in BVH leaf order, one cache line each, and
//! the per-ray view of them that the traversal's callbacks use.

use super::super::watertight::{LaneRay, TriangleHit, TriangleLanes};
use crate::geometry::Hit;

/// A triangle and its [geom_id, prim_id], one cache line each so a triangle test touches one line.
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
pub(super) struct Triangle {
    pub(super) lanes: TriangleLanes,
    pub(super) ids: [u32; 2],
    /// Explicit padding to 64 bytes (plain data has no implicit padding).
    pub(super) _pad: [u32; 2],
}

/// The triangles and primitive groups as plain slices (a [`HugeArray`] checks its alignment on
/// every dereference, so the traversal dereferences once per ray).
#[derive(Clone, Copy)]
pub(super) struct Leaves<'a> {
    pub(super) triangles: &'a [Triangle],
    pub(super) group_start: &'a [u32],
}

impl Leaves<'_> {
    /// Closest-hit candidate for slot `i`: hit if nearer than `best`, or equally near with smaller
    /// [geom_id, prim_id], so the result does not depend on traversal order.
    #[inline(always)]
    pub(super) fn closer<const KZ: usize>(
        &self,
        r: &LaneRay,
        i: usize,
        best: &mut Option<(TriangleHit, usize)>,
        t_max: f32,
    ) -> bool {
        let limit = best.map_or(t_max, |(h, _)| h.t);
        let tri = &self.triangles[i];
        match r.intersect::<KZ>(&tri.lanes, limit) {
            Some(h) if best.is_none_or(|(b, j)| h.t < b.t || tri.ids < self.triangles[j].ids) => {
                *best = Some((h, i));
                true
            }
            _ => false,
        }
    }

    /// The hit on triangle `i` with t in (0, t_max) (open at t_max: shadow rays, every-hit).
    #[inline(always)]
    pub(super) fn blocks<const KZ: usize>(&self, r: &LaneRay, i: usize, t_max: f32) -> Option<TriangleHit> {
        r.intersect::<KZ>(&self.triangles[i].lanes, t_max).filter(|h| h.t < t_max)
    }

    /// Indices into `triangles` of BVH primitive `k`.
    #[inline(always)]
    pub(super) fn group(&self, k: usize) -> std::ops::Range<usize> {
        if self.group_start.is_empty() {
            k..k + 1
        } else {
            self.group_start[k] as usize..self.group_start[k + 1] as usize
        }
    }

    /// Loads (and discards) the first triangle of BVH primitive `k` to start its cache miss early.
    #[inline(always)]
    pub(super) fn touch(&self, k: u32) {
        if let Some(t) = self.triangles.get(self.group(k as usize).start) {
            std::hint::black_box(*t);
        }
    }

    pub(super) fn hit_record(&self, (h, i): (TriangleHit, usize)) -> Hit {
        let [p0, p1, p2] = self.triangles[i].lanes.vertices();
        let [geom_id, prim_id] = self.triangles[i].ids;
        Hit { t: h.t, geom_id, prim_id, u: h.u, v: h.v, ng: (p1 - p0).cross(p2 - p0), inst_id: Hit::NO_INSTANCE }
    }
}

/// An iterator whose length is known from elsewhere (`flat_map` cannot know it).
pub(super) struct ExactLen<I>(pub(super) usize, pub(super) I);

impl<I: Iterator> Iterator for ExactLen<I> {
    type Item = I::Item;

    fn next(&mut self) -> Option<I::Item> {
        let item = self.1.next()?;
        self.0 = self.0.saturating_sub(1);
        Some(item)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.0, Some(self.0))
    }
}

impl<I: Iterator> ExactSizeIterator for ExactLen<I> {}

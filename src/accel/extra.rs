//! Geometry that is not triangles beside any triangle accelerator: curves ([`CurveBvh`]) and
//! quadrics ([`QuadricBvh`]) in BVHs of their own. The obvhs backend keeps them here, and so do
//! Embree's instanced scenes (and moving quadrics on Embree); a scene without them never meets
//! this wrapper.

use super::obvhs::curves::CurveBvh;
use super::obvhs::quadrics::QuadricBvh;
use super::Accel;
use crate::geometry::{Bounds3, Hit, Ray};

/// A triangle accelerator with curves and quadrics beside it: the closest hit of all, occlusion
/// by any.
pub struct WithExtra {
    triangles: Box<dyn Accel>,
    curves: Option<CurveBvh>,
    quadrics: Option<QuadricBvh>,
}

impl WithExtra {
    /// `triangles` with `curves` and `quadrics` beside it.
    pub fn new(triangles: Box<dyn Accel>, curves: Option<CurveBvh>, quadrics: Option<QuadricBvh>) -> Self {
        Self { triangles, curves, quadrics }
    }
}

/// The closer of two hits (the first on a tie).
#[inline]
fn closer(a: Option<Hit>, b: Option<Hit>) -> Option<Hit> {
    match (a, b) {
        (Some(x), Some(y)) if y.t < x.t => Some(y),
        (None, y) => y,
        (x, _) => x,
    }
}

impl Accel for WithExtra {
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let mut best = self.triangles.intersect(ray);
        let limited = |best: Option<Hit>| Ray { t_max: best.map_or(ray.t_max, |h| h.t), ..*ray };
        if let Some(c) = &self.curves {
            best = closer(best, c.intersect(&limited(best)));
        }
        if let Some(q) = &self.quadrics {
            best = closer(best, q.intersect(&limited(best)));
        }
        best
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.triangles.occluded(ray)
            || self.curves.as_ref().is_some_and(|c| c.occluded(ray))
            || self.quadrics.as_ref().is_some_and(|q| q.occluded(ray))
    }

    fn bounds(&self) -> Bounds3 {
        let b = self.triangles.bounds();
        let b = self.curves.as_ref().map_or(b, |c| b.union(c.bounds()));
        self.quadrics.as_ref().map_or(b, |q| b.union(q.bounds()))
    }

    fn memory_bytes(&self) -> usize {
        self.triangles.memory_bytes()
            + self.curves.as_ref().map_or(0, CurveBvh::memory_bytes)
            + self.quadrics.as_ref().map_or(0, QuadricBvh::memory_bytes)
    }

    fn name(&self) -> &'static str {
        self.triangles.name()
    }

    fn intersect_all(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        self.triangles.intersect_all(ray, hits);
        if let Some(c) = &self.curves {
            c.intersect_all(ray, hits);
        }
        if let Some(q) = &self.quadrics {
            q.intersect_all(ray, hits);
        }
    }
}

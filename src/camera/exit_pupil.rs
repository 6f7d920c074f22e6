//! Bounds of a lens system's exit pupil seen from the film (pbrt-v4 §5.3.5): for film points
//! on rings of radius [r₀, r₁) along +x, the box on the rear interface's plane that holds every
//! point a ray from the film can pass the whole system through. Rays are then sampled uniformly
//! over the box rotated to the film point's angle, so few are wasted on the blocked rest of the
//! rear element.

use super::lens_system::{LensRay, LensSystem};
use crate::sampling::radical_inverse;
use glam::{DVec2, DVec3, Vec2};
use rayon::prelude::*;

/// Film rings the pupil is bounded for (pbrt-v4's count).
pub const RINGS: usize = 64;

/// Points tried per ring: film positions across the ring paired with Halton points over the
/// rear element's enlarged square.
const TRIALS: u32 = 1 << 16;

/// An axis-aligned box on the rear interface's plane [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PupilBox {
    /// Lower corner.
    pub min: DVec2,
    /// Upper corner.
    pub max: DVec2,
}

impl PupilBox {
    /// Area [m²].
    pub fn area(&self) -> f64 {
        let e = (self.max - self.min).max(DVec2::ZERO);
        e.x * e.y
    }

    /// Whether `p` lies inside (edges included).
    pub fn contains(&self, p: DVec2) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// The exit-pupil boxes of a lens system for film points out to `half_diagonal` from the axis.
#[derive(Clone, Debug, PartialEq)]
pub struct ExitPupil {
    /// Box per ring, innermost first.
    pub boxes: Vec<PupilBox>,
    /// Radius of the film's outermost point [m].
    pub half_diagonal: f64,
    /// Distance of the rear interface's plane from the film [m].
    rear_z: f64,
}

impl ExitPupil {
    /// The boxes of `lens` for a film of diagonal `2 · half_diagonal` [m].
    pub fn new(lens: &LensSystem, half_diagonal: f64) -> Self {
        let boxes = (0..RINGS)
            .into_par_iter()
            .map(|i| {
                let r = |k: usize| k as f64 / RINGS as f64 * half_diagonal;
                Self::bound(lens, r(i), r(i + 1))
            })
            .collect();
        Self { boxes, half_diagonal, rear_z: lens.rear_z() }
    }

    /// The box of the rear-plane points that rays from film points (x, 0), x ∈ [x0, x1], pass
    /// through the system by; the whole enlarged rear element when none passes.
    pub fn bound(lens: &LensSystem, x0: f64, x1: f64) -> PupilBox {
        let rear = 1.5 * lens.rear_radius();
        let square = PupilBox { min: DVec2::splat(-rear), max: DVec2::splat(rear) };
        let mut found: Option<PupilBox> = None;
        for i in 0..TRIALS {
            let film = DVec3::new(x0 + (x1 - x0) * (f64::from(i) + 0.5) / f64::from(TRIALS), 0.0, 0.0);
            let u = DVec2::new(radical_inverse(2, i), radical_inverse(3, i));
            let p = square.min + u * (square.max - square.min);
            let inside = found.is_some_and(|b| b.contains(p));
            let passes = || lens.trace_from_film(LensRay { o: film, d: p.extend(lens.rear_z()) - film }).is_some();
            if inside || passes() {
                found = Some(
                    found.map_or(PupilBox { min: p, max: p }, |b| PupilBox { min: b.min.min(p), max: b.max.max(p) }),
                );
            }
        }
        // Grow by two sample spacings so rays just outside the samples that hit are kept.
        let grow = 2.0 * (square.max - square.min).length() / f64::from(TRIALS).sqrt();
        found.map_or(square, |b| PupilBox { min: b.min - grow, max: b.max + grow })
    }

    /// A point on the rear plane [camera space, m] for film point `p_film` [m] from `u` ∈ [0,1)²,
    /// uniform over its ring's box turned to `p_film`'s angle, and the box's area [m²] (the
    /// reciprocal of the density).
    pub fn sample(&self, p_film: DVec2, u: Vec2) -> (DVec3, f64) {
        let r = p_film.length();
        let ring = ((r / self.half_diagonal * RINGS as f64) as usize).min(RINGS - 1);
        let b = self.boxes[ring];
        let p = b.min + u.as_dvec2() * (b.max - b.min);
        let (sin, cos) = if r > 0.0 { (p_film.y / r, p_film.x / r) } else { (0.0, 1.0) };
        (DVec3::new(cos * p.x - sin * p.y, sin * p.x + cos * p.y, self.rear_z), b.area())
    }
}

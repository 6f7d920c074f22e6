//! Light bounds for many-light sampling (Conty Estevez & Kulla 2018, "Importance Sampling of Many
//! Lights with Adaptive Tree Splitting"; PBR 4th ed. §12.6.3): a box around the emitters, a cone
//! bounding their normals (half-angle θ_o about `w`), the angle θ_e beyond the normal over which
//! they still emit (π/2 for diffuse surfaces), their total flux Φ and whether they emit from both
//! sides. The importance of bounds at a point p (with normal n) bounds the contribution
//! Φ cos θ' / d² of any light inside, θ' the smallest angle between a normal in the cone and the
//! direction to p, shrunk by the angle the box subtends from p. Each light works out its own
//! bounds (`Light::bounds`, in the light's file); this file holds what they have in common.

use super::cone::{AngledCone, DirectionCone};
use crate::geometry::Bounds3;
use glam::Vec3;

/// Spatial and directional bounds of a set of emitters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Box around the emitters [scene units].
    pub bounds: Bounds3,
    /// Axis of the cone of emitting normals (unit).
    pub w: Vec3,
    /// Total flux Φ (the light sampler's unit).
    pub phi: f32,
    /// cos θ_o: the normals lie within θ_o of `w`.
    pub cos_theta_o: f32,
    /// cos θ_e: each emitter sends light up to θ_e beyond its normal.
    pub cos_theta_e: f32,
    /// Some emitter emits from both sides (its normal's negation counts too).
    pub two_sided: bool,
}

/// [`LightBounds`] as the importance reads them: the box as its bounding sphere (centre and
/// squared radius) and sin θ_o beside cos θ_o, so that a point's importance computes only what
/// depends on the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedBounds {
    /// Centre of the box [scene units].
    centre: Vec3,
    /// Squared radius of the box's bounding sphere (half its diagonal) [scene units²].
    radius2: f32,
    /// Its radius [scene units].
    radius: f32,
    /// The emitters share one normal (θ_o = 0) and emit over its hemisphere (θ_e = π/2), and the
    /// box is more than a point: [`PreparedBounds::reaches`] is then a plane test.
    flat: bool,
    /// A point emitting over the whole sphere (θ_o = π, r = 0: point, goniometric and
    /// projection lights): θ' = θ_b = 0, and the importance is Φ |cos θ_i| / d².
    point_isotropic: bool,
    /// Axis of the cone of emitting normals (unit).
    w: Vec3,
    /// Total flux Φ.
    phi: f32,
    cos_theta_o: f32,
    sin_theta_o: f32,
    cos_theta_e: f32,
    two_sided: bool,
}

/// The angles of [`PreparedBounds::importance`] at a point: the unit direction from the box's
/// centre to it and the squared distance, sin and cos θ_b, cos θ'.
struct Angles {
    wi: Vec3,
    dist2: f32,
    sin_b: f32,
    cos_b: f32,
    cos_p: f32,
}

impl PreparedBounds {
    /// Importance of the bounds at `p` with unit normal `n` (zero for a point in a medium):
    /// Φ cos θ' / d², times cos θ'_i at a surface, where θ' = max(0, θ_w − θ_o − θ_b) is the
    /// smallest angle between an emitting normal and the direction from the lights to `p`
    /// (θ_w that angle for the axis, θ_b the half-angle the box's bounding sphere subtends from
    /// `p`: sin²θ_b = r²/d², all directions from inside it), and θ'_i = max(0, θ_i − θ_b) the
    /// smallest angle between `n` and a direction to the box. It is 0 when θ' ≥ θ_e: no light
    /// inside can reach `p`. d² is the squared distance to the box's centre, clamped from below
    /// by r, half the box's diagonal — a length, not r²: pbrt-v4's `LightBounds::Importance`
    /// clamps by `Length(bounds.Diagonal()) / 2`, and this follows it so that lights are chosen
    /// with pbrt-v4's probabilities (the clamp then depends on the scene's unit: it acts out to
    /// d = √r, inside the bounding sphere for r > 1 and beyond it for r < 1).
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        if self.point_isotropic {
            // What `angles` and `incidence_factor` give with cos θ_o = −1 and sin θ_b = 0
            // (cos θ' = 1 up to rounding, cos θ'_i = cos θ_i) without their trigonometry; the
            // light's own position (d = 0) takes the general path.
            let d = p - self.centre;
            let dist2 = d.length_squared();
            if dist2 > 0.0 {
                let importance = self.phi / dist2;
                let cos_i = if n != Vec3::ZERO { (d * dist2.sqrt().recip()).dot(n).abs().min(1.0) } else { 1.0 };
                return (importance * cos_i).max(0.0).clamp(0.0, f32::MAX);
            }
        }
        let Some(a) = self.angles(p) else { return 0.0 };
        let mut importance = self.phi * a.cos_p / a.dist2.max(self.radius);
        if n != Vec3::ZERO {
            importance *= incidence_factor(&a, n);
        }
        // (Finite even at a point light's own position, where d² = 0.)
        importance.max(0.0).clamp(0.0, f32::MAX)
    }

    /// Whether [`PreparedBounds::importance`] is positive at `p`, `n` (up to rounding at the
    /// boundary and f32 underflow), without its value: θ' < θ_e, cos θ' > 0, and at a surface
    /// cos θ'_i > 0.
    ///
    /// For flat bounds (θ_o = 0, θ_e = π/2, r > 0) this is a plane test. θ'_i < π/2 always,
    /// θ_i being at most π/2 and θ_b positive; two-sided, θ_w ≤ π/2 and so θ' < π/2; one-sided,
    /// θ' = max(0, θ_w − θ_b) < π/2 ⟺ cos θ_w > cos(θ_b + π/2) = −sin θ_b ⟺
    /// w · (p − c) > −r (with sin θ_b = r/|p − c|; from inside the sphere both hold): `p` is in
    /// front of the plane normal to `w` that touches the bounding sphere behind its centre.
    #[inline]
    pub fn reaches(&self, p: Vec3, n: Vec3) -> bool {
        if self.flat {
            return self.two_sided || self.w.dot(p - self.centre) > -self.radius;
        }
        self.reaches_by_angles(p, n)
    }

    fn reaches_by_angles(&self, p: Vec3, n: Vec3) -> bool {
        let Some(a) = self.angles(p) else { return false };
        a.cos_p > 0.0 && (n == Vec3::ZERO || incidence_factor(&a, n) > 0.0)
    }

    /// The angles at `p`; `None` when θ' ≥ θ_e.
    #[inline(always)]
    fn angles(&self, p: Vec3) -> Option<Angles> {
        let d = p - self.centre;
        let dist2 = d.length_squared();
        let wi = if dist2 > 0.0 { d * dist2.sqrt().recip() } else { Vec3::ZERO };
        let mut cos_w = self.w.dot(wi);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = sin_from_cos(cos_w);
        let (sin_b, cos_b) = if dist2 < self.radius2 {
            (0.0, -1.0)
        } else {
            // (At the centre of a point box, 0/0: θ_b is taken as π/2.)
            let sin2_b = self.radius2 / dist2;
            (sin2_b.min(1.0).sqrt(), (1.0 - sin2_b).max(0.0).sqrt())
        };
        let cos_x = cos_sub_clamped(sin_w, cos_w, self.sin_theta_o, self.cos_theta_o);
        let sin_x = sin_sub_clamped(sin_w, cos_w, self.sin_theta_o, self.cos_theta_o);
        let cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
        (cos_p > self.cos_theta_e).then_some(Angles { wi, dist2, sin_b, cos_b, cos_p })
    }
}

/// cos θ'_i = cos(max(0, θ_i − θ_b)) for the unit normal `n`.
#[inline(always)]
fn incidence_factor(a: &Angles, n: Vec3) -> f32 {
    let cos_i = a.wi.dot(n).abs();
    cos_sub_clamped(sin_from_cos(cos_i), cos_i, a.sin_b, a.cos_b)
}

/// cos(max(0, a − b)) from the sines and cosines of angles a, b in [0, π].
#[inline]
fn cos_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        1.0
    } else {
        cos_a * cos_b + sin_a * sin_b
    }
}

/// sin(max(0, a − b)) from the sines and cosines of angles a, b in [0, π].
#[inline]
fn sin_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        0.0
    } else {
        sin_a * cos_b - cos_a * sin_b
    }
}

#[inline]
fn sin_from_cos(c: f32) -> f32 {
    (1.0 - c * c).max(0.0).sqrt()
}

impl LightBounds {
    /// The union: the box around both, the cone around both normal cones, the larger emission
    /// angle, the summed flux. Bounds without flux add nothing.
    pub fn union(a: &Self, b: &Self) -> Self {
        AngledBounds::new(*a).union(&AngledBounds::new(*b)).bounds
    }

    /// Centre of the box.
    pub fn centroid(&self) -> Vec3 {
        self.bounds.center()
    }

    /// Importance of these bounds at `p` with unit normal `n` (zero for a point in a medium):
    /// see [`PreparedBounds::importance`].
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        self.prepare().importance(p, n)
    }

    /// What the importance needs of these bounds alone, worked out once.
    pub fn prepare(&self) -> PreparedBounds {
        let half_diagonal = 0.5 * (self.bounds.max - self.bounds.min);
        let radius2 = half_diagonal.length_squared();
        PreparedBounds {
            centre: self.centroid(),
            radius2,
            radius: radius2.sqrt(),
            flat: self.cos_theta_o == 1.0 && self.cos_theta_e == 0.0 && radius2 > 0.0,
            point_isotropic: self.cos_theta_o == -1.0 && radius2 == 0.0,
            w: self.w,
            phi: self.phi,
            cos_theta_o: self.cos_theta_o,
            sin_theta_o: sin_from_cos(self.cos_theta_o),
            cos_theta_e: self.cos_theta_e,
            two_sided: self.two_sided,
        }
    }

    /// The same bounds but for the flux: their importance at any point differs by the ratio of
    /// their fluxes alone.
    pub fn same_but_flux(&self, o: &Self) -> bool {
        self.bounds == o.bounds
            && self.w == o.w
            && self.cos_theta_o == o.cos_theta_o
            && self.cos_theta_e == o.cos_theta_e
            && self.two_sided == o.two_sided
    }

    /// A point at `position` emitting flux `phi` over the whole sphere (θ_o = π, θ_e = π/2):
    /// the bounds of point, goniometric and projection lights.
    pub fn isotropic_point(position: Vec3, phi: f32) -> Self {
        let bounds = Bounds3::EMPTY.union_point(position);
        Self { bounds, w: Vec3::Z, phi, cos_theta_o: -1.0, cos_theta_e: 0.0, two_sided: false }
    }
}

/// [`LightBounds`] with the half-angles θ_o and θ_e [rad] worked out (acos of their cosines),
/// which every union and every split cost of the tree's build takes: a fold of many unions
/// works each out once per new cone instead of twice per union. Unions give exactly
/// [`LightBounds::union`]'s bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngledBounds {
    /// The bounds.
    pub bounds: LightBounds,
    /// θ_o, the half-angle of the normal cone.
    pub theta_o: f32,
    /// θ_e, the angle beyond the normals over which the emitters emit.
    pub theta_e: f32,
}

impl AngledBounds {
    /// `bounds` with their half-angles.
    pub fn new(bounds: LightBounds) -> Self {
        let theta_o = AngledCone::new(DirectionCone { w: bounds.w, cos_theta: bounds.cos_theta_o }).theta;
        Self { bounds, theta_o, theta_e: bounds.cos_theta_e.clamp(-1.0, 1.0).acos() }
    }

    /// [`LightBounds::union`] of the two, with its half-angles.
    pub fn union(&self, other: &Self) -> Self {
        let (a, b) = (&self.bounds, &other.bounds);
        if a.phi == 0.0 {
            return *other;
        }
        if b.phi == 0.0 {
            return *self;
        }
        let cone = |x: &Self| AngledCone {
            cone: DirectionCone { w: x.bounds.w, cos_theta: x.bounds.cos_theta_o },
            theta: x.theta_o,
        };
        let cone = AngledCone::union(&cone(self), &cone(other));
        // The smaller cosine is one of the two, and so is its angle.
        let cos_theta_e = a.cos_theta_e.min(b.cos_theta_e);
        let theta_e = if cos_theta_e == a.cos_theta_e { self.theta_e } else { other.theta_e };
        let bounds = LightBounds {
            bounds: a.bounds.union(b.bounds),
            w: cone.cone.w,
            phi: a.phi + b.phi,
            cos_theta_o: cone.cone.cos_theta,
            cos_theta_e,
            two_sided: a.two_sided || b.two_sided,
        };
        Self { bounds, theta_o: cone.theta, theta_e }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::{AreaLight, Light};
    use crate::spectrum::Spectrum;
    use std::sync::Arc;

    fn triangle(z: f32, two_sided: bool) -> Light {
        let p = [Vec3::new(0.0, 0.0, z), Vec3::new(1.0, 0.0, z), Vec3::new(0.0, 1.0, z)];
        Light::Area(AreaLight {
            p,
            n: Vec3::Z,
            area: 0.5,
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 1.0,
            two_sided,
            image: None,
        })
    }

    /// A one-sided triangle facing +z gives importance 0 to points behind it (farther than the
    /// box's subtended angle from its plane), and a positive one in front; two-sided, both sides
    /// see it.
    #[test]
    fn a_point_behind_a_one_sided_emitter_gets_no_importance() {
        let one = triangle(0.0, false).bounds(1.0).unwrap();
        let two = triangle(0.0, true).bounds(1.0).unwrap();
        for p in [Vec3::new(0.3, 0.3, -1.0), Vec3::new(2.0, -1.0, -3.0), Vec3::new(0.2, 0.2, -20.0)] {
            assert_eq!(one.importance(p, Vec3::ZERO), 0.0, "behind at {p}");
            assert_eq!(one.importance(p, Vec3::Z), 0.0, "behind at {p} with a normal");
            assert!(two.importance(p, Vec3::ZERO) > 0.0, "two-sided, behind at {p}");
        }
        let front = Vec3::new(0.3, 0.3, 2.0);
        assert!(one.importance(front, Vec3::ZERO) > 0.0);
    }

    /// Far from a small light, the importance tends to Φ cos θ / d² (times cos θ_i with a
    /// normal): checked against that expression at distance 1000 with the box's subtended angle
    /// negligible.
    #[test]
    fn far_away_the_importance_is_flux_times_cosine_over_distance_squared() {
        let b = triangle(0.0, false).bounds(3.0).unwrap();
        let pc = b.centroid();
        let dir = Vec3::new(0.6, 0.0, 0.8);
        let p = pc + 1000.0 * dir;
        let expected = 3.0 * 0.8 / 1.0e6;
        let got = b.importance(p, Vec3::ZERO);
        assert!((got - expected).abs() < 2e-3 * expected, "{got} vs {expected}");
        let n = Vec3::new(0.0, 0.0, -1.0);
        let got_n = b.importance(p, n);
        assert!((got_n - expected * 0.8).abs() < 2e-3 * expected, "{got_n} vs {}", expected * 0.8);
    }

    /// A point light's importance is Φ |cos θ_i| / d² (Φ / d² in a medium), computed here in
    /// double precision at random points and normals; at the light's own position it stays
    /// finite.
    #[test]
    fn a_point_lights_importance_is_flux_times_incident_cosine_over_distance_squared() {
        use crate::light::PointLight;
        use crate::sampling::rng::Rng;
        let c = Vec3::new(0.5, -2.0, 3.0);
        let point = Light::Point(PointLight::new(c, Arc::new(Spectrum::constant(1.0)), 1.0));
        let b = point.bounds(7.0).unwrap();
        let mut rng = Rng::new(5, 11);
        for _ in 0..1000 {
            let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 8.0 - 4.0;
            let n = (Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5).normalize();
            let d = (p - c).as_dvec3();
            let want = 7.0 * (d.normalize().dot(n.as_dvec3())).abs() / d.length_squared();
            let got = b.importance(p, n) as f64;
            // (The cosine is rounded in single precision: to about 1e-6 absolute.)
            let tolerance = 1e-5 * want + 1e-6 * 7.0 / d.length_squared();
            assert!((got - want).abs() <= tolerance, "at {p}, n {n}: {got} vs {want}");
            let in_medium = b.importance(p, Vec3::ZERO) as f64;
            assert!((in_medium - 7.0 / d.length_squared()).abs() <= 1e-5 * in_medium, "at {p} in a medium");
        }
        assert!(b.importance(c, Vec3::Z).is_finite() && b.importance(c, Vec3::ZERO).is_finite());
    }

    /// pbrt-v4 clamps d² from below by half the box's diagonal length r, not by r²: a light
    /// emitting every way (cos θ' = 1) in a box of half-side 2 (r = √12) has, in a medium,
    /// importance Φ / max(d², r) at points inside and near it, and Φ / d² beyond d = √r.
    #[test]
    fn the_squared_distance_is_clamped_by_half_the_diagonal_length() {
        let bounds = Bounds3 { min: Vec3::splat(-2.0), max: Vec3::splat(2.0) };
        let b = LightBounds { bounds, w: Vec3::Z, phi: 3.0, cos_theta_o: -1.0, cos_theta_e: 0.0, two_sided: false };
        let r = 12.0f64.sqrt();
        for d in [0.0f64, 0.5, 1.5, 1.8, 2.5, 10.0] {
            let want = 3.0 / (d * d).max(r);
            let got = b.importance(Vec3::new(0.0, d as f32, 0.0), Vec3::ZERO) as f64;
            assert!((got - want).abs() < 1e-5 * want, "at distance {d}: {got} vs {want}");
        }
    }

    /// The union keeps both boxes, a cone around both normals, the summed flux, the wider
    /// emission angle and two-sidedness.
    #[test]
    fn the_union_keeps_both_boxes_cones_and_the_summed_flux() {
        let a = triangle(0.0, false).bounds(1.0).unwrap();
        let mut b = triangle(2.0, true).bounds(2.0).unwrap();
        b.w = Vec3::X;
        let u = LightBounds::union(&a, &b);
        assert_eq!(u.phi, 3.0);
        assert_eq!(u.bounds, a.bounds.union(b.bounds));
        assert!(u.two_sided);
        assert!(u.w.dot(Vec3::Z) >= u.cos_theta_o - 1e-6 && u.w.dot(Vec3::X) >= u.cos_theta_o - 1e-6);
        assert_eq!(u.cos_theta_e, 0.0);
    }

    fn light(p: [Vec3; 3], two_sided: bool) -> Light {
        AreaLight::constant_triangle(p, two_sided)
    }

    /// `reaches` is `importance > 0`: by the plane test for flat bounds (a triangle, the two
    /// triangles of an axis-aligned rectangle), by the angles otherwise (two triangles at an
    /// angle, a point light), at points all around them and near their planes, with and without
    /// a normal.
    #[test]
    fn reaching_a_point_is_having_importance_there() {
        use crate::light::PointLight;
        use crate::sampling::rng::Rng;
        use crate::sampling::warp::sample_uniform_sphere;
        use glam::Vec2;
        let mut rng = Rng::new(31, 7);
        let unit = |rng: &mut Rng| sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
        let (mut flat, mut by_angles, mut reached, mut missed) = (0, 0, 0, 0);
        for k in 0..400 {
            let c = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0;
            let two_sided = k % 5 == 0;
            let (e1, e2) = match k % 3 {
                0 => (Vec3::X * (0.1 + rng.uniform()), Vec3::Y * (0.1 + rng.uniform())),
                1 => (Vec3::Z * (0.1 + rng.uniform()), Vec3::X * (0.1 + rng.uniform())),
                _ => (unit(&mut rng), unit(&mut rng)),
            };
            let of = |l: &Light| l.bounds(1.0).unwrap();
            let a = of(&light([c, c + e1, c + e1 + e2], two_sided));
            let b = of(&light([c, c + e1 + e2, c + e2], two_sided));
            let point = of(&Light::Point(PointLight::new(c, Arc::new(Spectrum::constant(1.0)), 1.0)));
            for bounds in [a, LightBounds::union(&a, &b), point] {
                let prepared = bounds.prepare();
                if prepared.flat {
                    flat += 1;
                } else {
                    by_angles += 1;
                }
                for _ in 0..200 {
                    // Around the box, and within 1% of its size of the plane through its centre.
                    let mut p = bounds.centroid() + unit(&mut rng) * (3.0 * rng.uniform());
                    if rng.uniform() < 0.3 {
                        p -= bounds.w * (bounds.w.dot(p - bounds.centroid()) + 0.01 * (rng.uniform() - 0.5));
                    }
                    let n = if rng.uniform() < 0.25 { Vec3::ZERO } else { unit(&mut rng) };
                    let positive = prepared.importance(p, n) > 0.0;
                    assert_eq!(prepared.reaches(p, n), positive, "{bounds:?} at {p}, n = {n}");
                    if positive {
                        reached += 1;
                    } else {
                        missed += 1;
                    }
                }
            }
        }
        assert!(flat > 300 && by_angles > 300, "{flat} flat, {by_angles} by angles");
        assert!(reached > 10_000 && missed > 10_000, "{reached} reached, {missed} not");
    }
}

//! Cones of directions (PBR 4th ed. §3.9.4): the unit vectors within angle θ of an axis `w`,
//! stored as cos θ. The light BVH bounds the normals of the lights below a node with one, and the
//! directions from a point toward a box with another.

use crate::geometry::Bounds3;
use crate::math::PI;
use glam::{Quat, Vec3};

/// The directions within θ of the unit axis `w`; cos θ = −1 is the whole sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCone {
    /// Unit axis.
    pub w: Vec3,
    /// cos θ of the half-angle.
    pub cos_theta: f32,
}

impl DirectionCone {
    /// Every direction.
    pub const ENTIRE_SPHERE: Self = Self { w: Vec3::Z, cos_theta: -1.0 };

    /// The smallest cone about a common axis containing both (PBR 4th ed. §3.9.4): when neither
    /// contains the other, the half-angle is (θ_a + θ_d + θ_b)/2 for axes θ_d apart, and the axis
    /// is `a.w` turned toward `b.w` by that half-angle minus θ_a.
    pub fn union(a: Self, b: Self) -> Self {
        let (theta_a, theta_b) = (a.cos_theta.clamp(-1.0, 1.0).acos(), b.cos_theta.clamp(-1.0, 1.0).acos());
        let theta_d = a.w.dot(b.w).clamp(-1.0, 1.0).acos();
        if (theta_d + theta_b).min(PI) <= theta_a {
            return a;
        }
        if (theta_d + theta_a).min(PI) <= theta_b {
            return b;
        }
        let theta_o = 0.5 * (theta_a + theta_d + theta_b);
        if theta_o >= PI {
            return Self::ENTIRE_SPHERE;
        }
        let axis = a.w.cross(b.w);
        if axis.length_squared() == 0.0 {
            return Self::ENTIRE_SPHERE;
        }
        let w = Quat::from_axis_angle(axis.normalize(), theta_o - theta_a) * a.w;
        Self { w: w.normalize(), cos_theta: theta_o.cos() }
    }

    /// The directions from `p` toward the box `b`, bounded by the cone about its bounding sphere
    /// (sin²θ = r²/d²); the whole sphere when `p` is inside that sphere.
    pub fn subtended_by(b: &Bounds3, p: Vec3) -> Self {
        let (center, r) = (b.center(), b.radius());
        let d2 = (p - center).length_squared();
        if d2 < r * r {
            return Self::ENTIRE_SPHERE;
        }
        let sin2_max = r * r / d2;
        Self { w: (center - p).normalize_or(Vec3::Z), cos_theta: (1.0 - sin2_max).max(0.0).sqrt() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::Rng;
    use crate::sampling::warp::sample_uniform_sphere;
    use glam::Vec2;

    fn random_cone(rng: &mut Rng) -> DirectionCone {
        let w = sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
        DirectionCone { w, cos_theta: 1.0 - 2.0 * rng.uniform() * rng.uniform() }
    }

    /// A direction inside either cone is inside their union: checked on directions sampled
    /// inside each cone by rejection, with a tolerance of 1e-4 in cos θ for rounding.
    #[test]
    fn a_union_contains_both_cones() {
        let mut rng = Rng::new(11, 2);
        for _ in 0..2000 {
            let (a, b) = (random_cone(&mut rng), random_cone(&mut rng));
            let u = DirectionCone::union(a, b);
            for _ in 0..50 {
                let d = sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
                let inside = d.dot(a.w) >= a.cos_theta || d.dot(b.w) >= b.cos_theta;
                if inside {
                    assert!(d.dot(u.w) >= u.cos_theta - 1e-4, "{a:?} ∪ {b:?} = {u:?} misses {d}");
                }
            }
        }
    }

    /// Two narrow cones 90° apart: the union's half-angle is (θ_a + 90° + θ_b)/2 about the
    /// bisector when θ_a = θ_b.
    #[test]
    fn the_union_of_two_equal_cones_is_centred_on_their_bisector() {
        let c = 10f32.to_radians().cos();
        let u = DirectionCone::union(
            DirectionCone { w: Vec3::X, cos_theta: c },
            DirectionCone { w: Vec3::Y, cos_theta: c },
        );
        assert!((u.cos_theta - 55f32.to_radians().cos()).abs() < 1e-5, "{u:?}");
        assert!((u.w - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5, "{u:?}");
    }

    /// Every corner of a box is inside the cone it subtends from an outside point.
    #[test]
    fn the_subtended_cone_contains_the_box() {
        let b = Bounds3 { min: Vec3::new(1.0, 2.0, 3.0), max: Vec3::new(2.0, 2.5, 5.0) };
        let p = Vec3::new(-3.0, 0.0, 1.0);
        let c = DirectionCone::subtended_by(&b, p);
        assert!(c.cos_theta > 0.0);
        for k in 0..8 {
            let q = Vec3::new(
                if k & 1 == 0 { b.min.x } else { b.max.x },
                if k & 2 == 0 { b.min.y } else { b.max.y },
                if k & 4 == 0 { b.min.z } else { b.max.z },
            );
            assert!((q - p).normalize().dot(c.w) >= c.cos_theta - 1e-6);
        }
        assert_eq!(DirectionCone::subtended_by(&b, b.center()), DirectionCone::ENTIRE_SPHERE);
    }
}

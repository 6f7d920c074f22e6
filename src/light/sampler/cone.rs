//! Cones of directions (PBR 4th ed. §3.9.4): the unit vectors within angle θ of an axis `w`,
//! stored as cos θ. The light BVH bounds the normals of the lights below a node with one.

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
}

/// A cone with its half-angle θ = acos(cos θ) [rad] worked out: a union needs the half-angles of
/// both cones, and a fold of many unions (the light BVH's build) works each out once instead of
/// once per union.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngledCone {
    /// The cone.
    pub cone: DirectionCone,
    /// Its half-angle [rad], in [0, π].
    pub theta: f32,
}

impl AngledCone {
    /// `cone` with its half-angle.
    pub fn new(cone: DirectionCone) -> Self {
        Self { cone, theta: cone.cos_theta.clamp(-1.0, 1.0).acos() }
    }

    /// The smallest cone about a common axis containing both (PBR 4th ed. §3.9.4), with its
    /// half-angle: when neither contains the other, the half-angle is (θ_a + θ_d + θ_b)/2 for
    /// axes θ_d apart, and the axis is `a.w` turned toward `b.w` by that half-angle minus θ_a.
    pub fn union(a: &Self, b: &Self) -> Self {
        let (theta_a, theta_b) = (a.theta, b.theta);
        // One axis: `angle_between` would give exactly 0 (2 asin 0), without its asin.
        let theta_d = if a.cone.w == b.cone.w { 0.0 } else { angle_between(a.cone.w, b.cone.w) };
        if (theta_d + theta_b).min(PI) <= theta_a {
            return *a;
        }
        if (theta_d + theta_a).min(PI) <= theta_b {
            return *b;
        }
        let theta_o = 0.5 * (theta_a + theta_d + theta_b);
        let axis = a.cone.w.cross(b.cone.w);
        if theta_o >= PI || axis.length_squared() == 0.0 {
            return Self::new(DirectionCone::ENTIRE_SPHERE);
        }
        let w = Quat::from_axis_angle(axis.normalize(), theta_o - theta_a) * a.cone.w;
        Self::new(DirectionCone { w: w.normalize(), cos_theta: theta_o.cos() })
    }
}

/// The angle between unit vectors `a` and `b` [rad], exact for nearly equal and nearly opposite
/// ones (as 2 asin(|a − b|/2), and π − 2 asin(|a + b|/2)), where acos(a · b) rounds a vector's
/// angle with itself up to 3·10⁻⁴.
fn angle_between(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        PI - 2.0 * (0.5 * (a + b).length()).min(1.0).asin()
    } else {
        2.0 * (0.5 * (b - a).length()).min(1.0).asin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::Rng;
    use crate::sampling::warp::sample_uniform_sphere;
    use glam::Vec2;

    fn union(a: DirectionCone, b: DirectionCone) -> DirectionCone {
        AngledCone::union(&AngledCone::new(a), &AngledCone::new(b)).cone
    }

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
            let u = union(a, b);
            for _ in 0..50 {
                let d = sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
                let inside = d.dot(a.w) >= a.cos_theta || d.dot(b.w) >= b.cos_theta;
                if inside {
                    assert!(d.dot(u.w) >= u.cos_theta - 1e-4, "{a:?} ∪ {b:?} = {u:?} misses {d}");
                }
            }
        }
    }

    /// A union's half-angle is the one a cone of its cosine has (acos of the cosine): a fold
    /// that carries it gives each later union the angle it would work out itself.
    #[test]
    fn a_union_carries_the_half_angle_of_its_cosine() {
        let mut rng = Rng::new(7, 9);
        for _ in 0..5000 {
            let (a, b) = (random_cone(&mut rng), random_cone(&mut rng));
            let b = if rng.uniform() < 0.2 { DirectionCone { w: a.w, ..b } } else { b };
            let u = AngledCone::union(&AngledCone::new(a), &AngledCone::new(b));
            assert_eq!(u, AngledCone::new(u.cone), "{a:?} ∪ {b:?}");
        }
    }

    /// Two narrow cones 90° apart: the union's half-angle is (θ_a + 90° + θ_b)/2 about the
    /// bisector when θ_a = θ_b.
    #[test]
    fn the_union_of_two_equal_cones_is_centred_on_their_bisector() {
        let c = 10f32.to_radians().cos();
        let u = union(DirectionCone { w: Vec3::X, cos_theta: c }, DirectionCone { w: Vec3::Y, cos_theta: c });
        assert!((u.cos_theta - 55f32.to_radians().cos()).abs() < 1e-5, "{u:?}");
        assert!((u.w - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5, "{u:?}");
    }

    /// A cone joined with itself is itself: the angle between an axis and itself is 0 (by
    /// acos(w · w) it was up to 3·10⁻⁴, which made the union of two equal narrow cones, with
    /// w × w = 0, the whole sphere).
    #[test]
    fn a_cone_joined_with_itself_is_itself() {
        let mut rng = Rng::new(5, 3);
        for _ in 0..2000 {
            let c = DirectionCone { w: sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform())), cos_theta: 1.0 };
            assert_eq!(union(c, c), c);
            let wide = DirectionCone { cos_theta: 0.3, ..c };
            assert_eq!(union(wide, c), wide);
        }
    }
}

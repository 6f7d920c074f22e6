//! How a placed object moves over the shutter interval: one animated transform, or the product
//! of two. pbrt-v4 lets a moving shape sit inside an object definition (an `AnimatedPrimitive`
//! inside the instance's BVH) and lets the instance itself move (another `AnimatedPrimitive`
//! around it), so a point of the shape reaches the world as outer(t) · inner(t) · p, each
//! factor interpolated on its own (PBR 4th ed. §3.10.1, §7.1.3). Embree has one level of
//! instancing, so prism places such a shape by one instance that carries the product.
//!
//! The product is one [`AnimatedTransform`] again when the outer factor's linear part is one
//! similarity kQ throughout (it is static, or only translates): then outer(t) · T(t) R(t) S(t)
//! has translation o(t) + kQ T(t) and linear part (Q R(t)) (k S(t)), whose keyframes the
//! polar decomposition recovers and whose interpolation — linear in the translation and
//! stretch, spherical in the rotation, which left multiplication by Q preserves — is the
//! product's. [`Motion::compose`] then keeps one transform, which Embree follows exactly.

use glam::{Mat3, Mat4};

use super::animated::AnimatedTransform;
use super::quadric::similarity_scale;
use super::Bounds3;

/// The motion of an instance.
#[derive(Clone, Debug, PartialEq)]
// Instances hold their motion behind an `Arc`: the larger variant costs no per-instance space.
#[allow(clippy::large_enum_variant)]
pub enum Motion {
    /// One animated transform.
    One(AnimatedTransform),
    /// `outer(t) · inner(t)`: an object instance's placement (static when its two matrices are
    /// equal) after the motion of a shape inside the object's definition.
    Composed {
        /// The instance's placement (world from instance space).
        outer: AnimatedTransform,
        /// The shape's motion (instance space from the shape's object space).
        inner: AnimatedTransform,
    },
}

impl From<AnimatedTransform> for Motion {
    fn from(m: AnimatedTransform) -> Self {
        Motion::One(m)
    }
}

impl Motion {
    /// `outer(t) · inner(t)`, as one transform when that is exact (see the module
    /// documentation): the outer linear part is one similarity at both keyframes, and the outer
    /// factor is static or moves over the inner one's time interval.
    pub fn compose(outer: AnimatedTransform, inner: AnimatedTransform) -> Self {
        let same_times = outer.start_time == inner.start_time && outer.end_time == inner.end_time;
        let linear_fixed = Mat3::from_mat4(outer.start) == Mat3::from_mat4(outer.end);
        if !outer.is_animated() && !inner.is_animated() {
            let m = outer.start * inner.start;
            return Motion::One(AnimatedTransform::new(m, inner.start_time, m, inner.end_time));
        }
        let outer_fits = !outer.is_animated() || same_times;
        if outer_fits && linear_fixed && similarity_scale(&outer.start).is_some() {
            let (start, end) = (outer.start * inner.start, outer.end * inner.end);
            return Motion::One(AnimatedTransform::new(start, inner.start_time, end, inner.end_time));
        }
        Motion::Composed { outer, inner }
    }

    /// The matrix at `time`.
    #[inline]
    pub fn interpolate(&self, time: f32) -> Mat4 {
        match self {
            Motion::One(m) => m.interpolate(time),
            Motion::Composed { outer, inner } => outer.interpolate(time) * inner.interpolate(time),
        }
    }

    /// The times between which it moves (outside them it rests at the nearer end).
    pub fn time_span(&self) -> (f32, f32) {
        match self {
            Motion::One(m) => (m.start_time, m.end_time),
            Motion::Composed { outer, inner } => {
                (outer.start_time.min(inner.start_time), outer.end_time.max(inner.end_time))
            }
        }
    }

    /// True when the matrix changes over time.
    pub fn is_animated(&self) -> bool {
        match self {
            Motion::One(m) => m.is_animated(),
            Motion::Composed { outer, inner } => outer.is_animated() || inner.is_animated(),
        }
    }

    /// The single transform, when it is one.
    pub fn as_one(&self) -> Option<&AnimatedTransform> {
        match self {
            Motion::One(m) => Some(m),
            Motion::Composed { .. } => None,
        }
    }

    /// A box containing `b` under the matrix of every time. A product is bounded factor by
    /// factor (the outer motion's bounds of the inner motion's box): conservative, since it
    /// also holds every pairing of the two factors' times.
    pub fn motion_bounds(&self, b: Bounds3) -> Bounds3 {
        match self {
            Motion::One(m) => m.motion_bounds(b),
            Motion::Composed { outer, inner } => outer.motion_bounds(inner.motion_bounds(b)),
        }
    }

    /// The motion followed by the static transform `m` (world from world).
    pub fn then(&self, m: Mat4) -> Self {
        let after = |a: &AnimatedTransform| AnimatedTransform::new(m * a.start, a.start_time, m * a.end, a.end_time);
        match self {
            Motion::One(a) => Motion::One(after(a)),
            Motion::Composed { outer, inner } => Motion::Composed { outer: after(outer), inner: *inner },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec3};

    fn max_diff(a: Mat4, b: Mat4) -> f32 {
        (a - b).to_cols_array().iter().fold(0.0f32, |m, x| m.max(x.abs()))
    }

    fn inner() -> AnimatedTransform {
        let a = Mat4::from_translation(Vec3::new(0.5, 0.0, 1.0)) * Mat4::from_scale(Vec3::new(1.0, 0.5, 2.0));
        let b = Mat4::from_translation(Vec3::new(-1.0, 2.0, 0.0))
            * Mat4::from_quat(Quat::from_axis_angle(Vec3::new(1.0, 1.0, 0.2).normalize(), 1.9))
            * Mat4::from_scale(Vec3::new(1.5, 0.7, 1.0));
        AnimatedTransform::new(a, 0.0, b, 1.0)
    }

    /// The product of the factors evaluated separately, in f64.
    fn product(outer: &AnimatedTransform, inner: &AnimatedTransform, t: f32) -> Mat4 {
        (outer.interpolate(t).as_dmat4() * inner.interpolate(t).as_dmat4()).as_mat4()
    }

    #[test]
    fn a_similarity_or_a_translation_outside_folds_into_one_transform() {
        let similarity = Mat4::from_translation(Vec3::new(3.0, -1.0, 2.0))
            * Mat4::from_rotation_y(0.8)
            * Mat4::from_scale(Vec3::new(-2.0, 2.0, 2.0));
        let fixed = AnimatedTransform::new(similarity, 0.0, similarity, 1.0);
        let sliding = AnimatedTransform::new(similarity, 0.0, Mat4::from_translation(Vec3::X * 4.0) * similarity, 1.0);
        for outer in [fixed, sliding] {
            let m = Motion::compose(outer, inner());
            assert!(m.as_one().is_some(), "{outer:?}");
            for k in 0..=10 {
                let t = k as f32 / 10.0;
                let d = max_diff(m.interpolate(t), product(&outer, &inner(), t));
                assert!(d < 2e-5, "t = {t}: {d}");
            }
        }
    }

    #[test]
    fn a_stretching_or_turning_outside_stays_a_product() {
        let stretch = Mat4::from_scale(Vec3::new(3.0, 1.0, 1.0)) * Mat4::from_rotation_z(0.5);
        let turning = AnimatedTransform::new(Mat4::IDENTITY, 0.0, Mat4::from_rotation_x(1.2), 1.0);
        for outer in [AnimatedTransform::new(stretch, 0.0, stretch, 1.0), turning] {
            let m = Motion::compose(outer, inner());
            assert!(m.as_one().is_none());
            assert_eq!(m.time_span(), (0.0, 1.0));
            assert!(m.is_animated());
            for k in 0..=10 {
                let t = k as f32 / 10.0;
                assert!(max_diff(m.interpolate(t), product(&outer, &inner(), t)) < 1e-5);
            }
            // The single transform between the products at the ends is another motion.
            let ends = AnimatedTransform::new(m.interpolate(0.0), 0.0, m.interpolate(1.0), 1.0);
            assert!(max_diff(ends.interpolate(0.5), m.interpolate(0.5)) > 1e-2);
            // The bounds hold the moving box at every time.
            let b = Bounds3 { min: Vec3::splat(-1.0), max: Vec3::new(1.0, 2.0, 0.5) };
            let bounds = m.motion_bounds(b);
            for k in 0..=50 {
                let moved = super::super::animated::corner_box(&m.interpolate(k as f32 / 50.0), b);
                assert!(bounds.min.cmple(moved.min).all() && bounds.max.cmpge(moved.max).all());
            }
        }
    }
}

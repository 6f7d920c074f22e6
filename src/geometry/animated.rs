//! A transform that moves over time: two keyframe matrices at a start and an end time,
//! interpolated as pbrt-v4's `AnimatedTransform` does (Pharr, Jakob & Humphreys, *Physically
//! Based Rendering*, 4th ed., §3.10.1). Each matrix is decomposed as M = T R S: the translation T,
//! a rotation R (a unit quaternion) and a symmetric stretch S found by polar decomposition
//! (Shoemake & Duff, "Matrix Animation and Polar Decomposition", Graphics Interface 1992). The
//! translation and stretch are interpolated linearly and the rotation by spherical linear
//! interpolation, so a rotating object keeps its shape instead of shearing through the linear
//! blend of its matrices.

use glam::{DMat3, Mat3, Mat4, Quat, Vec3};

use super::Bounds3;

/// One keyframe as M = T R S.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decomposed {
    /// Translation T [scene units].
    pub translation: Vec3,
    /// Rotation R, a unit quaternion (always proper: det R = +1).
    pub rotation: Quat,
    /// Symmetric stretch S (negative definite when the matrix mirrors).
    pub stretch: Mat3,
}

impl Decomposed {
    /// Decomposes the affine matrix `m` (its projective row is ignored). The polar factor is the
    /// limit of Rᵢ₊₁ = ½ (Rᵢ + Rᵢ⁻ᵀ) from R₀ = A, the linear part (Shoemake & Duff 1992, §3),
    /// iterated in f64; a mirroring A (det A < 0) gives the proper rotation −R and stretch −S, so
    /// that R is always a rotation a quaternion can hold.
    pub fn new(m: Mat4) -> Self {
        let a = Mat3::from_mat4(m).as_dmat3();
        let mut r = a;
        for _ in 0..100 {
            let next = (r + r.inverse().transpose()) * 0.5;
            let change = (0..3).map(|i| (next.col(i) - r.col(i)).abs().element_sum()).fold(0.0, f64::max);
            r = next;
            if change < 1e-12 {
                break;
            }
        }
        if r.determinant() < 0.0 {
            r = -r;
        }
        let s = r.transpose() * a;
        // Symmetrise: the product is symmetric up to rounding.
        let s = (s + s.transpose()) * 0.5;
        Self {
            translation: m.w_axis.truncate(),
            rotation: Quat::from_mat3(&orthonormal(r).as_mat3()).normalize(),
            stretch: s.as_mat3(),
        }
    }

    /// T R S as a matrix.
    pub fn matrix(&self) -> Mat4 {
        let linear = Mat3::from_quat(self.rotation) * self.stretch;
        Mat4::from_cols(
            linear.x_axis.extend(0.0),
            linear.y_axis.extend(0.0),
            linear.z_axis.extend(0.0),
            self.translation.extend(1.0),
        )
    }
}

/// Gram–Schmidt on a matrix that is already orthonormal up to rounding.
fn orthonormal(r: DMat3) -> DMat3 {
    let x = r.x_axis.normalize();
    let y = (r.y_axis - x * x.dot(r.y_axis)).normalize();
    DMat3::from_cols(x, y, x.cross(y))
}

/// A transform moving from `start` at `start_time` to `end` at `end_time` (times in the scene's
/// time units, as `TransformTimes` gives them); outside that interval it stays at the nearer end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimatedTransform {
    /// The matrix at `start_time`.
    pub start: Mat4,
    /// The matrix at `end_time`.
    pub end: Mat4,
    /// Time of `start`.
    pub start_time: f32,
    /// Time of `end` (≥ `start_time`).
    pub end_time: f32,
    from: Decomposed,
    /// The end keyframe, its quaternion on the same hemisphere as `from`'s (the shorter arc).
    to: Decomposed,
}

impl AnimatedTransform {
    /// The transform from `start` at `start_time` to `end` at `end_time`.
    pub fn new(start: Mat4, start_time: f32, end: Mat4, end_time: f32) -> Self {
        let from = Decomposed::new(start);
        let mut to = Decomposed::new(end);
        if from.rotation.dot(to.rotation) < 0.0 {
            to.rotation = -to.rotation;
        }
        Self { start, end, start_time, end_time: end_time.max(start_time), from, to }
    }

    /// True when the two matrices differ (the transform moves).
    pub fn is_animated(&self) -> bool {
        self.start != self.end
    }

    /// The two keyframes as T R S (the end's quaternion on the shorter arc from the start's).
    pub fn keyframes(&self) -> (Decomposed, Decomposed) {
        (self.from, self.to)
    }

    /// Where `time` falls between the keyframes, in [0, 1].
    #[inline]
    pub fn fraction(&self, time: f32) -> f32 {
        let span = self.end_time - self.start_time;
        if span > 0.0 {
            ((time - self.start_time) / span).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// The matrix at fraction `u` ∈ [0, 1] of the motion: exactly `start` at 0 and `end` at 1.
    pub fn at_fraction(&self, u: f32) -> Mat4 {
        if !self.is_animated() || u <= 0.0 {
            return self.start;
        }
        if u >= 1.0 {
            return self.end;
        }
        let (a, b) = (&self.from, &self.to);
        Decomposed {
            translation: a.translation.lerp(b.translation, u),
            rotation: slerp(a.rotation, b.rotation, u),
            stretch: a.stretch * (1.0 - u) + b.stretch * u,
        }
        .matrix()
    }

    /// The matrix at `time`.
    #[inline]
    pub fn interpolate(&self, time: f32) -> Mat4 {
        self.at_fraction(self.fraction(time))
    }

    /// Angle between the two keyframes' rotations [radians]: the rotation turns at this constant
    /// rate per unit of [`AnimatedTransform::fraction`].
    pub fn rotation_angle(&self) -> f32 {
        2.0 * self.from.rotation.dot(self.to.rotation).clamp(-1.0, 1.0).acos()
    }

    /// A box containing `b` transformed at every time of the motion (pbrt-v4's `MotionBounds`
    /// finds the extrema of the corners' paths analytically; this bound is conservative instead).
    /// The corner boxes at N+1 evenly spaced fractions contain the moving box at those times;
    /// between them a point p moves no farther than L Δu / 2 from the nearer sample, where
    /// |d/du (T + R S p)| ≤ L = |T₁ − T₀| + (θ max(‖S₀‖, ‖S₁‖) + ‖S₁ − S₀‖) |p|max with θ the
    /// rotation angle and ‖·‖ the Frobenius norm (≥ the spectral norm; S(u) is a convex blend).
    pub fn motion_bounds(&self, b: Bounds3) -> Bounds3 {
        if b.is_empty() || !self.is_animated() {
            return corner_box(&self.start, b);
        }
        const STEPS: usize = 32;
        let frob = |m: Mat3| (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared()).sqrt();
        let (s0, s1) = (self.from.stretch, self.to.stretch);
        let p_max = b.min.abs().max(b.max.abs()).length();
        let speed = (self.to.translation - self.from.translation).length()
            + (self.rotation_angle() * frob(s0).max(frob(s1)) + frob(s1 - s0)) * p_max;
        let pad = Vec3::splat(speed * 0.5 / STEPS as f32);
        let swept = (0..=STEPS)
            .fold(Bounds3::EMPTY, |acc, k| acc.union(corner_box(&self.at_fraction(k as f32 / STEPS as f32), b)));
        Bounds3 { min: swept.min - pad, max: swept.max + pad }
    }
}

/// Spherical linear interpolation of unit quaternions on the same hemisphere; nearly equal
/// ones are blended linearly and renormalised (the arc is then a straight line to f32 precision).
fn slerp(a: Quat, b: Quat, u: f32) -> Quat {
    let cos = a.dot(b).clamp(-1.0, 1.0);
    if cos > 0.9995 {
        return a.lerp(b, u).normalize();
    }
    let theta = cos.acos();
    let (wa, wb) = (((1.0 - u) * theta).sin(), (u * theta).sin());
    ((a * wa + b * wb) / theta.sin()).normalize()
}

/// The box around `b`'s eight corners under `m`.
pub(crate) fn corner_box(m: &Mat4, b: Bounds3) -> Bounds3 {
    if b.is_empty() {
        return b;
    }
    (0..8).fold(Bounds3::EMPTY, |acc, i| {
        let c = Vec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        );
        acc.union_point(m.transform_point3(c))
    })
}

#[cfg(test)]
#[path = "animated_tests.rs"]
mod tests;

//! Moving instances in Embree: an instance geometry with several time steps, each set as a
//! quaternion decomposition T · R · U (`rtcSetGeometryTransformQuaternion`, Embree ≥ 3.12), so
//! Embree interpolates the rotation by slerp and T and U linearly between steps, as
//! [`AnimatedTransform`] does with its polar decomposition M = T R S. Embree's ray time runs over
//! [0, 1] for every geometry: the scene's time span (the union of the moving instances'
//! intervals) is mapped onto it.
//!
//! Where U = S exactly — the keyframes' stretches are diagonal and positive, and the motion spans
//! the scene's whole time span — two time steps reproduce the interpolation exactly. Otherwise
//! (a skewing stretch, a mirror, or a shorter interval) the motion is sampled at
//! [`SAMPLED_STEPS`] times, each step factored by QR (Gram–Schmidt), and Embree's interpolation
//! between the steps approximates the polar one.

use glam::{Mat3, Mat4, Quat, Vec3};

use super::ffi;
use crate::geometry::animated::Decomposed;
use crate::geometry::Motion;

/// Time steps of a motion Embree cannot follow exactly with two.
pub const SAMPLED_STEPS: usize = 33;

/// The most time steps a geometry may have (`RTC_MAX_TIME_STEP_COUNT` in Embree 3 and 4).
pub const MAX_STEPS: usize = 129;

/// The scene's time span: the union of the moving instances' intervals (`None`: nothing moves).
pub fn time_span<'a>(motions: impl Iterator<Item = &'a Motion>) -> Option<(f32, f32)> {
    motions.fold(None, |acc, m| {
        let (start, end) = m.time_span();
        let (a, b) = acc.unwrap_or((start, end));
        Some((a.min(start), b.max(end)))
    })
}

/// Embree's ray time in [0, 1] for scene time `time` over `span`.
#[inline]
pub fn embree_time((start, end): (f32, f32), time: f32) -> f32 {
    if end > start {
        ((time - start) / (end - start)).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// A stretch Embree's upper-triangular U holds as it is: diagonal with positive entries.
fn is_positive_diagonal(s: &Mat3) -> bool {
    let d = Vec3::new(s.x_axis.x, s.y_axis.y, s.z_axis.z);
    let off = [s.x_axis.y, s.x_axis.z, s.y_axis.x, s.y_axis.z, s.z_axis.x, s.z_axis.y];
    d.min_element() > 0.0 && off.iter().all(|x| x.abs() <= 1e-6 * d.max_element())
}

/// Embree's decomposition of translation `t`, rotation `q` and upper-triangular `u` (its
/// entries below the diagonal are ignored).
fn rtc(t: Vec3, q: Quat, u: &Mat3) -> ffi::RTCQuaternionDecomposition {
    ffi::RTCQuaternionDecomposition {
        scale_x: u.x_axis.x,
        scale_y: u.y_axis.y,
        scale_z: u.z_axis.z,
        skew_xy: u.y_axis.x,
        skew_xz: u.z_axis.x,
        skew_yz: u.z_axis.y,
        shift_x: 0.0,
        shift_y: 0.0,
        shift_z: 0.0,
        quaternion_r: q.w,
        quaternion_i: q.x,
        quaternion_j: q.y,
        quaternion_k: q.z,
        translation_x: t.x,
        translation_y: t.y,
        translation_z: t.z,
    }
}

/// `m` as T · Q · U with Q a rotation and U upper triangular (QR by Gram–Schmidt on the
/// columns; a mirroring matrix gets a negative U₃₃).
fn qr(m: &Mat4) -> (Vec3, Quat, Mat3) {
    let a = Mat3::from_mat4(*m);
    let x = a.x_axis.normalize();
    let y = (a.y_axis - x * x.dot(a.y_axis)).normalize();
    let q = Mat3::from_cols(x, y, x.cross(y));
    (m.w_axis.truncate(), Quat::from_mat3(&q).normalize(), q.transpose() * a)
}

/// The time steps that make Embree follow `motion` over `span`: two for one transform Embree
/// interpolates as it is, else [`SAMPLED_STEPS`], or for a product of two motions Embree's most
/// ([`MAX_STEPS`]): Embree's interpolation between steps departs from the
/// product by about the motion's curvature times the squared step, (θ/128)² of its size for a
/// turn by θ.
pub fn time_steps(motion: &Motion, span: (f32, f32)) -> Vec<ffi::RTCQuaternionDecomposition> {
    let steps = match motion.as_one() {
        Some(one) => {
            let (from, to): (Decomposed, Decomposed) = one.keyframes();
            let whole_span = one.start_time == span.0 && one.end_time == span.1;
            if whole_span && is_positive_diagonal(&from.stretch) && is_positive_diagonal(&to.stretch) {
                return [from, to].iter().map(|k| rtc(k.translation, k.rotation, &k.stretch)).collect();
            }
            SAMPLED_STEPS
        }
        None => MAX_STEPS,
    };
    let mut previous = Quat::IDENTITY;
    (0..steps)
        .map(|k| {
            let time = span.0 + (span.1 - span.0) * k as f32 / (steps - 1) as f32;
            let (t, mut q, u) = qr(&motion.interpolate(time));
            // Consecutive quaternions on one hemisphere: slerp then takes the shorter arc.
            if k > 0 && q.dot(previous) < 0.0 {
                q = -q;
            }
            previous = q;
            rtc(t, q, &u)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::AnimatedTransform;

    /// The matrix Embree rebuilds from a decomposition: T · R · U.
    fn rebuilt(d: &ffi::RTCQuaternionDecomposition) -> Mat4 {
        let q = Quat::from_xyzw(d.quaternion_i, d.quaternion_j, d.quaternion_k, d.quaternion_r);
        let u = Mat3::from_cols(
            Vec3::new(d.scale_x, 0.0, 0.0),
            Vec3::new(d.skew_xy, d.scale_y, 0.0),
            Vec3::new(d.skew_xz, d.skew_yz, d.scale_z),
        );
        let a = Mat3::from_quat(q) * u;
        Mat4::from_cols(
            a.x_axis.extend(0.0),
            a.y_axis.extend(0.0),
            a.z_axis.extend(0.0),
            Vec3::new(d.translation_x, d.translation_y, d.translation_z).extend(1.0),
        )
    }

    fn close(a: Mat4, b: Mat4) -> bool {
        (a - b).to_cols_array().iter().all(|x| x.abs() < 1e-5)
    }

    #[test]
    fn steps_rebuild_the_motion_at_their_times() {
        let a = Mat4::from_translation(Vec3::new(1.3, 0.5, 0.2));
        let rotating = AnimatedTransform::new(a, 0.0, a * Mat4::from_rotation_y(1.3), 1.0);
        let steps = time_steps(&rotating.into(), (0.0, 1.0));
        assert_eq!(steps.len(), 2);
        assert!(close(rebuilt(&steps[0]), rotating.start) && close(rebuilt(&steps[1]), rotating.end));
        // A stretch along a rotated axis is not upper triangular: sampled steps, each exact.
        let skewed = AnimatedTransform::new(
            a,
            0.0,
            Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)) * Mat4::from_rotation_y(1.3),
            1.0,
        );
        let steps = time_steps(&skewed.into(), (0.0, 1.0));
        assert_eq!(steps.len(), SAMPLED_STEPS);
        for (k, s) in steps.iter().enumerate() {
            assert!(close(rebuilt(s), skewed.interpolate(k as f32 / (SAMPLED_STEPS - 1) as f32)), "step {k}");
        }
    }

    #[test]
    fn scene_time_maps_onto_embree_time() {
        let m = |t0, t1| Motion::from(AnimatedTransform::new(Mat4::IDENTITY, t0, Mat4::from_translation(Vec3::X), t1));
        let span = time_span([m(0.5, 1.0), m(0.0, 0.75)].iter()).unwrap();
        assert_eq!(span, (0.0, 1.0));
        assert_eq!(embree_time(span, 0.25), 0.25);
        assert_eq!(embree_time((2.0, 4.0), 3.0), 0.5);
        assert_eq!(embree_time((2.0, 4.0), 9.0), 1.0);
        assert_eq!(embree_time((1.0, 1.0), 3.0), 0.0);
    }
}

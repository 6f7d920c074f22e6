//! Moving instances in Embree: an instance geometry with several time steps, each set as a
//! quaternion decomposition T · R · U (`rtcSetGeometryTransformQuaternion`, Embree ≥ 3.12), so
//! Embree interpolates the rotation by slerp and T and U linearly between steps, as
//! [`AnimatedTransform`] does with its polar decomposition M = T R S. Embree's ray time runs over
//! [0, 1] for every geometry: the scene's time span (the union of the moving instances'
//! intervals) is mapped onto it.
//!
//! Where U = S exactly — the keyframes' stretches are diagonal and positive, and the motion spans
//! the scene's whole time span — two time steps reproduce the interpolation exactly. Otherwise
//! (a skewing stretch, a mirror, or a shorter interval) the motion is sampled at about
//! [`SAMPLED_STEPS`] evenly spaced times, each step factored by QR (Gram–Schmidt), and Embree's
//! interpolation between the steps approximates the polar one. The steps are spaced so that the
//! motion's start and end fall on steps, extended past its ends (where it stands still) to cover
//! Embree's [0, 1] (`rtcSetGeometryTimeRange`); a step interval straddling an end would follow
//! neither the still nor the moving part, an error of first order in the spacing instead of
//! second. Between steps the position error is below h²/8 · max|e″| (the `error_bound` of the
//! tests, with h the spacing): for a unit object turning 1.3 rad while stretching, 10⁻⁴–10⁻³ of
//! its size.

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

/// The time steps that make Embree follow `motion` over `span`, and the Embree time range
/// (containing [0, 1]) they are evenly spread over: two for one transform Embree interpolates as
/// it is; about [`SAMPLED_STEPS`] per unit of Embree time for one it does not, with the motion's
/// ends on steps; for a product of two motions Embree's most ([`MAX_STEPS`]) over [0, 1]:
/// Embree's interpolation between steps departs from the product by about the motion's
/// curvature times the squared step, (θ/128)² of its size for a turn by θ.
pub fn time_steps(motion: &Motion, span: (f32, f32)) -> (Vec<ffi::RTCQuaternionDecomposition>, (f32, f32)) {
    let times = match motion.as_one() {
        Some(one) => {
            let (from, to): (Decomposed, Decomposed) = one.keyframes();
            let whole_span = one.start_time == span.0 && one.end_time == span.1;
            if whole_span && is_positive_diagonal(&from.stretch) && is_positive_diagonal(&to.stretch) {
                let steps = [from, to].iter().map(|k| rtc(k.translation, k.rotation, &k.stretch)).collect();
                return (steps, (0.0, 1.0));
            }
            sample_times(embree_time(span, one.start_time), embree_time(span, one.end_time))
        }
        None => (0..MAX_STEPS).map(|k| k as f32 / (MAX_STEPS - 1) as f32).collect(),
    };
    let range = (times[0], times[times.len() - 1]);
    let mut previous = Quat::IDENTITY;
    let steps = times
        .iter()
        .enumerate()
        .map(|(k, &s)| {
            let (t, mut q, u) = qr(&motion.interpolate(span.0 + (span.1 - span.0) * s));
            // Consecutive quaternions on one hemisphere: slerp then takes the shorter arc.
            if k > 0 && q.dot(previous) < 0.0 {
                q = -q;
            }
            previous = q;
            rtc(t, q, &u)
        })
        .collect();
    (steps, range)
}

/// Evenly spaced Embree times, about `SAMPLED_STEPS` − 1 intervals per unit, with `a` and `b`
/// (the motion's ends in Embree time, 0 ≤ a ≤ b ≤ 1) among them and the first ≤ 0, the last ≥ 1;
/// [`MAX_STEPS`] over [0, 1] for a motion too short for that.
fn sample_times(a: f32, b: f32) -> Vec<f32> {
    let per_unit = (SAMPLED_STEPS - 1) as f32;
    if b <= a {
        // No interval to follow (the motion stands at one end): steps over [0, 1].
        return (0..SAMPLED_STEPS).map(|k| k as f32 / per_unit).collect();
    }
    let inside = ((b - a) * per_unit).round().max(1.0);
    let h = (b - a) / inside;
    let mut before = (a / h).ceil();
    if a - before * h > 0.0 {
        before += 1.0;
    }
    let mut after = ((1.0 - b) / h).ceil();
    if b + after * h < 1.0 {
        after += 1.0;
    }
    let count = (before + inside + after) as usize + 1;
    if count > MAX_STEPS {
        // A motion shorter than about 1/128 of the span: as many steps as Embree takes, its ends
        // between them.
        return (0..MAX_STEPS).map(|k| k as f32 / (MAX_STEPS - 1) as f32).collect();
    }
    // The ends of the motion exactly, the others from the nearer end.
    (0..count)
        .map(|k| {
            let j = k as f32 - before;
            if j <= inside * 0.5 {
                a + j * h
            } else {
                b - (inside - j) * h
            }
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
        let (steps, range) = time_steps(&rotating.into(), (0.0, 1.0));
        assert_eq!((steps.len(), range), (2, (0.0, 1.0)));
        assert!(close(rebuilt(&steps[0]), rotating.start) && close(rebuilt(&steps[1]), rotating.end));
        // A stretch along a rotated axis is not upper triangular: sampled steps, each exact.
        let skewed = AnimatedTransform::new(
            a,
            0.0,
            Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)) * Mat4::from_rotation_y(1.3),
            1.0,
        );
        let (steps, range) = time_steps(&skewed.into(), (0.0, 1.0));
        assert_eq!((steps.len(), range), (SAMPLED_STEPS, (0.0, 1.0)));
        for (k, s) in steps.iter().enumerate() {
            assert!(close(rebuilt(s), skewed.interpolate(k as f32 / (SAMPLED_STEPS - 1) as f32)), "step {k}");
        }
    }

    /// Embree's transform at its time `s` ∈ [0, 1] between `steps` (evenly spaced over
    /// `range`): the translation and U interpolated linearly, the rotation by slerp (Embree's
    /// `slerp(AffineSpace3ff, AffineSpace3ff, t)` for quaternion decompositions).
    fn embree_at(steps: &[ffi::RTCQuaternionDecomposition], range: (f32, f32), s: f32) -> Mat4 {
        let n = steps.len() - 1;
        let x = ((s - range.0) / (range.1 - range.0)).clamp(0.0, 1.0) * n as f32;
        let k = (x.floor() as usize).min(n - 1);
        let f = x - k as f32;
        let (a, b) = (rebuilt_parts(&steps[k]), rebuilt_parts(&steps[k + 1]));
        let t = a.0.lerp(b.0, f);
        let q = a.1.slerp(b.1, f);
        let u = a.2 * (1.0 - f) + b.2 * f;
        let l = Mat3::from_quat(q) * u;
        Mat4::from_cols(l.x_axis.extend(0.0), l.y_axis.extend(0.0), l.z_axis.extend(0.0), t.extend(1.0))
    }

    /// A step's translation, rotation and upper-triangular U.
    fn rebuilt_parts(d: &ffi::RTCQuaternionDecomposition) -> (Vec3, Quat, Mat3) {
        let q = Quat::from_xyzw(d.quaternion_i, d.quaternion_j, d.quaternion_k, d.quaternion_r);
        let u = Mat3::from_cols(
            Vec3::new(d.scale_x, 0.0, 0.0),
            Vec3::new(d.skew_xy, d.scale_y, 0.0),
            Vec3::new(d.skew_xz, d.skew_yz, d.scale_z),
        );
        (Vec3::new(d.translation_x, d.translation_y, d.translation_z), q, u)
    }

    /// Frobenius norm (≥ the spectral norm).
    fn frob(m: Mat3) -> f32 {
        (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared()).sqrt()
    }

    /// A bound on |M_embree(s) p − M(s) p| over s ∈ [0, 1] and |p| ≤ `radius` for `motion`
    /// sampled over `span`. Both paths agree at the steps, h apart over `range`.
    /// On a step interval where both are smooth the difference e vanishes at its ends, so
    /// |e| ≤ h²/8 · max|e″| (the error of linear interpolation), with |e″| ≤ |p″| + |p_e″|:
    /// p = T + R S p moving at rate r = d(fraction)/ds has |p″| ≤ r² (θ² σ + 2θ ‖S₁ − S₀‖) |p|
    /// (θ the rotation angle, σ the largest ‖S‖; T and S are linear), and Embree's path
    /// |p_e″| ≤ (ω² ‖U‖ + 2ω ‖ΔU‖/h) |p| with ω the step's angle over h. On the step interval
    /// holding an end of a motion shorter than the span (a kink of p) only |e| ≤ h/2 · max|e′|
    /// holds, with |p′| ≤ r (|ΔT| + (θ σ + ‖ΔS‖) |p|) and |p_e′| ≤ |ΔT_k|/h + (ω ‖U‖ + ‖ΔU‖/h) |p|.
    fn error_bound(
        motion: &AnimatedTransform,
        span: (f32, f32),
        (steps, range): (&[ffi::RTCQuaternionDecomposition], (f32, f32)),
        radius: f32,
    ) -> f32 {
        let h = (range.1 - range.0) / (steps.len() - 1) as f32;
        let (from, to) = motion.keyframes();
        let s_of = |time: f32| (time - span.0) / (span.1 - span.0);
        let (s0, s1) = (s_of(motion.start_time), s_of(motion.end_time));
        let r = 1.0 / (s1 - s0);
        let theta = motion.rotation_angle();
        let sigma = frob(from.stretch).max(frob(to.stretch));
        let ds = frob(to.stretch - from.stretch);
        let dt = (to.translation - from.translation).length();
        let p2 = r * r * (theta * theta * sigma + 2.0 * theta * ds) * radius;
        let p1 = r * (dt + (theta * sigma + ds) * radius);
        (0..steps.len() - 1)
            .map(|k| {
                let (a, b) = (rebuilt_parts(&steps[k]), rebuilt_parts(&steps[k + 1]));
                let omega = 2.0 * a.1.dot(b.1).abs().min(1.0).acos() / h;
                let u = frob(a.2).max(frob(b.2));
                let du = frob(b.2 - a.2) / h;
                let (lo, hi) = (range.0 + k as f32 * h, range.0 + (k + 1) as f32 * h);
                let kink = [s0, s1].iter().any(|&e| e > lo + 1e-6 && e < hi - 1e-6);
                if kink {
                    let pe1 = (b.0 - a.0).length() / h + (omega * u + du) * radius;
                    0.5 * h * (p1 + pe1)
                } else {
                    let pe2 = (omega * omega * u + 2.0 * omega * du) * radius;
                    h * h / 8.0 * (p2 + pe2)
                }
            })
            .fold(0.0, f32::max)
    }

    /// The largest |M_embree(s) c − M(s) c| over 4097 times and the corners c of [−1, 1]³ (the
    /// difference is affine in p, so on the cube it is largest at a corner).
    fn measured_error(
        motion: &AnimatedTransform,
        span: (f32, f32),
        (steps, range): (&[ffi::RTCQuaternionDecomposition], (f32, f32)),
    ) -> f32 {
        let mut worst = 0.0f32;
        for i in 0..=4096 {
            let s = i as f32 / 4096.0;
            let (e, m) = (embree_at(steps, range, s), motion.interpolate(span.0 + (span.1 - span.0) * s));
            for c in 0..8 {
                let p = Vec3::new([-1.0, 1.0][c & 1], [-1.0, 1.0][(c >> 1) & 1], [-1.0, 1.0][c >> 2]);
                worst = worst.max((e.transform_point3(p) - m.transform_point3(p)).length());
            }
        }
        worst
    }

    #[test]
    fn sampled_steps_follow_the_polar_interpolation_within_the_derived_bound() {
        let a = Mat4::from_translation(Vec3::new(1.3, 0.5, 0.2));
        let turned = Mat4::from_translation(Vec3::new(-0.4, 1.0, 0.7)) * Mat4::from_rotation_y(1.3);
        let cases = [
            // A stretch along a rotated axis (not upper triangular in any frame the rotation
            // passes through).
            ("skew", AnimatedTransform::new(a, 0.0, Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)) * turned, 1.0)),
            // A mirror at both keyframes.
            (
                "mirror",
                AnimatedTransform::new(
                    a * Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0)),
                    0.0,
                    turned * Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0)),
                    1.0,
                ),
            ),
            // A rigid motion over half of the scene's span, its ends on steps (0.25 = 8/32).
            ("aligned half", AnimatedTransform::new(a, 0.25, turned, 0.75)),
            // ... and ends between steps.
            ("unaligned", AnimatedTransform::new(a, 0.1, turned, 0.6)),
        ];
        for (what, m) in cases {
            let span = (0.0, 1.0);
            let (steps, range) = time_steps(&m.into(), span);
            assert!(
                steps.len() >= SAMPLED_STEPS && range.0 <= 0.0 && range.1 >= 1.0,
                "{what}: {} over {range:?}",
                steps.len()
            );
            let radius = 3f32.sqrt();
            let sampled = (&steps[..], range);
            let (measured, bound) = (measured_error(&m, span, sampled), error_bound(&m, span, sampled, radius));
            eprintln!("{what}: measured {measured:.2e}, bound {bound:.2e} over the cube [−1, 1]³");
            // f32 rounding of the matrices (~1e-6 at these magnitudes) on top of the bound.
            assert!(measured <= bound + 1e-5, "{what}: {measured} > {bound}");
            assert!(measured > 0.0);
        }
    }

    #[test]
    fn sample_times_put_the_motions_ends_on_steps_and_cover_embree_time() {
        for (a, b) in [(0.0, 1.0), (0.25, 0.75), (0.1, 0.6), (0.0, 0.3), (0.9, 1.0), (0.33, 0.34)] {
            let times = sample_times(a, b);
            let h = times[1] - times[0];
            assert!(times[0] <= 0.0 && times[times.len() - 1] >= 1.0, "{a}..{b}: {times:?}");
            assert!(times[0] > -h && times[times.len() - 1] < 1.0 + h, "{a}..{b}: one step at most beyond [0, 1]");
            assert!(times.contains(&a) && times.contains(&b), "{a}..{b}: {times:?}");
            assert!(times.windows(2).all(|w| ((w[1] - w[0]) - h).abs() < 1e-5), "{a}..{b}: uneven {times:?}");
            assert!(h <= 1.5 / (SAMPLED_STEPS - 1) as f32, "{a}..{b}: spacing {h}");
        }
        // Too short to hold both ends on at most Embree's most steps.
        let times = sample_times(0.5, 0.501);
        assert_eq!((times.len(), times[0], times[MAX_STEPS - 1]), (MAX_STEPS, 0.0, 1.0));
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

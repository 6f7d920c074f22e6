use glam::{Mat3, Mat4, Vec3};

use super::*;

fn max_diff(a: Mat4, b: Mat4) -> f32 {
    (a - b).to_cols_array().iter().fold(0.0f32, |m, x| m.max(x.abs()))
}

fn rng(seed: &mut u32) -> f32 {
    *seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
    (*seed >> 8) as f32 / (1u32 << 24) as f32
}

#[test]
fn keyframe_times_give_the_two_matrices() {
    let a = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)) * Mat4::from_rotation_x(0.4);
    let b = Mat4::from_translation(Vec3::new(-1.0, 0.5, 3.0)) * Mat4::from_scale(Vec3::new(2.0, 1.0, 0.5));
    let m = AnimatedTransform::new(a, 2.0, b, 5.0);
    assert_eq!(m.interpolate(2.0), a);
    assert_eq!(m.interpolate(5.0), b);
    // Outside the interval the transform stays at the nearer keyframe.
    assert_eq!(m.interpolate(-10.0), a);
    assert_eq!(m.interpolate(9.0), b);
    assert!(max_diff(m.interpolate(3.5), a) > 0.1 && max_diff(m.interpolate(3.5), b) > 0.1);
}

#[test]
fn a_quarter_turn_is_an_eighth_turn_halfway() {
    let m = AnimatedTransform::new(Mat4::IDENTITY, 0.0, Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2), 1.0);
    let half = m.interpolate(0.5);
    let expected = Mat4::from_rotation_y(std::f32::consts::FRAC_PI_4);
    assert!(max_diff(half, expected) < 1e-6, "{half:?}");
    // Orthonormal: the linear blend of the matrices would shrink the columns to |cos 45°| ≈ 0.707.
    let a = Mat3::from_mat4(half);
    assert!((a.transpose() * a - Mat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-6));
    assert!((m.rotation_angle() - std::f32::consts::FRAC_PI_2).abs() < 1e-5);
}

#[test]
fn translation_and_scale_blend_linearly() {
    let a = Mat4::from_translation(Vec3::new(-0.6, 0.3, 1.6)) * Mat4::from_scale(Vec3::splat(0.6));
    let b = Mat4::from_translation(Vec3::new(-0.6, 1.2, 1.6)) * Mat4::from_scale(Vec3::splat(1.2));
    let m = AnimatedTransform::new(a, 0.0, b, 1.0);
    let expected = Mat4::from_translation(Vec3::new(-0.6, 0.75, 1.6)) * Mat4::from_scale(Vec3::splat(0.9));
    assert!(max_diff(m.interpolate(0.5), expected) < 1e-6);
}

#[test]
fn decomposition_rebuilds_rotated_stretched_and_mirrored_matrices() {
    let mut seed = 7;
    for k in 0..200 {
        let axis = Vec3::new(rng(&mut seed) - 0.5, rng(&mut seed) - 0.5, rng(&mut seed) - 0.5).normalize();
        let s = Vec3::new(0.2 + 3.0 * rng(&mut seed), 0.2 + 3.0 * rng(&mut seed), 0.2 + 3.0 * rng(&mut seed));
        let mirror = if k % 3 == 0 { Vec3::new(-1.0, 1.0, 1.0) } else { Vec3::ONE };
        let m = Mat4::from_translation(Vec3::new(rng(&mut seed), 5.0, -2.0))
            * Mat4::from_axis_angle(axis, 6.0 * rng(&mut seed))
            * Mat4::from_scale(s * mirror)
            * Mat4::from_axis_angle(axis.cross(Vec3::Y).normalize(), rng(&mut seed));
        let d = Decomposed::new(m);
        assert!(max_diff(d.matrix(), m) < 1e-5 * (1.0 + s.max_element()), "{m:?}");
        assert!((Mat3::from_quat(d.rotation).determinant() - 1.0).abs() < 1e-5);
        assert!(max_diff(Mat4::from_mat3(d.stretch), Mat4::from_mat3(d.stretch.transpose())) < 1e-6);
    }
}

#[test]
fn motion_bounds_contain_the_moving_box_and_stay_tight() {
    let b = Bounds3 { min: Vec3::new(-0.5, -0.5, -0.5), max: Vec3::new(0.5, 1.5, 0.5) };
    let a = Mat4::from_translation(Vec3::new(1.3, 0.5, 0.2));
    let e = a * Mat4::from_rotation_y(75f32.to_radians()) * Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0));
    let m = AnimatedTransform::new(a, 0.0, e, 1.0);
    let bound = m.motion_bounds(b);
    let mut seed = 3;
    let mut seen = Bounds3::EMPTY;
    for _ in 0..100_000 {
        let p = b.min + (b.max - b.min) * Vec3::new(rng(&mut seed), rng(&mut seed), rng(&mut seed));
        let w = m.interpolate(rng(&mut seed)).transform_point3(p);
        assert!(w.cmpge(bound.min).all() && w.cmple(bound.max).all(), "{w} outside {bound:?}");
        seen = seen.union_point(w);
    }
    // Conservative but not loose: within 5% of the extent the samples reach.
    let slack = (bound.max - seen.max).max(seen.min - bound.min);
    assert!(slack.max_element() < 0.05 * (seen.max - seen.min).max_element(), "{bound:?} vs {seen:?}");
}

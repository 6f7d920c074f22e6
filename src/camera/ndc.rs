//! The projection pbrt-v4 records in an image's header (`worldToNDC`): its projective cameras'
//! screen space (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed., §5.2) mapped
//! from [−1, 1] to [0, 1] on each axis. It depends on the field of view only: the screen window,
//! the image's aspect ratio and a crop leave it alone, so the shorter image axis spans [0, 1]
//! and the longer one more.

use super::Projection;
use glam::Mat4;

/// pbrt-v4's near and far planes of its perspective projection [scene units].
const NEAR: f32 = 1e-2;
const FAR: f32 = 1000.0;

/// NDC from camera space for `projection` with full field of view `fov_deg` along the shorter
/// axis: Translate(½, ½, ½) · Scale(½, ½, ½) · screen-from-camera, where screen-from-camera is
/// pbrt-v4's `Perspective(fov, 0.01, 1000)` (x and y over z, scaled by 1/tan(fov/2); z mapped
/// to [0, 1] between the planes, so NDC z is ½ at the near plane) for the perspective camera and `Orthographic(0, 1)` (the
/// identity) for the orthographic one. `None` for the others, which pbrt-v4 gives no NDC.
pub fn ndc_from_camera(projection: Projection, fov_deg: f32) -> Option<Mat4> {
    let screen_from_camera = match projection {
        Projection::Perspective => {
            let inv_tan = 1.0 / (fov_deg.to_radians() * 0.5).tan();
            let persp = Mat4::from_cols_array_2d(&[
                // Columns: x, y, z, w.
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, FAR / (FAR - NEAR), 1.0],
                [0.0, 0.0, -FAR * NEAR / (FAR - NEAR), 0.0],
            ]);
            Mat4::from_scale(glam::Vec3::new(inv_tan, inv_tan, 1.0)) * persp
        }
        Projection::Orthographic => Mat4::IDENTITY,
        _ => return None,
    };
    let half = glam::Vec3::splat(0.5);
    Some(Mat4::from_translation(half) * Mat4::from_scale(half) * screen_from_camera)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn the_field_of_view_spans_zero_to_one() {
        let m = ndc_from_camera(Projection::Perspective, 60.0).unwrap();
        let t = 30f32.to_radians().tan();
        // The top-right corner of the view at depth 5 lands on (1, 1); the axis on (½, ½).
        let p = m * Vec4::new(5.0 * t, 5.0 * t, 5.0, 1.0);
        let q = m * Vec4::new(0.0, 0.0, 3.0, 1.0);
        assert!((p.truncate() / p.w - glam::Vec3::new(1.0, 1.0, p.z / p.w)).length() < 1e-5, "{p}");
        assert!(((q.x / q.w) - 0.5).abs() < 1e-6 && ((q.y / q.w) - 0.5).abs() < 1e-6);
        // Screen z is 0 at the near plane and 1 at the far one, so NDC z is ½ and 1.
        let near = m * Vec4::new(0.0, 0.0, NEAR, 1.0);
        let far = m * Vec4::new(0.0, 0.0, FAR, 1.0);
        assert!((near.z / near.w - 0.5).abs() < 1e-4, "{near}");
        assert!((far.z / far.w - 1.0).abs() < 1e-4, "{far}");
        assert_eq!(ndc_from_camera(Projection::Orthographic, 60.0).unwrap().w_axis, Vec4::new(0.5, 0.5, 0.5, 1.0));
        assert!(ndc_from_camera(Projection::SphericalEquirect, 60.0).is_none());
    }
}

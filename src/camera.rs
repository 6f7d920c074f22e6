//! Perspective camera (pbrt-v4 conventions): `fov` spans the shorter image axis, an optional thin
//! lens gives depth of field, and the camera looks down +z in its own space.

use crate::geometry::Ray;
use crate::sampling::warp::sample_uniform_disk_concentric;
use glam::{Mat4, Vec2, Vec3};

/// A pinhole or thin-lens perspective camera.
#[derive(Clone, Debug)]
pub struct Camera {
    /// Camera space → world space.
    pub camera_to_world: Mat4,
    /// Image size in pixels.
    pub resolution: (u32, u32),
    /// Screen window [x0, x1, y0, y1] at unit distance (tan of the half-angles).
    screen: [f32; 4],
    /// Thin-lens radius [scene units]; 0 for a pinhole.
    pub lens_radius: f32,
    /// Distance to the plane in focus [scene units].
    pub focal_distance: f32,
}

impl Camera {
    /// A perspective camera with full field of view `fov_deg` along the shorter image axis
    /// (pbrt-v4's "fov"), unless `screen_window` is given.
    pub fn perspective(
        camera_to_world: Mat4,
        resolution: (u32, u32),
        fov_deg: f32,
        lens_radius: f32,
        focal_distance: f32,
        screen_window: Option<[f32; 4]>,
    ) -> Self {
        let aspect = resolution.0 as f32 / resolution.1 as f32;
        let sw = screen_window.unwrap_or(if aspect > 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        });
        let t = (fov_deg.to_radians() * 0.5).tan();
        Self {
            camera_to_world,
            resolution,
            screen: [sw[0] * t, sw[1] * t, sw[2] * t, sw[3] * t],
            lens_radius,
            focal_distance,
        }
    }

    /// A camera-to-world matrix looking from `eye` at `target` with `up` (left-handed camera
    /// space like pbrt: +x right, +y up, +z forward).
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
        let dir = (target - eye).normalize();
        let right = up.normalize().cross(dir).normalize();
        let new_up = dir.cross(right);
        Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), eye.extend(1.0))
    }

    /// The primary ray through film position `p_film` (pixels, origin at the top-left corner,
    /// y down) using lens sample `u_lens` in [0,1)². The direction is unit length.
    pub fn generate_ray(&self, p_film: Vec2, u_lens: Vec2) -> Ray {
        let (w, h) = (self.resolution.0 as f32, self.resolution.1 as f32);
        let [x0, x1, y0, y1] = self.screen;
        let sx = x0 + (x1 - x0) * (p_film.x / w);
        let sy = y1 - (y1 - y0) * (p_film.y / h);
        let mut o = Vec3::ZERO;
        let mut d = Vec3::new(sx, sy, 1.0).normalize();
        if self.lens_radius > 0.0 {
            let lens = self.lens_radius * sample_uniform_disk_concentric(u_lens);
            let ft = self.focal_distance / d.z;
            let focus = d * ft;
            o = Vec3::new(lens.x, lens.y, 0.0);
            d = (focus - o).normalize();
        }
        let o = self.camera_to_world.transform_point3(o);
        let d = self.camera_to_world.transform_vector3(d).normalize();
        Ray::new(o, d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_points_at_target_and_fov_spans_short_axis() {
        let m = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, 10.0), Vec3::Y);
        let cam = Camera::perspective(m, (200, 100), 90.0, 0.0, 1.0, None);
        let r = cam.generate_ray(Vec2::new(100.0, 50.0), Vec2::ZERO);
        assert!((r.d - Vec3::Z).length() < 1e-6);
        assert!((r.o - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        // Top edge (short axis) at 45° for a 90° fov.
        let top = cam.generate_ray(Vec2::new(100.0, 0.0), Vec2::ZERO);
        assert!((top.d.y.atan2(top.d.z).to_degrees() - 45.0).abs() < 1e-3);
        // Right edge is wider by the aspect ratio; +x in camera space is image right.
        let right = cam.generate_ray(Vec2::new(200.0, 50.0), Vec2::ZERO);
        assert!((right.d.x / right.d.z - 2.0).abs() < 1e-4, "{:?}", right.d);
    }

    #[test]
    fn thin_lens_rays_converge_on_the_focal_plane() {
        let m = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y);
        let cam = Camera::perspective(m, (64, 64), 40.0, 0.5, 5.0, None);
        let p = Vec2::new(20.0, 40.0);
        let pin = Camera::perspective(m, (64, 64), 40.0, 0.0, 5.0, None).generate_ray(p, Vec2::ZERO);
        let target = pin.at(5.0 / pin.d.z);
        for u in [Vec2::new(0.1, 0.9), Vec2::new(0.7, 0.2), Vec2::new(0.5, 0.5)] {
            let r = cam.generate_ray(p, u);
            let hit = r.at((5.0 - r.o.z) / r.d.z);
            assert!((hit - target).length() < 1e-4, "{hit:?} vs {target:?}");
        }
    }
}

//! Cameras (pbrt-v4 conventions; the camera looks down +z in its own space, +y up): perspective
//! (`fov` spans the shorter image axis) and orthographic (the screen window in scene units),
//! both with an optional thin lens for depth of field; spherical (every direction, through an
//! equal-area or equirectangular image); and realistic (a lens system traced ray by ray, whose
//! rays carry weights). Every ray is made in camera space and carried to world space by the
//! camera's transform at the ray's time ([`CameraTransform`]), which may move over the shutter.

pub mod exit_pupil;
mod importance;
pub mod lens;
pub mod lens_system;
pub mod ndc;
pub mod realistic;
pub mod transform;

use crate::geometry::{AnimatedTransform, Ray};
use crate::math::equal_area;
use crate::sampling::warp::sample_uniform_disk_concentric;
use glam::{Mat4, Vec2, Vec3};
pub use importance::CameraWiSample;
pub use realistic::RealisticLens;
use std::sync::Arc;
pub use transform::CameraTransform;

/// How film positions become rays in camera space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Projection {
    /// Rays from the eye (or the lens) through the screen window at unit distance.
    #[default]
    Perspective,
    /// Parallel rays along +z from the screen window on the z = 0 plane.
    Orthographic,
    /// Every direction: the image is Clarberg's equal-area square (pbrt-v4's default
    /// "equalarea"; `math::equal_area`) with y and z swapped, as pbrt-v4 does, so the square's
    /// centre looks along camera +y.
    SphericalEqualArea,
    /// Every direction: latitude-longitude, θ = π v from +y down, φ = 2π u.
    SphericalEquirect,
    /// Through a lens system onto a physical film ([`RealisticLens`]).
    Realistic,
}

/// A primary ray and the factor the radiance it brings back is scaled by (pbrt-v4's
/// `CameraRay`; 1 for every camera but the realistic one).
#[derive(Clone, Copy, Debug)]
pub struct CameraRay {
    /// The ray [world space; unit direction].
    pub ray: Ray,
    /// The weight of its radiance.
    pub weight: f32,
}

/// A pinhole or thin-lens perspective camera.
#[derive(Clone, Debug)]
pub struct Camera {
    /// Camera space → world space, at each time.
    pub transform: CameraTransform,
    /// Image size in pixels.
    pub resolution: (u32, u32),
    /// Screen window [x0, x1, y0, y1] at unit distance (tan of the half-angles).
    screen: [f32; 4],
    /// Thin-lens radius [scene units]; 0 for a pinhole.
    pub lens_radius: f32,
    /// Distance to the plane in focus [scene units].
    pub focal_distance: f32,
    /// The projection.
    pub projection: Projection,
    /// The lens system of a realistic camera.
    pub lens: Option<Arc<RealisticLens>>,
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
            transform: CameraTransform::fixed(camera_to_world),
            resolution,
            screen: [sw[0] * t, sw[1] * t, sw[2] * t, sw[3] * t],
            lens_radius,
            focal_distance,
            projection: Projection::Perspective,
            lens: None,
        }
    }

    /// An orthographic camera whose screen window [x0, x1, y0, y1] is in scene units (default
    /// ±aspect by ±1 on the longer axis, as pbrt-v4), with an optional thin lens.
    pub fn orthographic(
        camera_to_world: Mat4,
        resolution: (u32, u32),
        lens_radius: f32,
        focal_distance: f32,
        screen_window: Option<[f32; 4]>,
    ) -> Self {
        let c = Self::perspective(camera_to_world, resolution, 90.0, lens_radius, focal_distance, screen_window);
        Self { projection: Projection::Orthographic, ..c }
    }

    /// A spherical camera (`projection` one of the two spherical ones).
    pub fn spherical(camera_to_world: Mat4, resolution: (u32, u32), projection: Projection) -> Self {
        let c = Self::perspective(camera_to_world, resolution, 90.0, 0.0, 1.0, None);
        Self { projection, ..c }
    }

    /// A realistic camera: film rays traced through `lens`.
    pub fn realistic(camera_to_world: Mat4, resolution: (u32, u32), lens: Arc<RealisticLens>) -> Self {
        let c = Self::perspective(camera_to_world, resolution, 90.0, 0.0, 1.0, None);
        Self { projection: Projection::Realistic, lens: Some(lens), ..c }
    }

    /// The same camera moving by `motion` (camera space → world space over the shutter; `None`
    /// or equal keyframes: it stays where it was built).
    pub fn with_motion(self, motion: Option<AnimatedTransform>) -> Self {
        let fixed = self.transform.world_from_camera(0.0);
        Self { transform: CameraTransform::new(fixed, motion), ..self }
    }

    /// A camera-to-world matrix looking from `eye` at `target` with `up` (left-handed camera
    /// space like pbrt: +x right, +y up, +z forward).
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
        let dir = (target - eye).normalize();
        let right = up.normalize().cross(dir).normalize();
        let new_up = dir.cross(right);
        Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), eye.extend(1.0))
    }

    /// The primary ray at `time` through film position `p_film` (pixels, origin at the
    /// top-left corner, y down) using lens sample `u_lens` in [0,1)², and its weight; `None`
    /// when a realistic camera's lens blocks it. The ray is made in camera space and carried to
    /// world space by the camera's transform at `time` (pbrt-v4 `CameraBase::RenderFromCamera`).
    #[inline]
    pub fn sample_ray(&self, p_film: Vec2, u_lens: Vec2, time: f32) -> Option<CameraRay> {
        let (o, d, weight) = match &self.lens {
            None => {
                let (o, d) = self.camera_space_ray(p_film, u_lens);
                (o, d, 1.0)
            }
            Some(lens) => lens.generate_ray(p_film, self.resolution, u_lens)?,
        };
        let world_from_camera = self.transform.world_from_camera(time);
        let o = world_from_camera.transform_point3(o);
        let d = world_from_camera.transform_vector3(d).normalize();
        Some(CameraRay { ray: Ray::new(o, d).at_time(time), weight })
    }

    /// The ray [camera space: origin, unit direction] of a camera without a lens system through
    /// film position `p_film` (as [`Camera::sample_ray`]) with lens sample `u_lens`.
    fn camera_space_ray(&self, p_film: Vec2, u_lens: Vec2) -> (Vec3, Vec3) {
        let (w, h) = (self.resolution.0 as f32, self.resolution.1 as f32);
        let [x0, x1, y0, y1] = self.screen;
        let sx = x0 + (x1 - x0) * (p_film.x / w);
        let sy = y1 - (y1 - y0) * (p_film.y / h);
        let uv = Vec2::new(p_film.x / w, p_film.y / h);
        let (mut o, mut d) = match self.projection {
            // A realistic projection without its lens (never built so) is a pinhole.
            Projection::Perspective | Projection::Realistic => (Vec3::ZERO, Vec3::new(sx, sy, 1.0).normalize()),
            Projection::Orthographic => (Vec3::new(sx, sy, 0.0), Vec3::Z),
            Projection::SphericalEqualArea => {
                // A filter sample beyond the film's edge continues across it, as pbrt-v4 wraps
                // it: the square's edges are glued to themselves reversed (a clamp would pile
                // those samples onto the edge's directions).
                let d = equal_area::square_to_sphere(equal_area::wrap_square(uv).clamp(Vec2::ZERO, Vec2::ONE));
                (Vec3::ZERO, Vec3::new(d.x, d.z, d.y))
            }
            Projection::SphericalEquirect => {
                let (theta, phi) = (std::f32::consts::PI * uv.y, std::f32::consts::TAU * uv.x);
                let (st, ct) = theta.sin_cos();
                let (sp, cp) = phi.sin_cos();
                (Vec3::ZERO, Vec3::new(st * cp, ct, st * sp))
            }
        };
        let has_lens = matches!(self.projection, Projection::Perspective | Projection::Orthographic);
        if has_lens && self.lens_radius > 0.0 {
            let lens = self.lens_radius * sample_uniform_disk_concentric(u_lens);
            let ft = self.focal_distance / d.z;
            let focus = o + d * ft;
            o = Vec3::new(o.x + lens.x, o.y + lens.y, 0.0);
            d = (focus - o).normalize();
        }
        (o, d)
    }

    /// The ray of a camera without a lens system at time 0 (as [`Camera::sample_ray`]).
    #[cfg(test)]
    fn generate_ray(&self, p_film: Vec2, u_lens: Vec2) -> Ray {
        self.sample_ray(p_film, u_lens, 0.0).expect("no lens system blocks it").ray
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
    fn orthographic_rays_are_parallel_from_the_screen_window() {
        let m = Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y);
        let cam = Camera::orthographic(m, (200, 100), 0.0, 1.0, None);
        // Default window ±2 × ±1 (aspect 2): the top-left corner is (−2, 1) in camera space,
        // whose axes are the world's here (looking down +z with +y up).
        let r = cam.generate_ray(Vec2::ZERO, Vec2::ZERO);
        assert!((r.d - Vec3::Z).length() < 1e-6 && (r.o - Vec3::new(-2.0, 1.0, -3.0)).length() < 1e-5, "{r:?}");
        let c = cam.generate_ray(Vec2::new(100.0, 50.0), Vec2::ZERO);
        assert!((c.o - Vec3::new(0.0, 0.0, -3.0)).length() < 1e-5 && (c.d - Vec3::Z).length() < 1e-6);
        // With a lens, rays through one film point meet on the focal plane at the pinhole ray.
        let lens = Camera::orthographic(m, (200, 100), 0.3, 2.0, Some([-1.0, 1.0, -1.0, 1.0]));
        let pin = Camera::orthographic(m, (200, 100), 0.0, 2.0, Some([-1.0, 1.0, -1.0, 1.0]));
        let p = Vec2::new(30.0, 70.0);
        let target = pin.generate_ray(p, Vec2::ZERO).at(2.0);
        for u in [Vec2::new(0.1, 0.9), Vec2::new(0.8, 0.3)] {
            let r = lens.generate_ray(p, u);
            assert!((r.at((target.z - r.o.z) / r.d.z) - target).length() < 1e-4);
        }
    }

    #[test]
    fn spherical_rays_cover_the_sphere_as_pbrt_v4_lays_it_out() {
        let m = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y);
        let dir = |p: Projection, x: f32, y: f32| {
            Camera::spherical(m, (64, 32), p).generate_ray(Vec2::new(x, y), Vec2::ZERO).d
        };
        // Equirectangular: the top row looks up (+y), the middle row along the horizon, φ = 2πu
        // from camera +x towards +z.
        assert!((dir(Projection::SphericalEquirect, 10.0, 0.0) - Vec3::Y).length() < 1e-5);
        assert!((dir(Projection::SphericalEquirect, 0.0, 16.0) - Vec3::X).length() < 1e-5);
        assert!((dir(Projection::SphericalEquirect, 16.0, 16.0) - Vec3::Z).length() < 1e-5);
        // Equal area: the centre looks along camera +y (the square's +z pole, y and z swapped),
        // the corners along −y.
        assert!((dir(Projection::SphericalEqualArea, 32.0, 16.0) - Vec3::Y).length() < 1e-5);
        assert!((dir(Projection::SphericalEqualArea, 0.0, 0.0) + Vec3::Y).length() < 1e-5);
    }

    #[test]
    fn equal_area_film_points_beyond_an_edge_wrap_across_it() {
        // A filter sample left of the film at height v looks where the mirrored point right of
        // the edge at 1 − v looks (pbrt-v4's wrap), not where the edge's nearest point does.
        let m = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y);
        let cam = Camera::spherical(m, (64, 64), Projection::SphericalEqualArea);
        let dir = |x: f32, y: f32| cam.generate_ray(Vec2::new(x, y), Vec2::ZERO).d;
        for (outside, inside) in [((-0.3, 20.0), (0.3, 44.0)), ((64.4, 9.0), (63.6, 55.0)), ((30.0, -0.5), (34.0, 0.5))]
        {
            let (a, b) = (dir(outside.0, outside.1), dir(inside.0, inside.1));
            assert!((a - b).length() < 1e-5, "{outside:?}: {a} vs {inside:?}: {b}");
            assert!((a - dir(outside.0.clamp(0.0, 64.0), outside.1.clamp(0.0, 64.0))).length() > 1e-3);
        }
    }

    /// A camera at the origin looking down +z that moves by `motion` over times 0 to 1, for
    /// each projection; the realistic one through the double-Gauss lens.
    fn cameras(motion: AnimatedTransform) -> Vec<Camera> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/compat/cameras-dgauss.50mm.dat");
        let elements = lens::parse_lens_file(&std::fs::read_to_string(path).unwrap()).unwrap();
        let lens = Arc::new(RealisticLens::new(elements, 0.014, 5.0, 0.035, 1.0).unwrap().0);
        let i = Mat4::IDENTITY;
        [
            Camera::perspective(i, (64, 48), 50.0, 0.2, 4.0, None),
            Camera::orthographic(i, (64, 48), 0.1, 3.0, None),
            Camera::spherical(i, (64, 32), Projection::SphericalEqualArea),
            Camera::spherical(i, (64, 32), Projection::SphericalEquirect),
            Camera::realistic(i, (64, 48), lens),
        ]
        .map(|c| c.with_motion(Some(motion)))
        .into()
    }

    #[test]
    fn a_translating_camera_shifts_every_ray_origin_by_the_distance_moved_at_the_rays_time() {
        // From the origin to (2, −1, 0.5) over times 0 to 1: at time t every projection's ray
        // starts t · (2, −1, 0.5) from where the same film and lens sample start it at time 0,
        // in the same direction, and carries the time.
        let step = Vec3::new(2.0, -1.0, 0.5);
        let motion = AnimatedTransform::new(Mat4::IDENTITY, 0.0, Mat4::from_translation(step), 1.0);
        for cam in cameras(motion) {
            assert!(cam.transform.moves());
            let mut compared = 0;
            for (p, u) in [((10.0, 7.0), (0.3, 0.6)), ((32.0, 24.0), (0.5, 0.5)), ((50.0, 40.0), (0.8, 0.1))] {
                let (p, u) = (Vec2::from(p), Vec2::from(u));
                let Some(r0) = cam.sample_ray(p, u, 0.0) else { continue };
                for t in [0.25, 0.5, 1.0] {
                    let r = cam.sample_ray(p, u, t).expect("the lens passes it at every time").ray;
                    assert_eq!(r.time, t);
                    assert!((r.o - (r0.ray.o + t * step)).length() < 1e-5, "{:?} at {t}: {r:?}", cam.projection);
                    assert!((r.d - r0.ray.d).length() < 1e-6, "{:?} at {t}: {r:?}", cam.projection);
                    compared += 1;
                }
            }
            assert!(compared >= 3, "{:?}", cam.projection);
        }
    }

    #[test]
    fn a_turning_camera_turns_every_ray_about_its_position_by_the_angle_turned_at_the_rays_time() {
        // A camera at (1, 2, 3) turning 60° about +y over times 0 to 2: at time t its rays are
        // those at time 0 turned by 30° t about the vertical through its position.
        let at = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0));
        let end = at * Mat4::from_rotation_y(60f32.to_radians());
        let motion = AnimatedTransform::new(at, 0.0, end, 2.0);
        for cam in cameras(motion) {
            let mut compared = 0;
            for (p, u) in [((10.0, 7.0), (0.3, 0.6)), ((32.0, 24.0), (0.5, 0.5)), ((50.0, 40.0), (0.8, 0.1))] {
                let (p, u) = (Vec2::from(p), Vec2::from(u));
                let Some(r0) = cam.sample_ray(p, u, 0.0).map(|c| c.ray) else { continue };
                for t in [0.5f32, 1.0, 2.0] {
                    let turn = glam::Quat::from_rotation_y((30.0 * t).to_radians());
                    let r = cam.sample_ray(p, u, t).expect("the lens passes it at every time").ray;
                    let o = Vec3::new(1.0, 2.0, 3.0) + turn * (r0.o - Vec3::new(1.0, 2.0, 3.0));
                    assert!((r.o - o).length() < 1e-5, "{:?} at {t}: {} vs {o}", cam.projection, r.o);
                    assert!(
                        (r.d - turn * r0.d).length() < 1e-5,
                        "{:?} at {t}: {} vs {}",
                        cam.projection,
                        r.d,
                        turn * r0.d
                    );
                    compared += 1;
                }
            }
            assert!(compared >= 3, "{:?}", cam.projection);
        }
        // Without motion the time changes nothing.
        let fixed = Camera::perspective(at, (64, 48), 50.0, 0.2, 4.0, None);
        assert!(!fixed.transform.moves());
        let (a, b) = (
            fixed.sample_ray(Vec2::new(5.0, 9.0), Vec2::splat(0.4), 0.0).unwrap().ray,
            fixed.sample_ray(Vec2::new(5.0, 9.0), Vec2::splat(0.4), 0.7).unwrap().ray,
        );
        assert_eq!((a.o, a.d), (b.o, b.d));
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

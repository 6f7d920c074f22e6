//! The footprint of a pixel at a shading point, ∂p/∂x and ∂p/∂y, estimated from the camera
//! alone as pbrt-v4's `CameraBase::Approximate_dp_dxy` does (§10.1.1): the smallest change of
//! camera ray direction (and origin) per pixel step over the film is found once; at a point p
//! with normal n, rays from the camera origin along the direction to p offset by that change
//! are intersected with p's tangent plane. The offsets are scaled by max(1/8, 1/√spp), since
//! many samples per pixel already average a pixel's area. The differentials are camera-space
//! quantities; a moving camera carries them to the shading point's time by its transform then
//! (pbrt-v4 `CameraFromRender(p, time)`).
//!
//! A camera ray's first hit uses the ray's own differentials instead, as pbrt-v4 does
//! (`CameraBase::GenerateRayDifferential`, `SurfaceInteraction::ComputeDifferentials`): the rays
//! through the film position's neighbours met with the tangent plane. Where the camera-wide
//! estimate and the ray's own differentials disagree most — a spherical camera's poles, where
//! a pixel's φ step shrinks to nothing and the estimate's fixed frame points across it — only
//! the latter follows the pixel.

use crate::camera::{Camera, CameraTransform};
use crate::geometry::Ray;
use glam::{Vec2, Vec3};

/// Film step of the finite differences that give a camera ray's change per pixel [pixels].
const FILM_STEP: f32 = 0.05;

/// Film points sampled, along the diagonal, when searching for the smallest differentials.
const SEARCH_POINTS: usize = 512;

/// What a shading point needs to know of the camera to estimate its pixel footprint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureFootprint {
    /// Camera space → world space at each time.
    transform: CameraTransform,
    /// Smallest change of a camera ray's origin per pixel along x, y [camera space].
    min_pos: [Vec3; 2],
    /// Smallest change of a camera ray's unit direction per pixel along x, y, in the frame of
    /// the ray it was measured on (z along the ray).
    min_dir: [Vec3; 2],
    /// max(1/8, 1/√spp).
    spp_scale: f32,
}

/// The reflection through the plane normal to `u`: x − 2 (u·x)/(u·u) u.
fn reflect(u: Vec3, x: Vec3) -> Vec3 {
    x - (2.0 * u.dot(x) / u.dot(u)) * u
}

/// The rotation taking unit vector `from` to +z, as the product of the reflections taking
/// `from` to an axis r and r to +z (r chosen away from `from`, so neither reflection is
/// degenerate; pbrt-v4's `RotateFromTo`): the two reflection normals.
fn down_z_reflections(from: Vec3) -> (Vec3, Vec3) {
    let r = if from.x.abs() < 0.72 { Vec3::X } else { Vec3::Y };
    (r - from, r - Vec3::Z)
}

/// The inverse of that rotation applied to `x` (each reflection is its own inverse, so the
/// inverse applies them in the opposite order).
fn from_down_z((u, v): (Vec3, Vec3), x: Vec3) -> Vec3 {
    reflect(u, reflect(v, x))
}

/// Components of `v` in the orthonormal frame whose z axis is the unit vector `z` (Duff et al.
/// 2017's branchless basis, as pbrt-v4's `Frame::FromZ`).
fn to_local(z: Vec3, v: Vec3) -> Vec3 {
    let (x, y) = z.any_orthonormal_pair();
    Vec3::new(v.dot(x), v.dot(y), v.dot(z))
}

/// A camera ray's neighbours one pixel step away along x and y (pbrt-v4's `RayDifferential`),
/// scaled by max(1/8, 1/√spp) as the camera-wide estimate is: origins and directions (not unit)
/// [world space].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayDifferentials {
    /// The neighbour along x: origin, direction.
    x: (Vec3, Vec3),
    /// The neighbour along y.
    y: (Vec3, Vec3),
}

impl RayDifferentials {
    /// ∂p/∂x and ∂p/∂y at `p` on the tangent plane of normal `n`: where the neighbouring rays
    /// meet it; `None` when one runs parallel to it.
    fn dp_dxy(&self, p: Vec3, n: Vec3) -> Option<(Vec3, Vec3)> {
        let on_plane = |(o, d): (Vec3, Vec3)| {
            let v = o + d * (n.dot(p - o) / n.dot(d)) - p;
            v.is_finite().then_some(v)
        };
        Some((on_plane(self.x)?, on_plane(self.y)?))
    }
}

/// What a shading point's pixel footprint is estimated from.
#[derive(Clone, Copy, Debug)]
pub enum Footprint<'a> {
    /// The camera-wide estimate: every vertex after a path's first.
    Camera(&'a TextureFootprint),
    /// A camera ray's own differentials, at its first hit (the estimate where they fail).
    CameraRay(&'a TextureFootprint, &'a RayDifferentials),
}

impl<'a> Footprint<'a> {
    /// The footprint at a path's vertex: the camera ray's differentials at the `first` vertex,
    /// when there are any; `None` without a camera estimate (textures at their finest detail).
    pub fn of_vertex(
        camera: Option<&'a TextureFootprint>,
        camera_ray: Option<&'a RayDifferentials>,
        first: bool,
    ) -> Option<Self> {
        let camera = camera?;
        Some(match camera_ray.filter(|_| first) {
            Some(r) => Footprint::CameraRay(camera, r),
            None => Footprint::Camera(camera),
        })
    }

    /// ∂p/∂x and ∂p/∂y at `p` on a surface with unit normal `n` [world space], at `time`.
    pub fn dp_dxy(&self, p: Vec3, n: Vec3, time: f32) -> (Vec3, Vec3) {
        match self {
            Footprint::Camera(c) => c.dp_dxy(p, n, time),
            Footprint::CameraRay(c, r) => r.dp_dxy(p, n).unwrap_or_else(|| c.dp_dxy(p, n, time)),
        }
    }
}

impl TextureFootprint {
    /// The differentials of `camera`'s ray `ray` through `p_film` with lens sample `u_lens`:
    /// finite differences over [`FILM_STEP`] pixel (the other way where a lens blocks the first),
    /// as pbrt-v4's `CameraBase::GenerateRayDifferential`; `None` when a lens blocks both.
    pub fn camera_ray_differentials(
        &self,
        camera: &Camera,
        ray: &Ray,
        p_film: Vec2,
        u_lens: Vec2,
    ) -> Option<RayDifferentials> {
        let neighbour = |axis: Vec2| {
            [FILM_STEP, -FILM_STEP].into_iter().find_map(|step| {
                let shifted = camera.sample_ray(p_film + axis * step, u_lens, ray.time)?.ray;
                let s = self.spp_scale / step;
                Some((ray.o + (shifted.o - ray.o) * s, ray.d + (shifted.d - ray.d) * s))
            })
        };
        Some(RayDifferentials { x: neighbour(Vec2::X)?, y: neighbour(Vec2::Y)? })
    }

    /// The footprint estimator for `camera` rendering `spp` samples per pixel.
    pub fn new(camera: &Camera, spp: u64) -> Self {
        // The rays are compared in camera space; a moving camera is measured at one time of its
        // motion (pbrt-v4 measures at the middle of the shutter), a fixed one at any.
        let time = camera.transform.mid_time();
        let camera_from_world = camera.transform.camera_from_world(time);
        let (w, h) = (camera.resolution.0 as f32, camera.resolution.1 as f32);
        let lens = Vec2::splat(0.5);
        let mut min_pos = [Vec3::splat(f32::INFINITY); 2];
        let mut min_dir = [Vec3::splat(f32::INFINITY); 2];
        for i in 0..SEARCH_POINTS {
            let film = Vec2::new(w, h) * (i as f32 / (SEARCH_POINTS - 1) as f32);
            // A realistic camera's lens blocks some rays; those points are skipped.
            let Some(ray) = camera.sample_ray(film, lens, time).map(|c| c.ray) else { continue };
            let d = ray.d.normalize();
            for (k, step) in [Vec2::new(FILM_STEP, 0.0), Vec2::new(0.0, FILM_STEP)].into_iter().enumerate() {
                let Some(shifted) = camera.sample_ray(film + step, lens, time).map(|c| c.ray) else { continue };
                // Per pixel: the finite difference over FILM_STEP, scaled up.
                let o_diff = (shifted.o - ray.o) / FILM_STEP;
                let d_diff = (d + (shifted.d.normalize() - d) / FILM_STEP).normalize();
                let dpos = camera_from_world.transform_vector3(o_diff);
                if dpos.length() < min_pos[k].length() {
                    min_pos[k] = dpos;
                }
                let ddir = to_local(d, d_diff).normalize() - to_local(d, d);
                if ddir.length() < min_dir[k].length() {
                    min_dir[k] = ddir;
                }
            }
        }
        let spp_scale = (1.0 / (spp.max(1) as f32).sqrt()).max(0.125);
        Self { transform: camera.transform, min_pos, min_dir, spp_scale }
    }

    /// ∂p/∂x and ∂p/∂y at `p` on a surface with unit normal `n` [world space], seen by a camera
    /// ray at `time`; zero where the estimate fails (a plane seen edge-on).
    pub fn dp_dxy(&self, p: Vec3, n: Vec3, time: f32) -> (Vec3, Vec3) {
        // The differential rays are given in a frame where p lies straight ahead (+z) of the
        // camera; carried back to world space they are intersected with p's tangent plane.
        let world_from_camera = self.transform.world_from_camera(time);
        let to_p = self.transform.camera_from_world(time).transform_point3(p).normalize_or_zero();
        let frame = down_z_reflections(to_p);
        let step = |k: usize| {
            let o = world_from_camera.transform_point3(from_down_z(frame, self.min_pos[k]));
            let d = world_from_camera.transform_vector3(to_p + from_down_z(frame, self.min_dir[k]));
            let t = n.dot(p - o) / n.dot(d);
            let v = self.spp_scale * (o + t * d - p);
            if v.is_finite() {
                v
            } else {
                Vec3::ZERO
            }
        };
        (step(0), step(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat3, Mat4};

    fn camera(res: (u32, u32), fov: f32) -> Camera {
        let m = Camera::look_at(Vec3::new(0.0, -9.0, 2.2), Vec3::new(0.0, 0.0, 2.2), Vec3::Z);
        Camera::perspective(m, res, fov, 0.0, 1e6, None)
    }

    #[test]
    fn the_down_z_frame_is_a_rotation_taking_the_direction_to_z() {
        for from in [Vec3::X, Vec3::Y, Vec3::new(0.3, -0.5, 0.81).normalize(), Vec3::new(-0.8, 0.1, 0.59).normalize()] {
            let f = down_z_reflections(from);
            let rotate = |x: Vec3| reflect(f.1, reflect(f.0, x));
            assert!((rotate(from) - Vec3::Z).length() < 1e-6, "{from} → {}", rotate(from));
            // Orthonormal, right-handed, and undone by `from_down_z`.
            let (a, b, c) = (rotate(Vec3::X), rotate(Vec3::Y), rotate(Vec3::Z));
            assert!((Mat3::from_cols(a, b, c).determinant() - 1.0).abs() < 1e-5);
            assert!((a.dot(b)).abs() < 1e-6 && a.length() - 1.0 < 1e-6);
            let x = Vec3::new(0.2, -1.3, 0.7);
            assert!((from_down_z(f, rotate(x)) - x).length() < 1e-5);
        }
    }

    #[test]
    fn a_fronto_parallel_plane_gets_one_pixel_per_step() {
        // 200 pixels over a 28° field of view, t = tan 14°: the film point (s_x, s_y, 1) moves
        // by 2t/200 per pixel, and the unit direction f/|f| by that times √(1 − d_x²)/|f|,
        // least at a corner (s_x = s_y = t): √(1 + t²)/(1 + 2t²).
        let cam = camera((200, 200), 28.0);
        let f = TextureFootprint::new(&cam, 1);
        // The wall y = 0 is 9 away, facing the camera.
        let (dx, dy) = f.dp_dxy(Vec3::new(0.0, 0.0, 2.2), -Vec3::Y, 0.0);
        let t = 14f32.to_radians().tan();
        let expect = 9.0 * 2.0 * t / 200.0 * (1.0 + t * t).sqrt() / (1.0 + 2.0 * t * t);
        assert!((dx.length() / expect - 1.0).abs() < 0.02, "{} vs {expect}", dx.length());
        assert!((dy.length() / expect - 1.0).abs() < 0.02, "{} vs {expect}", dy.length());
        // Both lie in the wall, nearly perpendicular (at the corner where they were measured the
        // x and y changes of direction meet at cos = −t²/(1 + t²) ≈ −0.06).
        assert!(dx.y.abs() < 1e-6 && dy.y.abs() < 1e-6);
        assert!(dx.normalize().dot(dy.normalize()).abs() < 0.08);
        // Many samples per pixel shrink the footprint, by 1/√spp down to 1/8.
        let f16 = TextureFootprint::new(&cam, 16);
        assert!((f16.dp_dxy(Vec3::new(0.0, 0.0, 2.2), -Vec3::Y, 0.0).0.length() / dx.length() - 0.25).abs() < 1e-4);
        let f1024 = TextureFootprint::new(&cam, 1024);
        assert!((f1024.dp_dxy(Vec3::new(0.0, 0.0, 2.2), -Vec3::Y, 0.0).0.length() / dx.length() - 0.125).abs() < 1e-4);
    }

    #[test]
    fn a_camera_rays_differentials_give_its_own_pixel_step() {
        // The ray through the film's centre meets the wall y = 0, 9 away, head-on: one pixel
        // moves the film point (s_x, s_y, 1) by 2t/200 (t = tan 14°), so the hit by 9 · 2t/200,
        // along the camera's x and y; the camera-wide estimate is the corner's, shorter by
        // √(1 + t²)/(1 + 2t²).
        let cam = camera((200, 200), 28.0);
        let f = TextureFootprint::new(&cam, 1);
        let (p_film, u_lens) = (Vec2::new(100.0, 100.0), Vec2::splat(0.5));
        let ray = cam.sample_ray(p_film, u_lens, 0.0).unwrap().ray;
        let rd = f.camera_ray_differentials(&cam, &ray, p_film, u_lens).unwrap();
        let p = Vec3::new(0.0, 0.0, 2.2);
        let (dx, dy) = Footprint::CameraRay(&f, &rd).dp_dxy(p, -Vec3::Y, 0.0);
        let t = 14f32.to_radians().tan();
        let step = 9.0 * 2.0 * t / 200.0;
        assert!((dx.length() / step - 1.0).abs() < 1e-3 && (dy.length() / step - 1.0).abs() < 1e-3, "{dx} {dy}");
        assert!(dx.normalize().cross(Vec3::X).length() < 1e-3 && dy.normalize().cross(Vec3::Z).length() < 1e-3);
        let (ax, _) = Footprint::Camera(&f).dp_dxy(p, -Vec3::Y, 0.0);
        let corner = (1.0 + t * t).sqrt() / (1.0 + 2.0 * t * t);
        assert!((ax.length() / (step * corner) - 1.0).abs() < 0.02, "{ax}");
        // 1024 samples per pixel: an eighth of that, as the estimate.
        let f1024 = TextureFootprint::new(&cam, 1024);
        let rd = f1024.camera_ray_differentials(&cam, &ray, p_film, u_lens).unwrap();
        let (dx, _) = Footprint::CameraRay(&f1024, &rd).dp_dxy(p, -Vec3::Y, 0.0);
        assert!((dx.length() / step - 0.125).abs() < 1e-3, "{dx}");
    }

    #[test]
    fn at_a_spherical_cameras_pole_the_differentials_follow_the_pixel() {
        // An equirectangular camera 1.1 above the floor y = 0, looking along +z; the pixel at
        // φ ≈ 89° (column 47.5 of 192), θ = π · 94.5/96 sees the floor at r = 1.1 tan(π − θ)
        // from the point below. One row turns θ by π/96, moving the hit by
        // 1.1 (π/96)/cos²(π − θ) radially (along z here); one column turns φ by 2π/192, moving it
        // by r · 2π/192 across (along x). The camera-wide estimate has one frame for the whole
        // pole and cannot follow φ.
        let m = Camera::look_at(Vec3::new(0.0, 1.1, 0.0), Vec3::new(0.0, 1.1, 1.0), Vec3::Y);
        let cam = Camera::spherical(m, (192, 96), crate::camera::Projection::SphericalEquirect);
        let f = TextureFootprint::new(&cam, 1);
        let (p_film, u_lens) = (Vec2::new(47.5, 94.5), Vec2::splat(0.5));
        let ray = cam.sample_ray(p_film, u_lens, 0.0).unwrap().ray;
        let p = ray.o + ray.d * (-ray.o.y / ray.d.y);
        let rd = f.camera_ray_differentials(&cam, &ray, p_film, u_lens).unwrap();
        let (dx, dy) = Footprint::CameraRay(&f, &rd).dp_dxy(p, Vec3::Y, 0.0);
        let pole = std::f32::consts::PI * 1.5 / 96.0;
        let radial = 1.1 * (std::f32::consts::PI / 96.0) / (pole.cos() * pole.cos());
        let across = 1.1 * pole.tan() * std::f32::consts::TAU / 192.0;
        assert!((dy.length() / radial - 1.0).abs() < 0.01, "{dy} vs {radial}");
        assert!((dx.length() / across - 1.0).abs() < 0.01, "{dx} vs {across}");
        assert!(dy.x.abs() < 0.03 * dy.length() && dx.z.abs() < 0.03 * dx.length(), "{dx} {dy}");
    }

    #[test]
    fn a_moving_camera_sees_the_footprint_of_where_it_is_at_the_shading_points_time() {
        // The camera dollies from 9 to 4.5 in front of the wall y = 0 over times 0 to 1 and
        // turns 10° about its view axis: at time 1 the wall is half as far, so the footprint
        // is half as long, and it turns with the camera.
        let start = Camera::look_at(Vec3::new(0.0, -9.0, 2.2), Vec3::new(0.0, 0.0, 2.2), Vec3::Z);
        let turn = Mat4::from_rotation_z(10f32.to_radians());
        let end = Mat4::from_translation(Vec3::new(0.0, 4.5, 0.0)) * start * turn;
        let motion = crate::geometry::AnimatedTransform::new(start, 0.0, end, 1.0);
        let moving = TextureFootprint::new(&camera((200, 200), 28.0).with_motion(Some(motion)), 1);
        let fixed = TextureFootprint::new(&camera((200, 200), 28.0), 1);
        let p = Vec3::new(0.0, 0.0, 2.2);
        let (fx, _) = fixed.dp_dxy(p, -Vec3::Y, 0.0);
        let (x0, _) = moving.dp_dxy(p, -Vec3::Y, 0.0);
        let (x1, _) = moving.dp_dxy(p, -Vec3::Y, 1.0);
        assert!((x0.length() / fx.length() - 1.0).abs() < 0.01, "{x0} vs {fx}");
        assert!((x1.length() / fx.length() - 0.5).abs() < 0.01, "{} vs {}", x1.length(), fx.length());
        // Both lie in the wall; the one at time 1 is turned 10° about the view axis.
        assert!(x0.y.abs() < 1e-5 && x1.y.abs() < 1e-5, "{x0} {x1}");
        let cos = x1.normalize().dot(x0.normalize());
        assert!((cos.acos().to_degrees() - 10.0).abs() < 0.5, "turned {}°", cos.acos().to_degrees());
    }

    #[test]
    fn footprints_grow_with_distance_and_obliquity() {
        let f = TextureFootprint::new(&camera((100, 100), 40.0), 1);
        let near = f.dp_dxy(Vec3::new(0.0, -4.0, 2.2), -Vec3::Y, 0.0).0.length();
        let far = f.dp_dxy(Vec3::new(0.0, 5.0, 2.2), -Vec3::Y, 0.0).0.length();
        assert!((far / near - 14.0 / 5.0).abs() < 1e-3, "{far} / {near}");
        // The floor seen at a grazing angle: the footprint along the view is stretched.
        let (a, b) = f.dp_dxy(Vec3::new(0.0, 5.0, 0.0), Vec3::Z, 0.0);
        assert!(a.length().max(b.length()) > 3.0 * far, "{a} {b}");
        // Edge-on: no estimate.
        let (a, b) = f.dp_dxy(Vec3::new(0.0, 5.0, 2.2), Vec3::X, 0.0);
        assert!(a.is_finite() && b.is_finite());
    }
}

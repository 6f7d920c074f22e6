//! The perspective camera as a sensor that light paths reach: its importance W_e, the densities
//! with which it emits rays, and sampling a point on its lens toward a point in the scene
//! (Veach 1997, §10.3.4; PBR 3rd ed. §16.1.1; pbrt-v4 `PerspectiveCamera::We`, `PDF_We`,
//! `SampleWi`).
//!
//! W_e is normalised so that it integrates to one over the lens and the directions through the
//! whole image: W_e(ω) = 1 / (A · A_lens · cos⁴θ) for rays that pass through the image, with A
//! the area of the image on the plane z = 1 in camera space, A_lens = π r² the lens's area (1 for
//! a pinhole) and θ the angle to the optical axis (cos³θ turns the image plane's area into
//! solid angle, one more cos the lens's area into projected area). A film position then
//! measures (pixels of the image) × W_e × the filter's normalised weight there.

use super::{Camera, Projection};
use crate::math::PI;
use crate::sampling::warp::sample_uniform_disk_concentric;
use glam::{Vec2, Vec3};

/// A point on the lens toward a reference point, and what the camera sees of it.
#[derive(Clone, Copy, Debug)]
pub struct CameraWiSample {
    /// Importance W_e of the ray from the lens point toward the reference point.
    pub we: f32,
    /// Unit direction from the reference point to the lens point.
    pub wi: Vec3,
    /// Solid-angle density at the reference point of `wi` [1/sr] (the lens's area density
    /// turned into solid angle; for a pinhole, distance² / cos θ).
    pub pdf: f32,
    /// The lens point [world space].
    pub p_lens: Vec3,
    /// The camera's optical axis [world space, unit]: the lens's normal.
    pub n_lens: Vec3,
    /// Where on the film the ray lands [pixels of the full image].
    pub p_raster: Vec2,
}

impl Camera {
    /// True when the camera has an importance function prism evaluates: a perspective camera,
    /// pinhole or thin lens (not the realistic camera's lens system).
    pub fn has_importance(&self) -> bool {
        self.projection == Projection::Perspective && self.lens.is_none()
    }

    /// Area of the image on the plane z = 1 in camera space.
    fn image_area(&self) -> f32 {
        let [x0, x1, y0, y1] = self.screen;
        ((x1 - x0) * (y1 - y0)).abs()
    }

    /// Area of the lens (1 for a pinhole, whose W_e is per unit of that nominal area).
    fn lens_area(&self) -> f32 {
        if self.lens_radius > 0.0 {
            PI * self.lens_radius * self.lens_radius
        } else {
            1.0
        }
    }

    /// The camera's optical axis in world space at `time`.
    pub fn axis(&self, time: f32) -> Vec3 {
        self.transform.world_from_camera(time).transform_vector3(Vec3::Z).normalize()
    }

    /// Where a ray leaving the lens at `p` [world] along the unit `d` lands on the film, and
    /// cos θ to the axis: `None` when it points away or lands outside the image.
    fn raster(&self, p: Vec3, d: Vec3, time: f32) -> Option<(Vec2, f32)> {
        let m = self.transform.camera_from_world(time);
        let d = m.transform_vector3(d).normalize();
        if d.z <= 0.0 {
            return None;
        }
        // The point the ray passes through on the plane in focus (for a pinhole, z = 1), seen
        // from the lens centre.
        let focus = if self.lens_radius > 0.0 {
            let o = m.transform_point3(p);
            let q = o + d * ((self.focal_distance - o.z) / d.z);
            q / q.z
        } else {
            d / d.z
        };
        let [x0, x1, y0, y1] = self.screen;
        let (w, h) = (self.resolution.0 as f32, self.resolution.1 as f32);
        let px = (focus.x - x0) / (x1 - x0) * w;
        let py = (y1 - focus.y) / (y1 - y0) * h;
        if !(px >= 0.0 && px < w && py >= 0.0 && py < h) {
            return None;
        }
        Some((Vec2::new(px, py), d.z))
    }

    /// Importance W_e of the ray leaving the lens at `p` along the unit `d` at `time`, and
    /// where it lands on the film (pbrt-v4 `We`); `None` outside the image.
    pub fn we(&self, p: Vec3, d: Vec3, time: f32) -> Option<(f32, Vec2)> {
        let (p_raster, cos) = self.raster(p, d, time)?;
        let cos2 = cos * cos;
        Some((1.0 / (self.image_area() * self.lens_area() * cos2 * cos2), p_raster))
    }

    /// Densities with which camera rays leave the lens at `p` along the unit `d`: area density
    /// on the lens [1/m²] and solid-angle density [1/sr] (pbrt-v4 `PDF_We`); zeros outside the
    /// image.
    pub fn pdf_we(&self, p: Vec3, d: Vec3, time: f32) -> (f32, f32) {
        match self.raster(p, d, time) {
            None => (0.0, 0.0),
            Some((_, cos)) => (1.0 / self.lens_area(), 1.0 / (self.image_area() * cos * cos * cos)),
        }
    }

    /// Samples a point on the lens with `u` in [0,1)² as seen from `p_ref` [world] at `time`
    /// (pbrt-v4 `SampleWi`); `None` when the ray from there toward `p_ref` misses the image.
    pub fn sample_wi(&self, p_ref: Vec3, u: Vec2, time: f32) -> Option<CameraWiSample> {
        let world = self.transform.world_from_camera(time);
        let lens = self.lens_radius * sample_uniform_disk_concentric(u);
        let p_lens = world.transform_point3(Vec3::new(lens.x, lens.y, 0.0));
        let n_lens = self.axis(time);
        let to_lens = p_lens - p_ref;
        let dist2 = to_lens.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let wi = to_lens / dist2.sqrt();
        let (we, p_raster) = self.we(p_lens, -wi, time)?;
        let pdf = dist2 / (n_lens.dot(wi).abs() * self.lens_area());
        pdf.is_finite().then_some(CameraWiSample { we, wi, pdf, p_lens, n_lens, p_raster })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    #[test]
    fn a_camera_ray_lands_where_it_was_made_and_importance_integrates_to_one() {
        let m = Camera::look_at(Vec3::new(1.0, 2.0, -3.0), Vec3::new(0.5, 1.5, 4.0), Vec3::Y);
        for cam in [
            Camera::perspective(m, (40, 30), 50.0, 0.0, 1.0, None),
            Camera::perspective(m, (40, 30), 50.0, 0.3, 6.0, None),
        ] {
            for (p, u) in [((3.5, 7.25), (0.2, 0.7)), ((20.0, 15.0), (0.5, 0.5)), ((39.0, 1.0), (0.9, 0.1))] {
                let r = cam.sample_ray(Vec2::from(p), Vec2::from(u), 0.0).unwrap().ray;
                let (_, at) = cam.we(r.o, r.d, 0.0).expect("inside the image");
                assert!((at - Vec2::from(p)).length() < 1e-3, "{at} vs {p:?}");
                // The lens point toward a point on the ray is the ray's origin, landing there too.
                let s = cam.sample_wi(r.at(5.0), Vec2::from(u), 0.0).unwrap();
                assert!((s.p_lens - r.o).length() < 1e-4 && (s.p_raster - Vec2::from(p)).length() < 1e-2);
            }
        }
        // ∫ W_e cos θ dω over the image's directions = 1 for a pinhole (A_lens = 1): summed
        // over a grid of film positions, dω = cos³θ dA on the plane z = 1.
        let (n, pin) = (200, Camera::perspective(Mat4::IDENTITY, (40, 30), 50.0, 0.0, 1.0, None));
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let p = Vec2::new((i as f32 + 0.5) / n as f32 * 40.0, (j as f32 + 0.5) / n as f32 * 30.0);
                let d = pin.sample_ray(p, Vec2::ZERO, 0.0).unwrap().ray.d;
                let (we, _) = pin.we(Vec3::ZERO, d, 0.0).unwrap();
                let da = pin.image_area() / (n * n) as f32;
                sum += (we * d.z * d.z.powi(3) * da) as f64;
            }
        }
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
        // Behind the camera or outside the image: no importance.
        let cam = Camera::perspective(Mat4::IDENTITY, (40, 30), 50.0, 0.0, 1.0, None);
        assert!(cam.we(Vec3::ZERO, -Vec3::Z, 0.0).is_none());
        assert!(cam.we(Vec3::ZERO, Vec3::new(5.0, 0.0, 1.0).normalize(), 0.0).is_none());
    }
}

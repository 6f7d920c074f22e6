//! A lens system of spherical interfaces and an aperture stop, traced ray by ray (pbrt-v4
//! §5.3.2–5.3.3): refraction by Snell's law at each interface, rejection outside each clear
//! aperture, and focusing by the thick-lens approximation (the cardinal points found by tracing
//! rays parallel to the axis from either side).
//!
//! Camera space here is pbrt-v4's: the film lies on z = 0 and the lens in front of it toward +z
//! (the scene). Interfaces are stored scene side first; interface i lies at
//! z = Σ_{j ≥ i} thickness_j. Lengths are in metres; the tracing runs in f64 so the
//! intersections with shallow curvatures do not lose their digits.

use super::lens::LensInterface;
use glam::DVec3;

/// Why a lens system cannot be focused.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum LensError {
    /// A ray parallel to the axis does not pass (aperture stop or element apertures too small).
    #[error("a ray parallel to the lens axis does not pass the lens system (is the aperture stop too small?)")]
    NoParallelRay,
    /// The focus distance is within the lens system's reach of the film.
    #[error("focus distance {0} m is too short for this lens system")]
    FocusTooClose(f32),
}

/// A ray in camera space [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensRay {
    /// Origin.
    pub o: DVec3,
    /// Direction (not necessarily unit length).
    pub d: DVec3,
}

impl LensRay {
    /// The point at parameter `t`.
    pub fn at(&self, t: f64) -> DVec3 {
        self.o + t * self.d
    }

    /// The ray with z flipped: camera space ↔ the lens space the interfaces are laid out in.
    fn flip_z(self) -> Self {
        let f = DVec3::new(1.0, 1.0, -1.0);
        Self { o: self.o * f, d: self.d * f }
    }
}

/// The index of refraction of a medium as written (0, the stop's, is air).
fn medium(eta: f32) -> f64 {
    if eta == 0.0 {
        1.0
    } else {
        f64::from(eta)
    }
}

/// Snell refraction of `wi` (unit, pointing away from the interface on the side of `n`) with
/// relative index `eta` = η_t/η_i; `None` on total internal reflection.
fn refract(wi: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = n.dot(wi);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wi / eta + (cos_i / eta - cos_t) * n)
}

/// The hit of `ray` with the sphere of signed `radius` centred on the axis at `z_center`
/// [lens space]: the parameter and the unit normal facing the ray's origin. Of the two roots
/// the one on the lens's side of the sphere is taken: the nearer when the ray runs toward the
/// centre side (d.z > 0 and a convex radius, or d.z < 0 and a concave one).
fn intersect_spherical(radius: f64, z_center: f64, ray: &LensRay) -> Option<(f64, DVec3)> {
    let o = ray.o - DVec3::new(0.0, 0.0, z_center);
    let (a, b, c) = (ray.d.length_squared(), 2.0 * o.dot(ray.d), o.length_squared() - radius * radius);
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    // The cancellation-free pair of roots (Numerical Recipes §5.6).
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (mut t0, mut t1) = (q / a, c / q);
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let t = if (ray.d.z > 0.0) ^ (radius < 0.0) { t0 } else { t1 };
    // A NaN root (a degenerate ray) fails too.
    if t.is_nan() || t < 0.0 {
        return None;
    }
    let n = (o + t * ray.d).normalize();
    Some((t, if n.dot(ray.d) > 0.0 { -n } else { n }))
}

/// The lens: its interfaces, scene side first.
#[derive(Clone, Debug, PartialEq)]
pub struct LensSystem {
    /// The interfaces, scene side first; the last one's thickness is its distance to the film.
    pub elements: Vec<LensInterface>,
}

impl LensSystem {
    /// The system of `elements`.
    pub fn new(elements: Vec<LensInterface>) -> Self {
        Self { elements }
    }

    /// Distance from the film to the rear interface [m].
    pub fn rear_z(&self) -> f64 {
        self.elements.last().map_or(0.0, |e| f64::from(e.thickness))
    }

    /// Distance from the film to the front interface [m].
    pub fn front_z(&self) -> f64 {
        self.elements.iter().map(|e| f64::from(e.thickness)).sum()
    }

    /// Clear-aperture radius of the rear interface [m].
    pub fn rear_radius(&self) -> f64 {
        self.elements.last().map_or(0.0, |e| f64::from(e.aperture_radius))
    }

    /// Where `ray` [lens space] meets interface `e` at axial position `z`, with the normal
    /// there (`None` at the stop's plane), if it meets it within the clear aperture.
    fn hit(e: &LensInterface, z: f64, ray: &LensRay) -> Option<(DVec3, Option<DVec3>)> {
        let (t, n) = if e.is_stop() {
            let t = (z - ray.o.z) / ray.d.z;
            (t, None)
        } else {
            let r = f64::from(e.curvature_radius);
            let (t, n) = intersect_spherical(r, z + r, ray)?;
            (t, Some(n))
        };
        if t.is_nan() || t < 0.0 {
            return None;
        }
        let p = ray.at(t);
        let a = f64::from(e.aperture_radius);
        (p.x * p.x + p.y * p.y <= a * a).then_some((p, n))
    }

    /// The ray leaving the front interface for `ray` starting at the film side [camera space],
    /// or `None` when an aperture blocks it or it is totally reflected.
    pub fn trace_from_film(&self, ray: LensRay) -> Option<LensRay> {
        let mut r = ray.flip_z();
        let mut z = 0.0;
        for (i, e) in self.elements.iter().enumerate().rev() {
            z -= f64::from(e.thickness);
            let (p, n) = Self::hit(e, z, &r)?;
            r.o = p;
            if let Some(n) = n {
                let eta_t = if i > 0 { medium(self.elements[i - 1].eta) } else { 1.0 };
                r.d = refract(-r.d.normalize(), n, eta_t / medium(e.eta))?;
            }
        }
        Some(r.flip_z())
    }

    /// The ray leaving the rear interface toward the film for `ray` coming from the scene
    /// [camera space], or `None` when it is blocked.
    pub fn trace_from_scene(&self, ray: LensRay) -> Option<LensRay> {
        let mut r = ray.flip_z();
        let mut z = -self.front_z();
        for (i, e) in self.elements.iter().enumerate() {
            let (p, n) = Self::hit(e, z, &r)?;
            r.o = p;
            if let Some(n) = n {
                let eta_i = if i > 0 { medium(self.elements[i - 1].eta) } else { 1.0 };
                r.d = refract(-r.d.normalize(), n, medium(e.eta) / eta_i)?;
            }
            z += f64::from(e.thickness);
        }
        Some(r.flip_z())
    }

    /// The thick-lens approximation: the principal planes' and focal points' z in lens space
    /// (negative, toward the scene), `[film side, scene side]` each, from rays parallel to the
    /// axis at height `height` [m] (pbrt-v4 §5.3.4).
    pub fn cardinal_points(&self, height: f64) -> Result<([f64; 2], [f64; 2]), LensError> {
        // Where the exiting ray crosses the axis (the focal point) and the height of the
        // entering ray (the principal plane), each as −z in camera space.
        let points = |r_in: LensRay, r_out: LensRay| {
            let tf = -r_out.o.x / r_out.d.x;
            let tp = (r_in.o.x - r_out.o.x) / r_out.d.x;
            (-r_out.at(tp).z, -r_out.at(tf).z)
        };
        let from_scene = LensRay { o: DVec3::new(height, 0.0, self.front_z() + 1.0), d: DVec3::NEG_Z };
        let to_film = self.trace_from_scene(from_scene).ok_or(LensError::NoParallelRay)?;
        let (p0, f0) = points(from_scene, to_film);
        let from_film = LensRay { o: DVec3::new(height, 0.0, self.rear_z() - 1.0), d: DVec3::Z };
        let to_scene = self.trace_from_film(from_film).ok_or(LensError::NoParallelRay)?;
        let (p1, f1) = points(from_film, to_scene);
        Ok(([p0, p1], [f0, f1]))
    }

    /// Moves the lens along the axis (changes the rear interface's distance to the film) so
    /// that a point `focus_distance` [m] in front of the film is imaged on it: the thick-lens
    /// equation solved for the lens translation (pbrt-v4 `FocusThickLens`).
    pub fn focus(&mut self, focus_distance: f32, height: f64) -> Result<(), LensError> {
        let (pz, fz) = self.cardinal_points(height)?;
        let f = fz[0] - pz[0];
        let z = -f64::from(focus_distance);
        let c = (pz[1] - z - pz[0]) * (pz[1] - z - 4.0 * f - pz[0]);
        if c.is_nan() || c <= 0.0 {
            return Err(LensError::FocusTooClose(focus_distance));
        }
        let delta = 0.5 * (pz[1] - z + pz[0] - c.sqrt());
        let last = self.elements.last_mut().ok_or(LensError::NoParallelRay)?;
        last.thickness = (f64::from(last.thickness) + delta) as f32;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric biconvex singlet: radii ±`r`, centre thickness `d`, index `n`, clear
    /// aperture radius `a` [m], its rear vertex `back` in front of the film.
    fn singlet(r: f32, d: f32, n: f32, a: f32, back: f32) -> LensSystem {
        let face =
            |curvature_radius, thickness, eta| LensInterface { curvature_radius, thickness, eta, aperture_radius: a };
        LensSystem::new(vec![face(r, d, n), face(-r, back, 1.0)])
    }

    /// The thick-lens focal length and the principal planes' offsets from the front and rear
    /// vertices along the light (Hecht, Optics §6.2): 1/f = (n−1)(1/R₁ − 1/R₂ + (n−1)d/(nR₁R₂)),
    /// h₁ = −f(n−1)d/(nR₂), h₂ = −f(n−1)d/(nR₁).
    fn lensmaker(r1: f64, r2: f64, d: f64, n: f64) -> (f64, f64, f64) {
        let f = 1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2)));
        (f, -f * (n - 1.0) * d / (n * r2), -f * (n - 1.0) * d / (n * r1))
    }

    #[test]
    fn a_singlets_cardinal_points_are_the_lensmakers() {
        let (r, d, n) = (0.05, 0.004, 1.5);
        let lens = singlet(r as f32, d as f32, n as f32, 0.01, 0.045);
        let (f, h1, h2) = lensmaker(r, -r, d, n);
        let (pz, fz) = lens.cardinal_points(3.5e-5).unwrap();
        // Lens space: the rear vertex at z = −0.045, the front at −0.049; light from the scene
        // runs toward +z, so offsets along it add.
        let (front, rear) = (-(0.045 + d), -0.045);
        assert!((fz[0] - pz[0] - f).abs() < 1e-6 * f, "f {} vs {f}", fz[0] - pz[0]);
        assert!((pz[0] - (rear + h2)).abs() < 1e-7, "film-side principal plane {} vs {}", pz[0], rear + h2);
        assert!((pz[1] - (front + h1)).abs() < 1e-7, "scene-side principal plane {} vs {}", pz[1], front + h1);
        assert!((fz[1] - pz[1] + f).abs() < 1e-6 * f, "the scene-side focal point lies f before its plane");
    }

    #[test]
    fn a_focused_singlet_images_a_point_at_the_focus_distance_on_the_film() {
        let (r, d, n, focus) = (0.05, 0.004, 1.5, 2.0);
        let mut lens = singlet(r as f32, d as f32, n as f32, 0.002, 0.045);
        lens.focus(focus as f32, 3.5e-5).unwrap();
        // Gaussian imaging between the principal planes: object distance s from H, image
        // distance s′ from H′ = the film, 1/s + 1/s′ = 1/f and s + s′ = D − d + h₁ − h₂.
        let (f, h1, h2) = lensmaker(r, -r, d, n);
        let l = focus - d + h1 - h2;
        let image = 0.5 * (l - (l * l - 4.0 * f * l).sqrt());
        let back = lens.rear_z();
        assert!((back - (image + h2)).abs() < 1e-6, "film at {back} behind the lens, thick-lens {}", image + h2);
        // Rays from the on-axis point at the focus distance, through the central 1 mm of the
        // lens (spherical aberration grows as the cube of the height), cross the film near the
        // axis; with the film 0.5 mm off focus they do not.
        let point = DVec3::new(0.0, 0.0, focus);
        let spread = |film_z: f64| {
            (1..=8).fold(0.0f64, |m, k| {
                let h = 0.001 * f64::from(k) / 8.0;
                let to = DVec3::new(h * 0.6, h * 0.8, lens.front_z());
                let out = lens.trace_from_scene(LensRay { o: point, d: to - point }).expect("passes the aperture");
                m.max(out.at((film_z - out.o.z) / out.d.z).truncate().length())
            })
        };
        // 2 µm: a hundredth of a pixel of a 35 mm film 128 pixels across.
        assert!(spread(0.0) < 2e-6, "rays from the focused point spread {} m on the film", spread(0.0));
        assert!(spread(5e-4) > 2e-6, "off focus {}", spread(5e-4));
    }

    #[test]
    fn rays_are_blocked_outside_the_clear_apertures() {
        let lens = singlet(0.05, 0.004, 1.5, 0.002, 0.045);
        let film = DVec3::ZERO;
        let through = |x: f64| lens.trace_from_film(LensRay { o: film, d: DVec3::new(x, 0.0, 0.045) });
        assert!(through(0.0019).is_some() && through(0.0021).is_none());
        assert!(through(0.0).is_some_and(|r| r.d.truncate().length() < 1e-12 && r.d.z > 0.0), "the axis ray");
    }
}

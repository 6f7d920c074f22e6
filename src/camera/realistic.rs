//! pbrt-v4's realistic camera (§5.3): rays from points on a physical film traced through a lens
//! system, sampled over the exit pupil. Each ray carries the weight that turns the film's
//! irradiance integral into a Monte Carlo estimate (pbrt-v4 Eq. 5.8 with the camera's
//! measurement): shutter time · cos⁴θ · A_pupil / z_rear², where θ is the angle of the film ray
//! to the axis, A_pupil the area of the box sampled (1/pdf) and z_rear the film's distance to
//! the rear interface.

use super::exit_pupil::ExitPupil;
use super::lens::LensInterface;
use super::lens_system::{LensError, LensRay, LensSystem};
use glam::{DVec2, DVec3, Vec2, Vec3};

/// A focused lens system in front of a film, with its exit-pupil boxes.
#[derive(Clone, Debug, PartialEq)]
pub struct RealisticLens {
    /// The lens, moved to focus.
    pub system: LensSystem,
    /// The exit pupil's boxes.
    pub pupil: ExitPupil,
    /// Film diagonal [m].
    pub film_diagonal: f64,
    /// Shutter open time (shutterclose − shutteropen) [s].
    pub shutter: f32,
}

/// What building a realistic camera noted without failing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopClamped {
    /// The diameter asked for [m].
    pub asked: f32,
    /// The stop's largest diameter, used instead [m].
    pub max: f32,
}

impl RealisticLens {
    /// The lens of `elements` with the aperture stop opened to `aperture_diameter` [m] (at
    /// most the stop's own diameter), focused at `focus_distance` [m] from the film, in front
    /// of a film of diagonal `film_diagonal` [m].
    pub fn new(
        mut elements: Vec<LensInterface>,
        aperture_diameter: f32,
        focus_distance: f32,
        film_diagonal: f32,
        shutter: f32,
    ) -> Result<(Self, Option<StopClamped>), LensError> {
        let mut clamped = None;
        for e in elements.iter_mut().filter(|e| e.is_stop()) {
            let max = 2.0 * e.aperture_radius;
            if aperture_diameter > max {
                clamped = Some(StopClamped { asked: aperture_diameter, max });
            } else {
                e.aperture_radius = 0.5 * aperture_diameter;
            }
        }
        let mut system = LensSystem::new(elements);
        let film_diagonal = f64::from(film_diagonal);
        // Parallel rays close to the axis (paraxial) give the cardinal points.
        system.focus(focus_distance, 1e-3 * film_diagonal)?;
        let pupil = ExitPupil::new(&system, 0.5 * film_diagonal);
        Ok((Self { system, pupil, film_diagonal, shutter }, clamped))
    }

    /// Half the film's extent along x and y [m] for an image of `resolution`: the diagonal
    /// split in the image's aspect ratio.
    pub fn film_half_extent(&self, resolution: (u32, u32)) -> DVec2 {
        let aspect = f64::from(resolution.1) / f64::from(resolution.0);
        let x = (self.film_diagonal * self.film_diagonal / (1.0 + aspect * aspect)).sqrt();
        0.5 * DVec2::new(x, aspect * x)
    }

    /// The ray [camera space; unit direction] for film position `p_film` (pixels, y down) of an
    /// image of `resolution`, through the pupil point picked by `u_lens`, and its weight; `None`
    /// when the lens blocks it.
    pub fn generate_ray(&self, p_film: Vec2, resolution: (u32, u32), u_lens: Vec2) -> Option<(Vec3, Vec3, f32)> {
        let half = self.film_half_extent(resolution);
        let s = p_film.as_dvec2() / DVec2::new(f64::from(resolution.0), f64::from(resolution.1));
        let on_film = -half + 2.0 * half * s;
        // The lens inverts the image: film +x is image left, film +y (raster down) image up.
        let film = DVec3::new(-on_film.x, on_film.y, 0.0);
        let (rear, area) = self.pupil.sample(film.truncate(), u_lens);
        let r_film = LensRay { o: film, d: rear - film };
        let out = self.system.trace_from_film(r_film)?;
        let cos = r_film.d.normalize().z;
        let rear_z = self.system.rear_z();
        let weight = f64::from(self.shutter) * cos.powi(4) * area / (rear_z * rear_z);
        Some((out.o.as_vec3(), out.d.normalize().as_vec3(), weight as f32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::lens::parse_lens_file;
    use crate::sampling::Rng;

    /// The double-Gauss 50 mm lens at f/3.6, focused at 5 m, before a 35 mm film.
    fn dgauss() -> RealisticLens {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/compat/cameras-dgauss.50mm.dat");
        let elements = parse_lens_file(&std::fs::read_to_string(path).unwrap()).unwrap();
        let (lens, clamped) = RealisticLens::new(elements, 0.014, 5.0, 0.035, 1.0).unwrap();
        assert!(clamped.is_none());
        lens
    }

    #[test]
    fn rays_from_the_film_centre_converge_on_the_axis_at_the_focus_distance() {
        let lens = dgauss();
        let mut rng = Rng::new(7, 1);
        let mut passed = 0;
        for _ in 0..2000 {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let Some((o, d, w)) = lens.generate_ray(Vec2::splat(64.0), (128, 128), u) else { continue };
            passed += 1;
            assert!(w > 0.0);
            let (o, d) = (o.as_dvec3(), d.as_dvec3());
            // Nearly parallel to the axis (within the 7 mm stop radius over 5 m, far less)
            // and through the axis point 5 m from the film, up to the lens's aberration.
            assert!(d.z > 0.999, "{d}");
            let at_focus = o + (5.0 - o.z) / d.z * d;
            assert!(
                at_focus.truncate().length() < 2e-3,
                "crosses the focus plane {} m off the axis",
                at_focus.truncate().length()
            );
        }
        assert!(passed > 1000, "only {passed} of 2000 pupil samples passed");
    }

    #[test]
    fn the_exit_pupil_boxes_hold_every_ray_that_passes() {
        let lens = dgauss();
        let (system, pupil) = (&lens.system, &lens.pupil);
        let rear = 1.5 * system.rear_radius();
        let mut rng = Rng::new(3, 5);
        let (mut passed, mut tried) = (0, 0);
        for _ in 0..40 {
            let r = rng.uniform_f64() * pupil.half_diagonal;
            let ring = ((r / pupil.half_diagonal * super::super::exit_pupil::RINGS as f64) as usize)
                .min(super::super::exit_pupil::RINGS - 1);
            let b = pupil.boxes[ring];
            for _ in 0..2000 {
                let p = DVec2::new(2.0 * rng.uniform_f64() - 1.0, 2.0 * rng.uniform_f64() - 1.0) * rear;
                let film = DVec3::new(r, 0.0, 0.0);
                tried += 1;
                if system.trace_from_film(LensRay { o: film, d: p.extend(system.rear_z()) - film }).is_some() {
                    passed += 1;
                    assert!(b.contains(p), "{p} passes from film radius {r} but lies outside {b:?}");
                }
            }
        }
        assert!(passed > tried / 20, "{passed} of {tried}");
    }
}

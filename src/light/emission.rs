//! Sampling the light a source emits, for paths that start at the lights (light tracing and
//! bidirectional path tracing; Veach 1997 §10.2, PBR 3rd ed. §16.1.2 and §16.3): a point on the
//! light and a direction leaving it, with their densities, and the densities of a given point
//! and direction (pbrt-v4 `Light::SampleLe`, `Light::PDF_Le`).
//!
//! Surface lights take the point uniformly by area and the direction cosine-distributed about
//! the emitting side's normal (either side, each with probability ½, for two-sided ones); point
//! lights take the direction uniformly over the sphere (goniometric and projection lights too),
//! spotlights over the cone they light. Lights at infinity take the direction as their light
//! sampling does (uniformly, by the map's importance, or a distant light's one direction) and
//! the point uniformly on a disk of the scene's bounding-sphere radius perpendicular to it, behind
//! the scene (PBR 3rd ed. §16.1.2: area density 1/(π r²) in the plane perpendicular to the
//! direction). A portal light's ray starts where it crosses the portal, and carries nothing when
//! it misses the portal.

use super::{Light, LightSampleContext};
use crate::math::{Frame, PI};
use crate::sampling::warp::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_cone, sample_uniform_disk_concentric,
    sample_uniform_sphere, uniform_cone_pdf, uniform_sphere_pdf, uniform_triangle,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// A point and direction of emitted light.
#[derive(Clone, Copy, Debug)]
pub struct EmissionSample {
    /// The point on the light [scene units].
    pub p: Vec3,
    /// The emitting side's unit normal there (zero for point lights; for lights at infinity,
    /// `d`: the disk the point lies on faces the direction).
    pub n: Vec3,
    /// Unit direction of the emitted ray.
    pub d: Vec3,
    /// Emitted radiance along `d` (for point lights, the intensity I [W/(sr·nm)]; for a distant
    /// light, the irradiance E [W/(m²·nm)] it brings perpendicular to `d`).
    pub le: SampledSpectrum,
    /// Area density of `p` [1/m²] (1 for point lights; for lights at infinity, in the plane
    /// perpendicular to `d`).
    pub pdf_pos: f32,
    /// Solid-angle density of `d` [1/sr] (1 for a distant light's single direction).
    pub pdf_dir: f32,
}

/// The scene's bounding sphere, which light from infinity is sent across.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneSphere {
    /// Centre [scene units].
    pub center: Vec3,
    /// Radius [scene units].
    pub radius: f32,
}

impl SceneSphere {
    /// Area density [1/m²] of a point uniform on a disk of the sphere's radius: 1/(π r²).
    pub fn disk_pdf(&self) -> f32 {
        1.0 / (PI * self.radius * self.radius)
    }

    /// A point uniform (with `u`) on the disk of the sphere's radius perpendicular to `d`,
    /// moved back against `d` by the radius, so that a ray from it along `d` meets all the
    /// scene that lies on its line.
    fn disk_point(&self, d: Vec3, u: Vec2) -> Vec3 {
        let frame = Frame::from_normal(d);
        let q = sample_uniform_disk_concentric(u) * self.radius;
        self.center + frame.s * q.x + frame.t * q.y - d * self.radius
    }
}

/// A direction about the normal `n`, cosine-distributed on one side chosen with `u.x` when the
/// light is two-sided: the direction and its density.
fn emitted_direction(n: Vec3, two_sided: bool, mut u: Vec2) -> (Vec3, f32) {
    let mut side = n;
    let mut share = 1.0;
    if two_sided {
        share = 0.5;
        if u.x < 0.5 {
            u.x *= 2.0;
        } else {
            u.x = (u.x - 0.5) * 2.0;
            side = -n;
        }
        u.x = u.x.min(1.0f32.next_down());
    }
    let local = sample_cosine_hemisphere(u);
    (Frame::from_normal(side).to_world(local), cosine_hemisphere_pdf(local.z) * share)
}

/// The density of direction `d` leaving a surface light with normal `n`.
fn emitted_direction_pdf(n: Vec3, two_sided: bool, d: Vec3) -> f32 {
    let cos = n.dot(d);
    if two_sided {
        0.5 * cosine_hemisphere_pdf(cos.abs())
    } else if cos > 0.0 {
        cosine_hemisphere_pdf(cos)
    } else {
        0.0
    }
}

impl Light {
    /// Samples a point on the light (with `u_pos`) and a direction leaving it (with `u_dir`),
    /// both in [0,1)²; lights at infinity send it across `sphere`. `None` when the light emits
    /// nothing there.
    pub fn sample_le(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        sphere: &SceneSphere,
        w: &SampledWavelengths,
    ) -> Option<EmissionSample> {
        let s = match self {
            Light::Area(l) => {
                let b = uniform_triangle(u_pos.x, u_pos.y);
                let p = l.p[0] * b[0] + l.p[1] * b[1] + l.p[2] * b[2];
                let (d, pdf_dir) = emitted_direction(l.n, l.two_sided, u_dir);
                let le = match &l.image {
                    None => l.spectrum.sample(w) * l.scale,
                    Some(image) => image.radiance_at(b, w) * l.scale,
                };
                EmissionSample { p, n: l.n, d, le, pdf_pos: 1.0 / l.area, pdf_dir }
            }
            Light::Rectangle(l) => {
                let p = l.corner + l.ex * u_pos.x + l.ey * u_pos.y;
                let (d, pdf_dir) = emitted_direction(l.n, l.two_sided, u_dir);
                EmissionSample { p, n: l.n, d, le: l.radiance(d, w), pdf_pos: 1.0 / l.area(), pdf_dir }
            }
            Light::Sphere(l) => {
                let n = sample_uniform_sphere(u_pos);
                let p = l.center + n * l.radius;
                let n = if l.inward { -n } else { n };
                let (d, pdf_dir) = emitted_direction(n, l.two_sided, u_dir);
                EmissionSample { p, n, d, le: l.radiance(n, d, w), pdf_pos: 1.0 / l.area(), pdf_dir }
            }
            Light::Quadric(l) => {
                let uv = l.shape.quadric.uniform_area_uv(u_pos);
                let (p, n, area_scale) = l.shape.point(uv.x, uv.y);
                let (d, pdf_dir) = emitted_direction(n, l.two_sided, u_dir);
                let pdf_pos = 1.0 / (l.shape.quadric.area() * area_scale);
                EmissionSample { p, n, d, le: l.radiance(n, d, w), pdf_pos, pdf_dir }
            }
            Light::Point(l) => EmissionSample {
                p: l.position,
                n: Vec3::ZERO,
                d: sample_uniform_sphere(u_dir),
                le: l.spectrum.sample(w) * l.scale,
                pdf_pos: 1.0,
                pdf_dir: uniform_sphere_pdf(),
            },
            Light::Spot(l) => {
                let cos_max = l.cone_cos_max();
                let d = l.frame.to_world(sample_uniform_cone(u_dir, cos_max));
                let le = l.spectrum.sample(w) * (l.scale * l.falloff.factor(l.frame.n.dot(d)));
                EmissionSample { p: l.position, n: Vec3::ZERO, d, le, pdf_pos: 1.0, pdf_dir: uniform_cone_pdf(cos_max) }
            }
            Light::Goniometric(_) | Light::Projection(_) => {
                let d = sample_uniform_sphere(u_dir);
                let (p, le) = self.point_intensity(d, w);
                EmissionSample { p, n: Vec3::ZERO, d, le, pdf_pos: 1.0, pdf_dir: uniform_sphere_pdf() }
            }
            Light::Distant(l) => {
                let d = -l.to_light;
                let le = l.spectrum.sample(w) * l.scale;
                let p = sphere.disk_point(d, u_pos);
                EmissionSample { p, n: d, d, le, pdf_pos: sphere.disk_pdf(), pdf_dir: 1.0 }
            }
            Light::UniformInfinite(_) | Light::EnvMap(_) => {
                let ls = self.sample_li(&LightSampleContext::medium(sphere.center), u_dir, w)?;
                let d = -ls.wi;
                let p = sphere.disk_point(d, u_pos);
                EmissionSample { p, n: d, d, le: ls.li, pdf_pos: sphere.disk_pdf(), pdf_dir: ls.pdf }
            }
            Light::Portal(l) => {
                let (d, le, pdf_dir) = l.sample_emitted(u_dir, w)?;
                let p = l.crossing(sphere.disk_point(d, u_pos), d)?;
                EmissionSample { p, n: d, d, le, pdf_pos: sphere.disk_pdf(), pdf_dir }
            }
        };
        // A point light's position is a sample whatever it sends along the direction drawn
        // (bidirectional connections take the position alone).
        let emits = !s.le.is_black() || s.n == Vec3::ZERO;
        (s.pdf_pos > 0.0 && s.pdf_dir > 0.0 && s.pdf_pos.is_finite() && emits).then_some(s)
    }

    /// [`Light::sample_le`] for its point alone (a bidirectional connection to the light): the
    /// direction sample is fixed where every light emits with a positive density — the centre of
    /// the front side's cosine lobe of a two-sided surface light (u = (¼, ½)), inside the lobe
    /// of a one-sided one — so no light's point is lost to a direction at its horizon.
    pub fn sample_le_point(&self, u_pos: Vec2, sphere: &SceneSphere, w: &SampledWavelengths) -> Option<EmissionSample> {
        self.sample_le(u_pos, Vec2::new(0.25, 0.5), sphere, w)
    }

    /// The position of a goniometric or projection light and the intensity I [W/(sr·nm)] it
    /// sends along the unit direction `d` (zero for other lights).
    fn point_intensity(&self, d: Vec3, w: &SampledWavelengths) -> (Vec3, SampledSpectrum) {
        let p = match self {
            Light::Goniometric(l) => l.position,
            Light::Projection(l) => l.position,
            _ => return (Vec3::ZERO, SampledSpectrum::zero()),
        };
        // At unit distance the incident radiance of a point light is its intensity.
        let ls = self.sample_li(&LightSampleContext::medium(p + d), Vec2::ZERO, w);
        (p, ls.map_or(SampledSpectrum::zero(), |ls| ls.li))
    }

    /// The radiance (for point lights, intensity) the light sends from the point of `s` along
    /// the unit direction `d`: surface lights are Lambertian emitters, the same radiance toward
    /// every direction of an emitting side. Lights at infinity send light along `s.d` only and
    /// give 0 (light reaching a point from them is [`Light::sample_li`]'s).
    pub fn emitted_toward(&self, s: &EmissionSample, d: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Light::Area(l) if l.two_sided || l.n.dot(d) > 0.0 => s.le,
            Light::Rectangle(l) if l.two_sided || l.n.dot(d) > 0.0 => s.le,
            Light::Sphere(l) if l.two_sided || s.n.dot(d) > 0.0 => s.le,
            Light::Quadric(l) if l.two_sided || s.n.dot(d) > 0.0 => s.le,
            Light::Point(_) => s.le,
            Light::Spot(l) => l.spectrum.sample(w) * (l.scale * l.falloff.factor(l.frame.n.dot(d))),
            Light::Goniometric(_) | Light::Projection(_) => self.point_intensity(d, w).1,
            _ => SampledSpectrum::zero(),
        }
    }

    /// The densities (area [1/m²], solid angle [1/sr]) with which [`Light::sample_le`] picks
    /// the point with emitting-side normal `n` and the unit direction `d` leaving it (pbrt-v4
    /// `PDF_Le`). A surface point's area density is 1/A, the quadrics' under a transform that
    /// is not a similarity included (there it is the mean density, which MIS weights may use).
    /// For lights at infinity, the disk's density across `sphere` and the direction's (0 for a
    /// distant light's delta).
    pub fn pdf_le(&self, n: Vec3, d: Vec3, sphere: &SceneSphere) -> (f32, f32) {
        match self {
            Light::Area(l) => (1.0 / l.area, emitted_direction_pdf(l.n, l.two_sided, d)),
            Light::Rectangle(l) => (1.0 / l.area(), emitted_direction_pdf(l.n, l.two_sided, d)),
            Light::Sphere(l) => (1.0 / l.area(), emitted_direction_pdf(n, l.two_sided, d)),
            Light::Quadric(l) => (1.0 / l.area, emitted_direction_pdf(n, l.two_sided, d)),
            Light::Point(_) => (1.0, uniform_sphere_pdf()),
            Light::Spot(l) => {
                let cos_max = l.cone_cos_max();
                (1.0, if l.frame.n.dot(d) >= cos_max { uniform_cone_pdf(cos_max) } else { 0.0 })
            }
            Light::Goniometric(_) | Light::Projection(_) => (1.0, uniform_sphere_pdf()),
            Light::Distant(_) => (sphere.disk_pdf(), 0.0),
            Light::Portal(l) => (sphere.disk_pdf(), l.pdf_emitted(-d)),
            Light::UniformInfinite(_) | Light::EnvMap(_) => {
                (sphere.disk_pdf(), self.pdf_li(&LightSampleContext::medium(sphere.center), -d))
            }
        }
    }
}

/// A scene sphere for tests.
#[cfg(test)]
const TEST_SPHERE: SceneSphere = SceneSphere { center: Vec3::new(0.5, -1.0, 2.0), radius: 3.0 };

/// ∫ over the unit sphere of the density of [`Light::sample_le`]'s directions, for tests.
#[cfg(test)]
fn direction_pdf_integral(light: &Light, n: Vec3) -> f32 {
    use crate::math::PI;
    let k = 400;
    let mut sum = 0.0f64;
    for i in 0..k {
        for j in 0..2 * k {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / k as f32;
            let phi = PI * (j as f32 + 0.5) / k as f32;
            let r = (1.0 - z * z).sqrt();
            let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            sum += light.pdf_le(n, d, &TEST_SPHERE).1 as f64;
        }
    }
    (sum * 4.0 * PI as f64 / (2 * k * k) as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::light::{AreaLight, EnvMapLight, PointLight, SpotFalloff, SpotLight, UniformInfiniteLight};
    use crate::sampling::rng::Rng;
    use crate::spectrum::Spectrum;
    use glam::Mat3;
    use std::sync::Arc;

    fn triangle(two_sided: bool) -> Light {
        let p = [Vec3::new(0.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(0.0, 2.5, 1.5)];
        AreaLight::constant_triangle(p, two_sided)
    }

    #[test]
    fn sampled_densities_are_those_pdf_le_gives_and_integrate_to_one() {
        let w = SampledWavelengths::sample_visible(0.5);
        let spot = Light::Spot(SpotLight::new(
            Vec3::ONE,
            Vec3::new(0.2, -1.0, 0.1),
            Arc::new(Spectrum::constant(1.0)),
            1.0,
            SpotFalloff::Cone { cos_start: 0.9, cos_end: 0.7 },
        ));
        let point = Light::Point(PointLight::new(Vec3::ZERO, Arc::new(Spectrum::constant(1.0)), 2.0));
        let mut rng = Rng::new(1, 2);
        for light in [triangle(false), triangle(true), spot, point, uniform_sky(), image_sky()] {
            let mut n = Vec3::ZERO;
            for _ in 0..1000 {
                let u = |r: &mut Rng| Vec2::new(r.uniform(), r.uniform());
                let Some(s) = light.sample_le(u(&mut rng), u(&mut rng), &TEST_SPHERE, &w) else { continue };
                let (pos, dir) = light.pdf_le(s.n, s.d, &TEST_SPHERE);
                assert!((pos - s.pdf_pos).abs() <= 1e-5 * pos && (dir - s.pdf_dir).abs() <= 1e-4 * dir, "{light:?}");
                n = s.n;
            }
            let total = direction_pdf_integral(&light, n);
            assert!((total - 1.0).abs() < 0.01, "{light:?}: ∫ pdf_dir = {total}");
        }
    }

    fn uniform_sky() -> Light {
        Light::UniformInfinite(UniformInfiniteLight { spectrum: Arc::new(Spectrum::constant(1.0)), scale: 1.0 })
    }

    /// A 16 × 8 latitude–longitude map, bright toward one side.
    fn image_sky() -> Light {
        let mut img = Image::new(16, 8, 3);
        for (i, v) in img.data.iter_mut().enumerate() {
            *v = 0.1 + ((i / 3) % 16) as f32 * 0.3;
        }
        Light::EnvMap(EnvMapLight::new(&img, Mat3::from_rotation_x(0.3), 1.0, crate::spectrum::ColorSpace::srgb()))
    }

    #[test]
    fn light_from_infinity_starts_uniformly_on_a_disk_behind_the_scene() {
        // Every point lies on the disk of radius r perpendicular to its direction, r behind the
        // centre; uniform on it, its squared distance from the disk's centre has mean r²/2.
        let w = SampledWavelengths::sample_visible(0.5);
        let distant = Light::Distant(crate::light::DistantLight {
            to_light: Vec3::new(0.3, 0.9, -0.2).normalize(),
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 2.0,
        });
        let (c, r) = (TEST_SPHERE.center, TEST_SPHERE.radius);
        let mut rng = Rng::new(3, 4);
        for light in [distant, uniform_sky(), image_sky()] {
            let (mut sum, mut count) = (0.0f64, 0);
            for _ in 0..4000 {
                let u = |r: &mut Rng| Vec2::new(r.uniform(), r.uniform());
                let s = light.sample_le(u(&mut rng), u(&mut rng), &TEST_SPHERE, &w).unwrap();
                let q = s.p - c;
                assert!((q.dot(s.d) + r).abs() < 1e-4 * r, "{light:?}");
                let across = (q - q.dot(s.d) * s.d).length_squared();
                assert!(across <= r * r * (1.0 + 1e-5));
                assert_eq!(s.n, s.d);
                assert!((s.pdf_pos * PI * r * r - 1.0).abs() < 1e-5);
                sum += across as f64;
                count += 1;
            }
            let mean = sum / count as f64 / (r * r) as f64;
            // σ of r²-normalised squared distance: 1/√12 per sample.
            assert!((mean - 0.5).abs() < 4.0 * (1.0 / 12f64).sqrt() / (count as f64).sqrt(), "{light:?}: {mean}");
        }
    }
}

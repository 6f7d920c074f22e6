//! A diffuse area light on a disk, a cylinder or a partial sphere, sampled uniformly by area as
//! pbrt-v4 samples these shapes (PBR 4th ed. §6.2.4, §6.3.4, §6.4.4), the area density turned
//! into solid angle at the reference point: p_ω = d² / (|cos θ_l| A). (A full sphere is a
//! [`super::SphereLight`], sampled by the cone it subtends.)
//!
//! Unlike pbrt-v4, which samples a partial sphere's points over the whole sphere and a disk's
//! over the full disk whatever its `innerradius` and `phimax`, points are drawn over the shape's
//! own ranges: z uniform in [z_min, z_max] on the sphere (Archimedes: equal heights, equal
//! areas) and the cylinder, ρ² uniform in [rᵢ², r²] on the disk, φ uniform in [0, φmax].
//! Under a transform that is not a similarity the object-space density is divided by the
//! world area per unit object area at the point, so the density stays exact in world space.

use super::point::spectral_integral;
use super::sampler::LightBounds;
use super::selection_flux::{max_value, visible_flux};
use super::LightSample;
use crate::geometry::{PlacedQuadric, Ray};
use crate::math::PI;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// An emitting quadric of constant radiance L = `scale · spectrum(λ)` [W/(sr·m²·nm)].
#[derive(Clone, Debug)]
pub struct QuadricLight {
    /// The shape (static).
    pub shape: PlacedQuadric,
    /// World area [scene units²].
    pub area: f32,
    /// Spectral shape of the radiance.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` into radiance L.
    pub scale: f32,
    /// Emits from both sides.
    pub two_sided: bool,
}

impl QuadricLight {
    /// Radiance leaving the surface with normal `n` (its emitting side) toward `w`.
    #[inline]
    pub fn radiance(&self, n: Vec3, w: Vec3, lambdas: &SampledWavelengths) -> SampledSpectrum {
        if !self.two_sided && n.dot(w) <= 0.0 {
            return SampledSpectrum::zero();
        }
        self.spectrum.sample(lambdas) * self.scale
    }

    pub(super) fn sample_li(&self, p: Vec3, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let uv = self.shape.quadric.uniform_area_uv(u);
        let (q, n, area_scale) = self.shape.point(uv.x, uv.y);
        let d = q - p;
        let dist2 = d.length_squared();
        let dist = dist2.sqrt();
        let wi = d / dist;
        let cos_l = n.dot(wi).abs();
        let pdf = dist2 / (cos_l * self.shape.quadric.area() * area_scale);
        if !(pdf.is_finite() && pdf > 0.0) {
            return None;
        }
        let li = self.radiance(n, -wi, w);
        (!li.is_black()).then_some(LightSample { li, wi, pdf, p_light: q, dist })
    }

    /// Solid-angle density with which `sample_li` at `p` picks the unit direction `wi`, at the
    /// first point where the ray meets the shape (pbrt-v4 `Shape::PDF(ctx, wi)`); 0 when it
    /// misses.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3) -> f32 {
        let ray = Ray::new(p, wi);
        let Some(t) = self.shape.intersect(&ray, f32::INFINITY) else { return 0.0 };
        let s = self.shape.surface(&ray, t);
        let cos_l = s.n.dot(wi).abs();
        let pdf = t * t / (cos_l * self.shape.quadric.area() * s.area_scale);
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    /// The radiant flux Φ = π L A per emitting side [W], L integrated over 360–830 nm (what it
    /// emits; [`QuadricLight::power`] is the weight light samplers choose it by).
    pub fn radiant_flux(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        PI * self.area * sides * self.scale * spectral_integral(&self.spectrum)
    }

    /// pbrt-v4's `DiffuseAreaLight::Phi` for the power sampler: π L A per emitting side, L's
    /// spectrum by `visible_flux` (see `selection_flux`).
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        PI * self.area * sides * self.scale * visible_flux(&self.spectrum)
    }

    /// pbrt-v4's `DiffuseAreaLight::Bounds` flux: π A scale MaxValue(L) for one side, two-sided
    /// or not (see `selection_flux`).
    pub fn bound_flux(&self) -> f32 {
        PI * self.area * self.scale * max_value(&self.spectrum)
    }

    /// Bounds for many-light sampling, emitting flux `phi`: the placed shape's box and θ_e =
    /// π/2; a disk's normal is one direction (θ_o = 0), the other shapes' span every direction.
    pub(super) fn bounds(&self, phi: f32) -> LightBounds {
        let (w, cos_theta_o) =
            if self.shape.quadric.is_planar() { (self.shape.point(0.0, 0.5).1, 1.0) } else { (Vec3::Z, -1.0) };
        LightBounds { bounds: self.shape.bounds(), w, phi, cos_theta_o, cos_theta_e: 0.0, two_sided: self.two_sided }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Quadric;
    use crate::sampling::chi2::Chi2Test;
    use glam::{Mat4, Quat};

    /// The light on `quadric` placed by a rotation, a non-uniform scale and a translation, so
    /// that the object-to-world area element varies over the surface.
    fn light(quadric: Quadric) -> QuadricLight {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(1.0, 1.6, 0.7),
            Quat::from_axis_angle(Vec3::new(0.3, 1.0, 0.2).normalize(), 0.8),
            Vec3::new(0.5, -1.0, 2.0),
        );
        let shape = PlacedQuadric::new(quadric, m, false).unwrap();
        QuadricLight {
            area: shape.area(),
            shape,
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 1.0,
            two_sided: true,
        }
    }

    /// χ² of the directions `sample_li` draws against `pdf_li`, from a point every ray from
    /// which meets the shape at most once (the centre of the sphere and the cylinder's axis,
    /// where pdf_li's first hit is the only one; any point off the disk's plane).
    #[test]
    fn area_sampling_passes_chi_square_against_pdf_li() {
        let cases = [
            (Quadric::Sphere { radius: 1.0, z_min: -0.6, z_max: 0.9, phi_max: 250.0 }, Vec3::ZERO),
            (Quadric::Cylinder { radius: 0.8, z_min: -0.5, z_max: 1.5, phi_max: 300.0 }, Vec3::new(0.0, 0.0, 0.2)),
            (Quadric::Disk { height: 0.0, radius: 1.0, inner_radius: 0.35, phi_max: 280.0 }, Vec3::new(0.3, 0.2, 0.8)),
            (Quadric::Disk { height: 0.2, radius: 2.0, inner_radius: 0.0, phi_max: 360.0 }, Vec3::new(-0.5, 1.0, -0.6)),
        ];
        let w = SampledWavelengths::sample_visible(0.5);
        for (q, object_point) in cases {
            let l = light(q);
            let p = l.shape.placement.world_from_object.transform_point3(object_point);
            let test = Chi2Test {
                test_count: cases.len(),
                sample_count: 400_000,
                theta_res: 40,
                phi_res: 80,
                ..Default::default()
            };
            let r = test.run(|_, u| l.sample_li(p, u, &w).map(|s| s.wi), |wi| l.pdf_li(p, wi));
            assert!(r.passed, "{q:?}: {r}");
            assert!((r.sampled_fraction - 1.0).abs() < 1e-4, "{q:?}: {r}");
            // Every sample is a direction toward the shape, so its density integrates to 1.
            assert!((r.pdf_integral - 1.0).abs() < 2e-3, "{q:?}: {r}");
        }
    }

    #[test]
    fn the_power_is_pi_l_times_the_area() {
        // A disk of radius 2 under a uniform scale 3: A = π (6)², Φ = π L A per side.
        let shape = PlacedQuadric::new(
            Quadric::Disk { height: 0.0, radius: 2.0, inner_radius: 0.0, phi_max: 360.0 },
            Mat4::from_scale(Vec3::splat(3.0)),
            false,
        )
        .unwrap();
        let l = QuadricLight {
            area: shape.area(),
            shape,
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 2.0,
            two_sided: false,
        };
        let a = PI * 36.0;
        assert!((l.area - a).abs() < 1e-4 * a);
        let expected = PI * a * 2.0 * spectral_integral(&Spectrum::constant(1.0));
        assert!((l.radiant_flux() - expected).abs() < 1e-4 * expected);
    }
}

//! Diffuse area light: one emissive triangle of radiance L [W/(sr·m²·nm)] on its front side (or
//! both), constant or an image looked up at the point's (u, v). Flux per side Φ = π L̄ A
//! (Φ = ∫_A ∫_{H²} L cos θ dω dA, L̄ the mean radiance over the triangle).

use super::emission_image::ImageEmission;
use super::point::spectral_integral;
use super::sampler::LightBounds;
use super::selection_flux::{max_value, visible_flux};
use super::LightSample;
use crate::geometry::Bounds3;
use crate::math::PI;
use crate::sampling::warp::uniform_triangle;
use crate::simd::{Mask, Real, V3};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// One emitting triangle. Emitting meshes become one `AreaLight` per triangle so the light
/// sampler can pick triangles in proportion to their power.
#[derive(Clone, Debug)]
pub struct AreaLight {
    /// Vertices [scene units].
    pub p: [Vec3; 3],
    /// Unit normal of the emitting (front) side.
    pub n: Vec3,
    /// Area [scene units²].
    pub area: f32,
    /// Spectral shape of the radiance.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` into radiance L.
    pub scale: f32,
    /// Emits from both sides.
    pub two_sided: bool,
    /// The image whose texels replace `spectrum`, if any (`spectrum` is then the colour space's
    /// white, for the power).
    pub image: Option<Box<ImageEmission>>,
}

impl AreaLight {
    /// A triangle with corners `p` emitting a constant radiance of 1 (test scenes).
    #[cfg(test)]
    pub(crate) fn constant_triangle(p: [Vec3; 3], two_sided: bool) -> super::Light {
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        super::Light::Area(AreaLight {
            p,
            n: n.normalize(),
            area: 0.5 * n.length(),
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 1.0,
            two_sided,
            image: None,
        })
    }
    /// Radiance leaving the light at the surface point with texture coordinates `uv` toward the
    /// direction `w` (pointing away from the light): 0 behind a one-sided light.
    #[inline]
    pub fn radiance(&self, w: Vec3, uv: Vec2, lambdas: &SampledWavelengths) -> SampledSpectrum {
        if !self.two_sided && self.n.dot(w) <= 0.0 {
            return SampledSpectrum::zero();
        }
        match &self.image {
            None => self.spectrum.sample(lambdas) * self.scale,
            Some(image) => image.image.radiance(uv, lambdas) * self.scale,
        }
    }

    pub(super) fn sample_li(&self, p: Vec3, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let s = TriangleLightLanes::<f32>::splat(self).sample(p.into(), u.x, u.y);
        if !s.valid {
            return None;
        }
        let li = match &self.image {
            None => self.spectrum.sample(w) * self.scale,
            // The image at the point `sample` picked (the same barycentrics).
            Some(image) => image.radiance_at(uniform_triangle(u.x, u.y), w) * self.scale,
        };
        (!li.is_black()).then(|| LightSample {
            li,
            wi: s.wi.into(),
            pdf: s.pdf,
            p_light: s.p_light.into(),
            dist: s.dist,
        })
    }

    /// Solid-angle density with which `sample_li` at `p` picks the direction `wi` (unit):
    /// r² / (|cos θ_l| A) at the point where the ray from `p` along `wi` meets the triangle, 0
    /// when it misses (pbrt-v4 `Triangle::PDF(ctx, wi)`, which intersects the shape likewise).
    pub fn pdf_li(&self, p: Vec3, wi: Vec3) -> f32 {
        let Some(t) = self.ray_distance(p, wi) else { return 0.0 };
        let cos_l = self.n.dot(wi).abs();
        if cos_l == 0.0 {
            return 0.0;
        }
        t * t / (cos_l * self.area)
    }

    /// Distance along the unit direction `d` from `o` to the triangle, if the ray meets it
    /// (Möller & Trumbore 1997).
    fn ray_distance(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let (e1, e2) = (self.p[1] - self.p[0], self.p[2] - self.p[0]);
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let tv = o - self.p[0];
        let u = tv.dot(pv) * inv;
        let qv = tv.cross(e1);
        let v = d.dot(qv) * inv;
        // A small tolerance: the caller found the hit with another (watertight) test, and a
        // direction grazing an edge must not lose its density to rounding.
        const EDGE: f32 = 1e-5;
        if u < -EDGE || v < -EDGE || u + v > 1.0 + EDGE {
            return None;
        }
        let t = e2.dot(qv) * inv;
        (t > 0.0).then_some(t)
    }

    /// pbrt-v4's `DiffuseAreaLight::Phi` for the power sampler: π L A per emitting side, L's
    /// spectrum by [`visible_flux`] (see `selection_flux`); for an image, L is its mean
    /// luminance times the white (the whole image's mean, as pbrt-v4's `Phi`, though the
    /// triangle may show only part of it).
    pub fn power(&self) -> f32 {
        self.power_given(visible_flux(&self.spectrum))
    }

    /// [`AreaLight::power`] given [`visible_flux`] of its spectrum (shared by every triangle of
    /// a mesh, so the light sampler evaluates it once per spectrum).
    pub fn power_given(&self, visible_flux: f32) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        let image = self.image.as_ref().map_or(1.0, |i| i.image.mean_luminance());
        PI * self.area * sides * self.scale * visible_flux * image
    }

    /// pbrt-v4's `DiffuseAreaLight::Bounds` flux: π A scale MaxValue(L) for one side, two-sided
    /// or not, an image's mean channel value standing in for MaxValue (see `selection_flux`).
    pub fn bound_flux(&self) -> f32 {
        self.bound_flux_given(max_value(&self.spectrum))
    }

    /// [`AreaLight::bound_flux`] given MaxValue of its spectrum (shared by a mesh's triangles).
    pub fn bound_flux_given(&self, max_value: f32) -> f32 {
        let l = self.image.as_ref().map_or(max_value, |i| i.image.mean_channel());
        PI * self.area * self.scale * l
    }

    /// Bounds for many-light sampling, emitting flux `phi`: its box, its normal and θ_e = π/2.
    pub(super) fn bounds(&self, phi: f32) -> LightBounds {
        let bounds = self.p.iter().fold(Bounds3::EMPTY, |b, &q| b.union_point(q));
        LightBounds { bounds, w: self.n, phi, cos_theta_o: 1.0, cos_theta_e: 0.0, two_sided: self.two_sided }
    }

    /// The radiance scale that makes a set of triangles of total area `area` emit `flux` [W]
    /// over 360–830 nm: L = Φ / (π A · sides · ∫s dλ). Works for any transformed mesh, since it
    /// uses world-space areas.
    pub fn scale_for_flux(flux: f32, spectrum: &Spectrum, area: f32, two_sided: bool) -> f32 {
        let sides = if two_sided { 2.0 } else { 1.0 };
        let denom = PI * area * sides * spectral_integral(spectrum);
        if denom > 0.0 {
            flux / denom
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::Rng;

    fn triangle() -> AreaLight {
        let p = [Vec3::new(0.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(0.0, 2.5, 1.5)];
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        AreaLight {
            p,
            n: n.normalize(),
            area: 0.5 * n.length(),
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 1.0,
            two_sided: true,
            image: None,
        }
    }

    #[test]
    fn pdf_li_from_the_direction_alone_matches_the_sampled_density() {
        // The sample's density is r²/(|cos θ_l| A) at the sampled point; pdf_li must find the
        // same point from (p, ωi) by intersecting the triangle.
        let light = triangle();
        let w = SampledWavelengths::sample_visible(0.5);
        let mut rng = Rng::new(3, 5);
        for _ in 0..10_000 {
            let p = Vec3::new(rng.uniform() * 4.0 - 2.0, rng.uniform() * 4.0 - 2.0, rng.uniform() * 4.0 - 2.0);
            let Some(ls) = light.sample_li(p, Vec2::new(rng.uniform(), rng.uniform()), &w) else { continue };
            let pdf = light.pdf_li(p, ls.wi);
            assert!((pdf - ls.pdf).abs() <= 1e-3 * ls.pdf, "p {p}: pdf_li {pdf} vs sampled {}", ls.pdf);
        }
        // Directions that miss the triangle have density 0.
        assert_eq!(light.pdf_li(Vec3::ZERO, -Vec3::Y), 0.0);
        assert_eq!(light.pdf_li(Vec3::ZERO, Vec3::new(5.0, 1.0, 0.0).normalize()), 0.0);
    }
}

/// An emitting triangle per lane (each lane's path may have picked a different one).
#[derive(Clone, Copy, Debug)]
pub struct TriangleLightLanes<R: Real> {
    /// Vertices.
    pub p: [V3<R>; 3],
    /// Unit normal of the front side.
    pub n: V3<R>,
    /// Area.
    pub area: R,
    /// Emits from both sides.
    pub two_sided: R::Mask,
}

/// A point sampled on each lane's triangle as seen from a reference point.
#[derive(Clone, Copy, Debug)]
pub struct TriangleLightSample<R: Real> {
    /// The point on the light.
    pub p_light: V3<R>,
    /// Unit direction from the reference point to it.
    pub wi: V3<R>,
    /// Solid-angle density [1/sr].
    pub pdf: R,
    /// Distance to it.
    pub dist: R,
    /// Lanes whose sample exists and whose side of the light emits toward the reference point.
    pub valid: R::Mask,
}

impl<R: Real> TriangleLightLanes<R> {
    /// `light` in every lane.
    pub fn splat(light: &AreaLight) -> Self {
        Self {
            p: light.p.map(V3::splat),
            n: V3::splat(light.n),
            area: R::splat(light.area),
            two_sided: R::Mask::splat(light.two_sided),
        }
    }

    /// Uniform area sampling, converted to solid angle: pdf_ω = r² / (|cos θ_l| A).
    #[inline(always)]
    pub fn sample(&self, p: V3<R>, ux: R, uy: R) -> TriangleLightSample<R> {
        let b = uniform_triangle(ux, uy);
        let p_light = self.p[0] * b[0] + self.p[1] * b[1] + self.p[2] * b[2];
        let d = p_light - p;
        let r2 = d.length_squared();
        let dist = r2.sqrt();
        let wi = d * (R::splat(1.0) / dist);
        let cos_front = -self.n.dot(wi);
        let cos_l = cos_front.abs();
        let pdf = r2 / (cos_l * self.area);
        let zero = R::splat(0.0);
        let emits = self.two_sided | zero.lt(cos_front);
        let valid = zero.lt(r2) & zero.lt(cos_l) & pdf.is_finite() & emits;
        TriangleLightSample { p_light, wi, pdf, dist, valid }
    }
}

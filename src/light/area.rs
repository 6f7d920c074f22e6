//! Diffuse area light: one emissive triangle of constant radiance L [W/(sr·m²·nm)] on its front
//! side (or both). Flux per side Φ = π L A (lecture: Φ = ∫_A ∫_{H²} L cos θ dω dA).

use super::point::spectral_integral;
use super::LightSample;
use crate::math::PI;
use crate::sampling::warp::sample_uniform_triangle;
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
    /// Index of the mesh this triangle belongs to, and the triangle's index in it.
    pub mesh: u32,
    /// See `mesh`.
    pub prim: u32,
}

impl AreaLight {
    /// Radiance leaving the light at a point with normal-side test against direction `w`
    /// (pointing away from the light).
    #[inline]
    pub fn radiance(&self, w: Vec3, lambdas: &SampledWavelengths) -> SampledSpectrum {
        if !self.two_sided && self.n.dot(w) <= 0.0 {
            return SampledSpectrum::zero();
        }
        self.spectrum.sample(lambdas) * self.scale
    }

    pub(super) fn sample_li(&self, p: Vec3, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        // Uniform area sampling, converted to solid angle: pdf_ω = r² / (|cos θ_l| A).
        let b = sample_uniform_triangle(u);
        let p_light = self.p[0] * b[0] + self.p[1] * b[1] + self.p[2] * b[2];
        let d = p_light - p;
        let r2 = d.length_squared();
        if r2 == 0.0 {
            return None;
        }
        let dist = r2.sqrt();
        let wi = d / dist;
        let cos_l = self.n.dot(-wi).abs();
        if cos_l == 0.0 {
            return None;
        }
        let pdf = r2 / (cos_l * self.area);
        let li = self.radiance(-wi, w);
        if li.is_black() || !pdf.is_finite() {
            return None;
        }
        Some(LightSample { li, wi, pdf, p_light, dist })
    }

    /// Solid-angle density of `sample_li` at `p` choosing the point `p_light` (normal `n_light`).
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        let r2 = (p_light - p).length_squared();
        let cos_l = n_light.normalize_or_zero().dot(-wi).abs();
        if cos_l == 0.0 {
            return 0.0;
        }
        r2 / (cos_l * self.area)
    }

    /// Φ = π L A per emitting side [W] (with L integrated over 360–830 nm).
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        PI * self.area * sides * self.scale * spectral_integral(&self.spectrum)
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

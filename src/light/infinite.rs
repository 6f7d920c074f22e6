//! Infinite lights: radiance arriving from every direction at infinity.

use super::selection_flux::visible_flux;
use super::LightSample;
use crate::math::PI;
use crate::sampling::warp::sample_uniform_sphere;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// Constant radiance L [W/(sr·m²·nm)] from all directions. An unoccluded plane receives
/// E = ∫_{H²} L cos θ dω = π L.
#[derive(Clone, Debug)]
pub struct UniformInfiniteLight {
    /// Spectral shape of the radiance.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` into radiance.
    pub scale: f32,
}

/// Density of uniform sphere sampling [1/sr].
pub(super) fn uniform_sphere_pdf() -> f32 {
    1.0 / (4.0 * PI)
}

impl UniformInfiniteLight {
    /// Radiance arriving along any escaping ray.
    pub fn le(&self, w: &SampledWavelengths) -> SampledSpectrum {
        self.spectrum.sample(w) * self.scale
    }

    pub(super) fn sample_li(&self, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let wi = sample_uniform_sphere(u);
        Some(LightSample { li: self.le(w), wi, pdf: uniform_sphere_pdf(), p_light: Vec3::ZERO, dist: f32::INFINITY })
    }

    /// pbrt-v4's `UniformInfiniteLight::Phi` for the power sampler: 4π² r² L over the scene's
    /// bounding sphere of radius `scene_radius` (see `selection_flux`).
    pub(super) fn power(&self, scene_radius: f32) -> f32 {
        4.0 * PI * PI * scene_radius * scene_radius * self.scale * visible_flux(&self.spectrum)
    }
}

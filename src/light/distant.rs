//! Distant (directional) light: irradiance E [W/(m²·nm)] on a surface perpendicular to it,
//! E cos θ on a tilted one (Lambert's law).

use super::selection_flux::visible_flux;
use super::LightSample;
use crate::math::PI;
use crate::spectrum::{SampledWavelengths, Spectrum};
use glam::Vec3;
use std::sync::Arc;

/// Light arriving from one direction at infinity.
#[derive(Clone, Debug)]
pub struct DistantLight {
    /// Unit direction *toward* the light.
    pub to_light: Vec3,
    /// Spectral shape of the irradiance.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` into perpendicular irradiance E.
    pub scale: f32,
}

impl DistantLight {
    pub(super) fn sample_li(&self, w: &SampledWavelengths) -> Option<LightSample> {
        Some(LightSample {
            li: self.spectrum.sample(w) * self.scale,
            wi: self.to_light,
            pdf: 1.0,
            p_light: Vec3::ZERO,
            dist: f32::INFINITY,
        })
    }

    /// pbrt-v4's `DistantLight::Phi` for the power sampler: E π r² over the scene's bounding
    /// sphere of radius `scene_radius` (see `selection_flux`).
    pub(super) fn power(&self, scene_radius: f32) -> f32 {
        PI * scene_radius * scene_radius * self.scale * visible_flux(&self.spectrum)
    }
}

//! Distant (directional) light: irradiance E [W/(m²·nm)] on a surface perpendicular to it,
//! E cos θ on a tilted one (Lambert's law).

use super::point::spectral_integral;
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

    pub(super) fn power(&self, scene_radius: f32) -> f32 {
        PI * scene_radius * scene_radius * self.scale * spectral_integral(&self.spectrum)
    }
}

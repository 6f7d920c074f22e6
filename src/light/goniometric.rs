//! Goniometric light: a point light whose intensity over directions is an equal-area image
//! (pbrt-v4's `goniometric`): I(ω) = scale · s(λ) · Y(ω), Y the image's value (the mean of its
//! RGB) at the nearest pixel of Clarberg's square for the light-space direction with y and z
//! swapped, as pbrt-v4 lays the image out.

use super::point::delta_sample;
use super::sampler::LightBounds;
use super::selection_flux::{max_value, visible_flux};
use super::LightSample;
use crate::image::Image;
use crate::math::{equal_area, PI};
use crate::spectrum::{SampledWavelengths, Spectrum};
use glam::{Mat3, Vec3};
use std::sync::Arc;

/// A point light with an equal-area intensity image.
#[derive(Clone, Debug)]
pub struct GoniometricLight {
    /// Position [scene units].
    pub position: Vec3,
    /// World directions → the image's frame (the light's, y and z swapped).
    image_from_world: Mat3,
    /// Spectral shape of the intensity.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` × image value into intensity I [W/(sr·nm)].
    pub scale: f32,
    /// Side of the square image [pixels].
    size: usize,
    /// The mean of each pixel's channels, row-major from the top row.
    values: Vec<f32>,
}

impl GoniometricLight {
    /// A light at `position` whose frame is `world_from_light` (rotation), intensity
    /// `scale · spectrum · image`. The image must be square (an equal-area map).
    pub fn new(position: Vec3, world_from_light: Mat3, image: &Image, spectrum: Arc<Spectrum>, scale: f32) -> Self {
        let c = image.channels.max(1) as usize;
        let n = c.min(3);
        let values = image
            .data
            .chunks_exact(c)
            .map(|p| p[..n].iter().map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 }).sum::<f32>() / n as f32)
            .collect();
        let swap_yz = Mat3::from_cols(Vec3::X, Vec3::Z, Vec3::Y);
        let image_from_world = (world_from_light * swap_yz).inverse();
        Self { position, image_from_world, spectrum, scale, size: image.width.max(1) as usize, values }
    }

    /// The image's mean value over the sphere (each pixel covers 4π/N sr).
    pub fn mean_value(&self) -> f32 {
        self.values.iter().sum::<f32>() / self.values.len().max(1) as f32
    }

    /// The image's value for the world direction `w` leaving the light.
    fn value(&self, w: Vec3) -> f32 {
        let d = (self.image_from_world * w).normalize_or_zero();
        let uv = equal_area::sphere_to_square(d);
        let px = |t: f32| ((t * self.size as f32) as usize).min(self.size - 1);
        let i = px(uv.y) * self.size + px(uv.x);
        self.values.get(i).copied().unwrap_or(0.0)
    }

    pub(super) fn sample_li(&self, p: Vec3, w: &SampledWavelengths) -> Option<LightSample> {
        let value = self.value(p - self.position);
        if value <= 0.0 {
            return None;
        }
        delta_sample(self.position, p, self.spectrum.sample(w) * (self.scale * value))
    }

    /// pbrt-v4's `GoniometricLight::Phi` for the power sampler: 4π I times the image's mean
    /// (see `selection_flux`).
    pub(super) fn power(&self) -> f32 {
        4.0 * PI * self.scale * self.mean_value() * visible_flux(&self.spectrum)
    }

    /// pbrt-v4's `GoniometricLight::Bounds` flux: 4π scale MaxValue(I) times the image's mean.
    pub(super) fn bound_flux(&self) -> f32 {
        4.0 * PI * self.scale * self.mean_value() * max_value(&self.spectrum)
    }

    /// Bounds for many-light sampling, emitting flux `phi`: a point emitting over the whole
    /// sphere.
    pub(super) fn bounds(&self, phi: f32) -> LightBounds {
        LightBounds::isotropic_point(self.position, phi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intensity_follows_the_image_in_pbrt_v4s_layout() {
        // A 2×2 image: the four quadrants of the square; with y and z swapped, light-space +y is
        // the square's centre (all four quadrants meet there), +x lies in the quadrants u > ½
        // and −z (the square's −y) in those with v < ½.
        let data = [1.0f32, 2.0, 3.0, 4.0].iter().flat_map(|&v| [v; 3]).collect();
        let image = Image { width: 2, height: 2, channels: 3, data };
        let l = GoniometricLight::new(Vec3::ZERO, Mat3::IDENTITY, &image, Arc::new(Spectrum::constant(1.0)), 2.0);
        assert!((l.mean_value() - 2.5).abs() < 1e-6);
        // Row 0 (v < ½) holds 1 and 2, row 1 holds 3 and 4.
        let at = |d: Vec3| l.value(d);
        assert_eq!(at(Vec3::new(0.5, 0.1, -0.5)), 2.0); // u > ½, v < ½
        assert_eq!(at(Vec3::new(-0.5, 0.1, -0.5)), 1.0);
        assert_eq!(at(Vec3::new(-0.5, 0.1, 0.5)), 3.0);
        assert_eq!(at(Vec3::new(0.5, 0.1, 0.5)), 4.0);
        // I / r² at distance 2 toward the "4" quadrant, times the scale.
        let w = SampledWavelengths::sample_uniform(0.3);
        let s = l.sample_li(Vec3::new(1.0, 0.2, 1.0).normalize() * 2.0, &w).unwrap();
        assert!((s.li.to_array()[0] - 2.0 * 4.0 / 4.0).abs() < 1e-5, "{:?}", s.li);
    }
}

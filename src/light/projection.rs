//! Projection light: a point light that projects an image like a slide projector (pbrt-v4's
//! `projection`). The image fills the screen window of a perspective projection with field of
//! view `fov` along the shorter image axis, looking down the light's +z; a direction's intensity
//! is its nearest pixel's RGB, as an illuminant spectrum of the colour space, times `scale`.
//! Row 0 of the image is at the top (light-space +y), as pbrt-v4 flips y.

use super::point::delta_sample;
use super::sampler::LightBounds;
use super::selection_flux::visible_flux;
use super::texel_spectrum::TexelSpectrum;
use super::LightSample;
use crate::image::Image;
use crate::spectrum::{ColorSpace, SampledWavelengths, Spectrum};
use glam::{Mat3, Vec3};
use std::sync::Arc;

/// Directions closer than this to the light's image plane (z ≤ it) receive nothing (pbrt-v4's
/// `hither`).
const HITHER: f32 = 1e-3;

/// A point light projecting an RGB image.
#[derive(Clone, Debug)]
pub struct ProjectionLight {
    /// Position [scene units].
    pub position: Vec3,
    /// World directions → the light's frame.
    light_from_world: Mat3,
    /// tan(fov / 2).
    tan_half_fov: f32,
    /// The screen window [x0, x1, y0, y1] at unit distance before the tan(fov/2) scale.
    screen: [f32; 4],
    width: usize,
    height: usize,
    texels: Vec<TexelSpectrum>,
    /// Mean over pixels of Y × cos³θ (the pixels' share of the solid angle), for the power.
    mean_y_cos3: f32,
    /// Mean over pixels of their largest channel (pbrt-v4's `ProjectionLight::Bounds` flux).
    mean_max_channel: f32,
    /// The colour space's white illuminant (unit luminance).
    white: Arc<Spectrum>,
    /// Multiplier turning the texels' spectra into intensity I [W/(sr·nm)].
    pub scale: f32,
}

impl ProjectionLight {
    /// A light at `position` with frame `world_from_light` (rotation), field of view `fov_deg`,
    /// projecting `image` (its RGB an illuminant of `space`) times `scale`.
    pub fn new(
        position: Vec3,
        world_from_light: Mat3,
        fov_deg: f32,
        image: &Image,
        space: &'static ColorSpace,
        scale: f32,
    ) -> Self {
        let (width, height) = (image.width.max(1) as usize, image.height.max(1) as usize);
        let aspect = width as f32 / height as f32;
        let screen = if aspect > 1.0 { [-aspect, aspect, -1.0, 1.0] } else { [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect] };
        let c = image.channels.max(1) as usize;
        let tan_half_fov = (fov_deg.to_radians() * 0.5).tan();
        let mut rgbs = Vec::with_capacity(width * height);
        let (mut sum, mut max_channels) = (0.0f64, 0.0f64);
        for (i, p) in image.data.chunks_exact(c).enumerate() {
            let px = |k: usize| p.get(k.min(c - 1)).copied().filter(|v| v.is_finite()).unwrap_or(0.0).max(0.0);
            let rgb = [px(0), px(1), px(2)];
            rgbs.push(rgb);
            max_channels += f64::from(rgb[0].max(rgb[1]).max(rgb[2]));
            let (x, y) = ((i % width) as f32 + 0.5, (i / width) as f32 + 0.5);
            let sx = (screen[0] + (screen[1] - screen[0]) * x / width as f32) * tan_half_fov;
            let sy = (screen[2] + (screen[3] - screen[2]) * y / height as f32) * tan_half_fov;
            let cos = 1.0 / (1.0 + sx * sx + sy * sy).sqrt();
            sum += f64::from(space.rgb_to_xyz(Vec3::from_array(rgb)).y * cos * cos * cos);
        }
        let mean_y_cos3 = (sum / rgbs.len().max(1) as f64) as f32;
        let mean_max_channel = (max_channels / rgbs.len().max(1) as f64) as f32;
        let texels = TexelSpectrum::from_rgbs(&rgbs, space);
        Self {
            position,
            light_from_world: world_from_light.inverse(),
            tan_half_fov,
            screen,
            width,
            height,
            texels,
            mean_y_cos3,
            mean_max_channel,
            white: Arc::new(space.illuminant.clone()),
            scale,
        }
    }

    /// Area of the screen window on the plane at unit distance (pbrt-v4's A).
    pub fn screen_area(&self) -> f32 {
        let [x0, x1, y0, y1] = self.screen;
        (x1 - x0) * (y1 - y0) * self.tan_half_fov * self.tan_half_fov
    }

    /// The texel lit along world direction `w` from the light, if any: the image is upright in
    /// the light's frame (row 0 at +y).
    fn texel(&self, w: Vec3) -> Option<&TexelSpectrum> {
        let d = self.light_from_world * w.normalize_or_zero();
        if d.z < HITHER {
            return None;
        }
        let (sx, sy) = (d.x / (d.z * self.tan_half_fov), d.y / (d.z * self.tan_half_fov));
        let [x0, x1, y0, y1] = self.screen;
        if !(x0..=x1).contains(&sx) || !(y0..=y1).contains(&sy) {
            return None;
        }
        let u = (sx - x0) / (x1 - x0);
        let v = (y1 - sy) / (y1 - y0);
        let x = ((u * self.width as f32) as usize).min(self.width - 1);
        let y = ((v * self.height as f32) as usize).min(self.height - 1);
        self.texels.get(y * self.width + x)
    }

    pub(super) fn sample_li(&self, p: Vec3, w: &SampledWavelengths) -> Option<LightSample> {
        let t = self.texel(p - self.position)?;
        delta_sample(self.position, p, t.sample(w) * self.white.sample(w) * self.scale)
    }

    /// Luminous-weighted flux factor: ∫ Y(ω) dω = A × mean(Y cos³θ) (a pixel of the screen
    /// subtends cos³θ/d² per unit area at unit distance), pbrt-v4's k_e for `power`.
    pub fn k_e(&self) -> f32 {
        self.screen_area() * self.mean_y_cos3
    }

    /// pbrt-v4's `ProjectionLight::Phi` for the power sampler, the texels' spectra as their
    /// luminance times the white (see `selection_flux`).
    pub(super) fn power(&self) -> f32 {
        self.scale * self.k_e() * visible_flux(&self.white)
    }

    /// pbrt-v4's `ProjectionLight::Bounds` flux: scale times the mean over pixels of their
    /// largest channel, with no solid angle (see `selection_flux`).
    pub(super) fn bound_flux(&self) -> f32 {
        self.scale * self.mean_max_channel
    }

    /// Bounds for many-light sampling with flux `phi` ([`ProjectionLight::bound_flux`]), as
    /// pbrt-v4's `ProjectionLight::Bounds`: a point emitting along the light's +z (θ_o = 0) out
    /// to the angle of the screen window's corner (θ_e).
    pub(super) fn bounds(&self, phi: f32) -> LightBounds {
        let [_, x1, _, y1] = self.screen;
        let cos_theta_e = Vec3::new(x1 * self.tan_half_fov, y1 * self.tan_half_fov, 1.0).normalize().z;
        let w = (self.light_from_world.inverse() * Vec3::Z).normalize();
        let bounds = crate::geometry::Bounds3::EMPTY.union_point(self.position);
        LightBounds { bounds, w, phi, cos_theta_o: 1.0, cos_theta_e, two_sided: false }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slide_is_upright_and_bounded_by_the_field_of_view() {
        // 2 × 1 image: left pixel red, right pixel blue, 90° fov along the short (vertical) axis:
        // the window is x ∈ [−2, 2], y ∈ [−1, 1] at unit distance.
        let image = Image { width: 2, height: 1, channels: 3, data: vec![1.0, 0.0, 0.0, 0.0, 0.0, 1.0] };
        let l = ProjectionLight::new(Vec3::ZERO, Mat3::IDENTITY, 90.0, &image, ColorSpace::srgb(), 1.0);
        assert!((l.screen_area() - 8.0).abs() < 1e-5);
        let red = l.texel(Vec3::new(-1.0, 0.0, 1.0)).copied();
        let blue = l.texel(Vec3::new(1.5, 0.5, 1.0)).copied();
        let w = SampledWavelengths::sample_uniform(0.5);
        let (r, b) = (red.unwrap().sample(&w).to_array(), blue.unwrap().sample(&w).to_array());
        assert!(r != b, "left and right pixels differ");
        // Outside the window (x beyond 2, y beyond 1) or behind: nothing.
        assert!(l.texel(Vec3::new(2.5, 0.0, 1.0)).is_none());
        assert!(l.texel(Vec3::new(0.0, 1.2, 1.0)).is_none());
        assert!(l.texel(Vec3::new(0.0, 0.0, -1.0)).is_none());
    }
}

//! Environment map: radiance from every direction given by an equirectangular (latitude–longitude)
//! RGB image, importance-sampled in proportion to luminance × sin θ (the sin θ is the Jacobian of
//! the equirectangular map, so bright texels near the poles are not over-sampled).

use super::LightSample;
use crate::image::Image;
use crate::material::ImageTexture;
use crate::math::PI;
use crate::sampling::Distribution2D;
use crate::spectrum::{ColorSpace, RgbKind, SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Mat3, Vec2, Vec3};
use std::sync::Arc;

/// An image-based infinite light.
#[derive(Clone, Debug)]
pub struct EnvMapLight {
    texture: ImageTexture,
    distribution: Arc<Distribution2D>,
    /// Light space → world (rotation only).
    world_from_light: Mat3,
    space: &'static ColorSpace,
    /// Multiplier on the image's radiance.
    pub scale: f32,
}

impl EnvMapLight {
    /// An environment from a linear RGB image (+z up in light space, u = φ/2π, v = θ/π).
    pub fn new(image: Arc<Image>, world_from_light: Mat3, scale: f32, space: &'static ColorSpace) -> Self {
        let (w, h) = (image.width as usize, image.height as usize);
        let c = image.channels as usize;
        let mut f = vec![0.0f32; w * h];
        for y in 0..h {
            let sin_theta = (PI * (y as f32 + 0.5) / h as f32).sin();
            for x in 0..w {
                let o = (y * w + x) * c;
                let rgb = if c >= 3 {
                    Vec3::new(image.data[o], image.data[o + 1], image.data[o + 2])
                } else {
                    Vec3::splat(image.data[o])
                };
                let lum = space.rgb_to_xyz(rgb.max(Vec3::ZERO)).y;
                f[y * w + x] = lum.max(0.0) * sin_theta;
            }
        }
        // Importance is never zero where radiance is not, so MIS with BSDF sampling stays unbiased.
        let distribution = Arc::new(Distribution2D::new(&f, w, h));
        Self { texture: ImageTexture { image, scale: 1.0 }, distribution, world_from_light, space, scale }
    }

    fn dir_to_uv(&self, d_world: Vec3) -> (Vec2, f32) {
        let d = self.world_from_light.transpose() * d_world.normalize();
        let theta = d.z.clamp(-1.0, 1.0).acos();
        let mut phi = d.y.atan2(d.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        (Vec2::new(phi / (2.0 * PI), theta / PI), theta.sin())
    }

    /// Radiance arriving from direction `d` (world, pointing away from the scene).
    pub fn le(&self, d: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        let (uv, _) = self.dir_to_uv(d);
        // ImageTexture's v runs bottom-up; the map's θ runs top-down.
        let rgb = self.texture.rgb(Vec2::new(uv.x, 1.0 - uv.y)).map(|c| c.max(0.0));
        Spectrum::from_rgb(rgb, RgbKind::Illuminant, self.space).sample(w) * self.scale
    }

    pub(super) fn sample_li(&self, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let (uv, pdf_uv) = self.distribution.sample(u);
        if pdf_uv == 0.0 {
            return None;
        }
        let (theta, phi) = (uv.y * PI, uv.x * 2.0 * PI);
        let sin_theta = theta.sin();
        if sin_theta == 0.0 {
            return None;
        }
        let d_light = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), theta.cos());
        let wi = (self.world_from_light * d_light).normalize();
        // Change of variables (u, v) → ω: dω = 2π² sin θ du dv.
        let pdf = pdf_uv / (2.0 * PI * PI * sin_theta);
        Some(LightSample { li: self.le(wi, w), wi, pdf, p_light: Vec3::ZERO, dist: f32::INFINITY })
    }

    /// Solid-angle density of `sample_li` choosing direction `wi`.
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        let (uv, sin_theta) = self.dir_to_uv(wi);
        if sin_theta == 0.0 {
            return 0.0;
        }
        self.distribution.pdf(uv) / (2.0 * PI * PI * sin_theta)
    }

    pub(super) fn power(&self, scene_radius: f32) -> f32 {
        // Φ ≈ π r² ∫ L dω with ∫ L dω = 2π² ∫∫ lum(u, v) sin θ du dv; × the wavelength range, to
        // be comparable with the other lights' ∫ dλ (only used to choose between lights).
        let range = crate::spectrum::LAMBDA_MAX - crate::spectrum::LAMBDA_MIN;
        PI * scene_radius * scene_radius * self.scale * 2.0 * PI * PI * self.distribution.integral() * range
    }
}

//! Environment map: radiance from every direction given by an equirectangular (latitude–longitude)
//! RGB image, importance-sampled in proportion to luminance × sin θ (the sin θ is the Jacobian of
//! the equirectangular map, so bright texels near the poles are not over-sampled).
//!
//! Each texel's RGB is upsampled once, at load, to a Jakob–Hanika illuminant spectrum
//! (`s(λ) = scale · σ(c₀x² + c₁x + c₂) · W(λ)`, W the colour space's white with Y = 1), so a
//! lookup evaluates one sigmoid per wavelength and never runs the RGB→spectrum fit. Lookups take
//! the nearest texel: radiance is then piecewise constant exactly like the sampling density.

use super::LightSample;
use crate::image::Image;
use crate::math::PI;
use crate::sampling::Distribution2D;
use crate::spectrum::{
    ColorSpace, RgbToSpectrumTable, SampledSpectrum, SampledWavelengths, Spectrum, LAMBDA_MAX, LAMBDA_MIN,
};
use glam::{Mat3, Vec2, Vec3};
use rayon::prelude::*;
use std::sync::Arc;

/// One texel's spectrum shape: `scale · σ(poly(x))`, x = (λ − 360 nm)/470 nm (times the white).
#[derive(Clone, Copy, Debug, Default)]
struct TexelSpectrum {
    c: [f32; 3],
    scale: f32,
}

impl TexelSpectrum {
    /// The unbounded form of `Spectrum::from_rgb` (m = max(rgb), 2m · σ(fit of rgb/2m)), with the
    /// coefficients from the colour space's Jakob–Hanika table (trilinear, no Newton refinement:
    /// a 2k × 1k map has two million texels; accuracy in docs/colour.md).
    fn from_rgb(rgb: [f32; 3], table: &RgbToSpectrumTable) -> Self {
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        if !(m > 0.0 && m.is_finite()) {
            return Self::default();
        }
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            // σ(0) = ½, so a constant m is scale 2m with a zero polynomial.
            return Self { c: [0.0; 3], scale: 2.0 * m };
        }
        let scaled = rgb.map(|v| (v / (2.0 * m)) as f64);
        let poly = table.lookup(scaled);
        Self { c: poly.c.map(|c| c as f32), scale: 2.0 * m }
    }

    #[inline]
    fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        if self.scale == 0.0 {
            return SampledSpectrum::zero();
        }
        let span = LAMBDA_MAX - LAMBDA_MIN;
        SampledSpectrum::new(w.lambda.map(|l| {
            let x = (l - LAMBDA_MIN) / span;
            let t = (self.c[0] * x + self.c[1]) * x + self.c[2];
            let s = if t.is_infinite() { (t > 0.0) as u8 as f32 } else { 0.5 + t / (2.0 * (1.0 + t * t).sqrt()) };
            self.scale * s
        }))
    }
}

/// An image-based infinite light.
#[derive(Clone, Debug)]
pub struct EnvMapLight {
    width: usize,
    height: usize,
    texels: Arc<Vec<TexelSpectrum>>,
    /// Luminance Y of each texel (∫ȳ normalisation of `spectrum::cie`: Y = 1 for RGB white).
    luminance: Arc<Vec<f32>>,
    distribution: Arc<Distribution2D>,
    /// Light space → world (a rotation; + z is the map's zenith).
    world_from_light: Mat3,
    light_from_world: Mat3,
    /// The colour space's white illuminant (unit luminance).
    white: Arc<Spectrum>,
    /// Multiplier on the image's radiance.
    pub scale: f32,
}

impl EnvMapLight {
    /// An environment from a linear RGB (or grey) image: +z up in light space, u = φ/2π across,
    /// v = θ/π down (row 0 is the zenith). Radiance of a texel is `scale` × its RGB upsampled as
    /// an illuminant of `space` (RGB (1,1,1) is the space's white at luminance Y = 1).
    /// Negative and non-finite samples count as 0.
    pub fn new(image: &Image, world_from_light: Mat3, scale: f32, space: &'static ColorSpace) -> Self {
        let (w, h) = (image.width.max(1) as usize, image.height.max(1) as usize);
        let c = image.channels as usize;
        let rgb_at = |i: usize| -> [f32; 3] {
            let o = i * c;
            let px = |k: usize| image.data.get(o + k).copied().unwrap_or(0.0);
            let rgb = if c >= 3 { [px(0), px(1), px(2)] } else { [px(0); 3] };
            rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
        };
        // Build (or fetch) the lazily-made table before going parallel: its construction runs
        // rayon jobs inside a OnceLock, and a worker stealing one of ours in the middle of it
        // would re-enter the OnceLock and deadlock.
        let table = space.rgb_to_spectrum_table();
        let texels: Vec<TexelSpectrum> =
            (0..w * h).into_par_iter().map(|i| TexelSpectrum::from_rgb(rgb_at(i), table)).collect();
        let luminance: Vec<f32> = (0..w * h).map(|i| space.rgb_to_xyz(Vec3::from(rgb_at(i))).y.max(0.0)).collect();
        let mut f = vec![0.0f32; w * h];
        for y in 0..h {
            let sin_theta = (PI * (y as f32 + 0.5) / h as f32).sin();
            for x in 0..w {
                // Importance is never zero where radiance is not (luminance weights are positive
                // for every supported space), so NEE alone stays unbiased.
                f[y * w + x] = luminance[y * w + x] * sin_theta;
            }
        }
        let distribution = Arc::new(Distribution2D::new(&f, w, h));
        let light_from_world = world_from_light.inverse();
        Self {
            width: w,
            height: h,
            texels: Arc::new(texels),
            luminance: Arc::new(luminance),
            distribution,
            world_from_light,
            light_from_world,
            white: Arc::new(space.illuminant.clone()),
            scale,
        }
    }

    fn dir_to_uv(&self, d_world: Vec3) -> (Vec2, f32) {
        let d = (self.light_from_world * d_world).normalize_or_zero();
        // sin θ from x, y rather than sin(acos z): near the poles acos loses precision, and
        // sin(π as f32) is negative, which made the density there negative.
        let sin_theta = (d.x * d.x + d.y * d.y).sqrt();
        let theta = sin_theta.atan2(d.z);
        let mut phi = d.y.atan2(d.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        (Vec2::new(phi / (2.0 * PI), theta / PI), sin_theta)
    }

    fn texel(&self, uv: Vec2) -> usize {
        let x = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        y * self.width + x
    }

    fn radiance_at(&self, uv: Vec2, w: &SampledWavelengths) -> SampledSpectrum {
        self.texels[self.texel(uv)].sample(w) * self.white.sample(w) * self.scale
    }

    /// Radiance arriving from direction `d` (world, pointing away from the scene).
    pub fn le(&self, d: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        self.radiance_at(self.dir_to_uv(d).0, w)
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
        Some(LightSample { li: self.radiance_at(uv, w), wi, pdf, p_light: Vec3::ZERO, dist: f32::INFINITY })
    }

    /// A direction drawn by importance sampling (world space) with its solid-angle density, for
    /// tests of the sampling routine; `None` where the map is black.
    pub fn sample_direction(&self, u: Vec2) -> Option<(Vec3, f32)> {
        let w = SampledWavelengths::sample_uniform(0.5);
        self.sample_li(u, &w).map(|s| (s.wi, s.pdf))
    }

    /// Solid-angle density of `sample_li` choosing direction `wi`.
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        let (uv, sin_theta) = self.dir_to_uv(wi);
        if sin_theta == 0.0 {
            return 0.0;
        }
        self.distribution.pdf(uv) / (2.0 * PI * PI * sin_theta)
    }

    /// Illuminance-like integral ∫ Y(ω) cos θ dω over the map's upper hemisphere (+z in light
    /// space), in luminance units Y (without `scale`): what an upward-facing patch receives.
    /// Exact for the nearest-texel map: each row contributes (2π/w)·½(sin²θ₁ − sin²θ₀).
    pub fn upper_hemisphere_y(&self) -> f64 {
        let (w, h) = (self.width, self.height);
        let mut total = 0.0f64;
        for y in 0..h {
            let t0 = std::f64::consts::PI * y as f64 / h as f64;
            let t1 = (std::f64::consts::PI * (y + 1) as f64 / h as f64).min(std::f64::consts::FRAC_PI_2);
            if t1 <= t0 {
                break;
            }
            let row_weight = 0.5 * (t1.sin().powi(2) - t0.sin().powi(2)) * 2.0 * std::f64::consts::PI / w as f64;
            let row: f64 = self.luminance[y * w..(y + 1) * w].iter().map(|&l| l as f64).sum();
            total += row * row_weight;
        }
        total
    }

    pub(super) fn power(&self, scene_radius: f32) -> f32 {
        // Φ ≈ π r² ∫ L dω with ∫ L dω = 2π² ∫∫ lum(u, v) sin θ du dv; × the wavelength range, to
        // be comparable with the other lights' ∫ dλ (only used to choose between lights).
        let range = LAMBDA_MAX - LAMBDA_MIN;
        PI * scene_radius * scene_radius * self.scale * 2.0 * PI * PI * self.distribution.integral() * range
    }
}

//! Image infinite light: radiance from every direction given by an RGB image in one of two
//! layouts (`MapLayout`): pbrt-v4's square equal-area octahedral maps (its `ImageInfiniteLight`,
//! PBR 4th ed. §12.5.2) or prism's latitude–longitude maps for images that are not square.
//!
//! Lookups take the nearest texel (as pbrt-v4's `LookupNearest` with the octahedral wrap), so
//! radiance is piecewise constant over the map exactly like the sampling density, which is
//! piecewise constant over (u, v): on an equal-area map ∝ the texel's mean RGB (pbrt-v4's
//! `GetSamplingDistribution`) less the map's mean (pbrt-v4's MIS compensation), on a
//! latitude–longitude one ∝ its luminance × sin θ (the sin θ is that map's Jacobian, so bright
//! texels near the poles are not over-sampled). The solid-angle
//! density is the (u, v) density divided by the Jacobian dω/(du dv): 4π, or 2π² sin θ.
//! Texels hold their RGB upsampled once as illuminant spectra (`TexelSpectrum`).

use super::map_layout::MapLayout;
use super::texel_spectrum::TexelSpectrum;
use super::LightSample;
use crate::image::Image;
use crate::math::PI;
use crate::sampling::Distribution2D;
use crate::spectrum::{ColorSpace, SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Mat3, Vec2, Vec3};
use std::sync::Arc;

/// pbrt-v4's MIS-compensated sampling weights (Karlík et al., "MIS Compensation: Optimizing
/// Sampling Techniques in Multiple Importance Sampling", ACM TOG 38(6), 2019): each texel's
/// weight v becomes max(v − v̄, min(v̄/1000, v)) with v̄ the mean, leaving the dim, flat part of
/// the map to BSDF sampling. The floor keeps every weight positive where v is, so light
/// sampling alone still covers the whole map (pbrt-v4 uses the uncompensated weights there;
/// prism has one density for both, unbiased either way).
fn mis_compensated(v: &[f32]) -> Vec<f32> {
    let mean = (v.iter().map(|&x| x as f64).sum::<f64>() / v.len().max(1) as f64) as f32;
    v.iter().map(|&x| (x - mean).max((0.001 * mean).min(x))).collect()
}

/// An image's texels as linear RGB, row-major; grey images repeated in three channels, negative
/// and non-finite samples 0.
pub(super) fn image_rgb(image: &Image) -> Vec<[f32; 3]> {
    image_channels(image, [0, 1, 2])
}

/// The image's channels `channels` of every texel as an RGB triple (grey images: their one
/// channel three times), negative and non-finite samples 0.
fn image_channels(image: &Image, channels: [usize; 3]) -> Vec<[f32; 3]> {
    let c = image.channels as usize;
    let n = image.width.max(1) as usize * image.height.max(1) as usize;
    (0..n)
        .map(|i| {
            let px = |k: usize| image.data.get(i * c + k).copied().unwrap_or(0.0);
            let rgb = if c >= 3 { channels.map(px) } else { [px(0); 3] };
            rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
        })
        .collect()
}

fn luminance_of(rgb: &[[f32; 3]], space: &ColorSpace) -> Vec<f32> {
    rgb.iter().map(|&c| space.rgb_to_xyz(Vec3::from(c)).y.max(0.0)).collect()
}

/// ∫ Y(ω) max(cos θ, 0) dω over the upper hemisphere (+z in light space) of the map `image`
/// (laid out by its shape), in luminance units Y: the illuminance an upward-facing patch
/// receives, divided by K_m ∫ȳ dλ. Exact for the nearest-texel map
/// ([`MapLayout::texel_cosine_weight`]).
///
/// With `pbrt_v4_channels`, what pbrt-v4 (`Light::Create`, "illuminance") takes instead: on an
/// equal-area map its midpoint sum, about half the true integral, weighing the channels
/// `pbrt_v4_channels` in the order the file lists them and rounded as pbrt-v4's
/// single-precision accumulator rounds it (`pbrt_v4_equal_area_sum`); pbrt-v4 has no
/// latitude–longitude maps: there the true value.
pub fn image_upper_hemisphere_y(image: &Image, space: &ColorSpace, pbrt_v4_channels: Option<[usize; 3]>) -> f64 {
    let layout = MapLayout::for_size(image.width, image.height);
    if let (Some(channels), MapLayout::EqualArea) = (pbrt_v4_channels, layout) {
        return pbrt_v4_equal_area_sum(image, space, channels);
    }
    let (w, h) = (image.width.max(1) as usize, image.height.max(1) as usize);
    let luminance = luminance_of(&image_rgb(image), space);
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| luminance[y * w + x] > 0.0)
        .map(|(x, y)| luminance[y * w + x] as f64 * layout.texel_cosine_weight(x, y, w, h))
        .sum()
}

/// pbrt-v4's "illuminance" sum over an equal-area map, evaluated as pbrt-v4 evaluates it: for
/// each texel whose centre lies above the horizon (rows outer, columns inner), for each of the
/// image's first three channels `channels` in the order its file lists them, value · luminance
/// weight of red, green, blue in turn · cos θ of the centre, added to one single-precision
/// accumulator, which is then multiplied by 2π/(w h).
///
/// Each texel subtends 4π/(w h), so the value is about half the true integral, and a map
/// scaled to `illuminance` E gives an upward patch about 2E (1.016 · 2E for a constant 16²
/// map, whose midpoint sum is 1.6 % low); scenes are tuned on that, so prism's "illuminance"
/// does the same (its "lux" is the true illuminance). An OpenEXR file lists its channels by
/// name, so they are B, G, R, or A, B, G with alpha: see
/// [`crate::image::exr_channels_in_file_order`]. The accumulator's rounding matters on big
/// maps: once the sum is 2²⁴ times a term, the term is lost, so a 2048² map comes out ~1–3 %
/// low and a 4096² one 5–7 %, and pbrt-v4's scale E / k_e, and its image, that much brighter.
fn pbrt_v4_equal_area_sum(image: &Image, space: &ColorSpace, channels: [usize; 3]) -> f64 {
    let (w, h) = (image.width.max(1) as usize, image.height.max(1) as usize);
    let luminance_weights = space.rgb_to_xyz_matrix.row(1).to_array();
    let texels = image_channels(image, channels);
    let mut sum = 0.0f32;
    for y in 0..h {
        let v = (y as f32 + 0.5) / h as f32;
        for x in 0..w {
            let cos_theta = crate::math::equal_area::square_to_sphere(Vec2::new((x as f32 + 0.5) / w as f32, v)).z;
            if cos_theta > 0.0 {
                for (value, weight) in texels[y * w + x].iter().zip(luminance_weights) {
                    sum += value * weight * cos_theta;
                }
            }
        }
    }
    (sum * (2.0 * PI / (w * h) as f32)) as f64
}

/// An image-based infinite light.
#[derive(Clone, Debug)]
pub struct EnvMapLight {
    layout: MapLayout,
    width: usize,
    height: usize,
    texels: Arc<Vec<TexelSpectrum>>,
    distribution: Arc<Distribution2D>,
    /// ∫ Y dω over the sphere [sr], without `scale`.
    luminance_integral: f64,
    /// Light space → world for sampled directions (a rotation; + z is the map's zenith), and
    /// world → light space for looked-up ones: its inverse, but for pbrt-v4's maps that are not
    /// rotations ([`Self::with_pbrt_v4_direction_maps`]).
    world_from_light: Mat3,
    light_from_world: Mat3,
    /// Whether `world_from_light` may change a direction's length (see
    /// [`Self::with_pbrt_v4_direction_maps`]).
    stretches: bool,
    /// The colour space's white illuminant (unit luminance).
    white: Arc<Spectrum>,
    /// Multiplier on the image's radiance.
    pub scale: f32,
}

impl EnvMapLight {
    /// An environment from a linear RGB (or grey) image, laid out by its shape
    /// ([`MapLayout::for_size`]: square images are equal-area). Radiance of a texel is `scale` ×
    /// its RGB upsampled as an illuminant of `space` (RGB (1,1,1) is the space's white at
    /// luminance Y = 1). Negative and non-finite samples count as 0.
    pub fn new(image: &Image, world_from_light: Mat3, scale: f32, space: &'static ColorSpace) -> Self {
        let layout = MapLayout::for_size(image.width, image.height);
        let (w, h) = (image.width.max(1) as usize, image.height.max(1) as usize);
        let rgb = image_rgb(image);
        let rgb_at = |i: usize| rgb[i];
        let texels = TexelSpectrum::from_rgbs(&rgb[..w * h], space);
        let luminance = luminance_of(&rgb, space);
        // The importance is positive wherever radiance is (luminance weights are positive for
        // every supported space), so light sampling alone stays unbiased.
        let (f, luminance_integral) = match layout {
            MapLayout::EqualArea => {
                let mean_rgb: Vec<f32> = (0..w * h).map(|i| rgb_at(i).iter().sum::<f32>() / 3.0).collect();
                let solid_angle = layout.texel_solid_angle(0, w, h);
                (mis_compensated(&mean_rgb), luminance.iter().map(|&y| y as f64).sum::<f64>() * solid_angle)
            }
            MapLayout::LatLong => {
                let f: Vec<f32> =
                    (0..w * h).map(|i| luminance[i] * (PI * ((i / w) as f32 + 0.5) / h as f32).sin()).collect();
                // ∫∫ Y sin θ du dv · 2π², as the sampling density has it.
                let integral = Distribution2D::new(&f, w, h).integral() as f64;
                (f, 2.0 * std::f64::consts::PI.powi(2) * integral)
            }
        };
        let distribution = Arc::new(Distribution2D::new(&f, w, h));
        Self {
            layout,
            width: w,
            height: h,
            texels: Arc::new(texels),
            distribution,
            luminance_integral,
            world_from_light,
            light_from_world: world_from_light.inverse(),
            stretches: false,
            white: Arc::new(space.illuminant.clone()),
            scale,
        }
    }

    /// This light with pbrt-v4's direction maps for a light transform that is not a rotation
    /// (a scale, or a projective row as in pbrt-v4's `sssdragon` scenes). pbrt-v4's
    /// `ImageInfiniteLight` turns a sampled map direction ω_L into the rendering-space vector
    /// `sample_from_light` · ω_L (the upper 3 × 3 of render-from-light) and returns it without
    /// normalising it, with the map's density; its integrators then scale the BSDF's cosine and
    /// density by that vector's length |v|. An escaped ray is looked up along
    /// `light_from_world` · ω (the upper 3 × 3 of light-from-render), which with a projective
    /// row is not the first map's inverse. For a Lambertian surface, weighting by the power or
    /// balance heuristic, that estimate equals the one for the unit direction v/|v| with the
    /// light's density divided by |v|, which is what [`Self::sample_li`] then returns; other BSDFs
    /// are evaluated at the unit direction.
    pub fn with_pbrt_v4_direction_maps(self, sample_from_light: Mat3, light_from_world: Mat3) -> Self {
        Self { world_from_light: sample_from_light, light_from_world, stretches: true, ..self }
    }

    /// How the image covers the sphere.
    pub fn layout(&self) -> MapLayout {
        self.layout
    }

    fn radiance_at(&self, uv: Vec2, w: &SampledWavelengths) -> SampledSpectrum {
        let texel = self.layout.texel(uv, self.width, self.height);
        self.texels[texel].sample(w) * self.white.sample(w) * self.scale
    }

    fn light_uv(&self, d_world: Vec3) -> (Vec2, f32) {
        self.layout.uv((self.light_from_world * d_world).normalize_or_zero())
    }

    /// Radiance arriving from direction `d` (world, pointing away from the scene).
    pub fn le(&self, d: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        self.radiance_at(self.light_uv(d).0, w)
    }

    pub(super) fn sample_li(&self, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let (uv, pdf_uv) = self.distribution.sample(u);
        if pdf_uv == 0.0 {
            return None;
        }
        let (d_light, jacobian) = self.layout.direction(uv);
        if jacobian == 0.0 {
            return None;
        }
        let v = self.world_from_light * d_light;
        let (wi, stretch) = if self.stretches { (v.normalize_or_zero(), v.length()) } else { (v.normalize(), 1.0) };
        if stretch == 0.0 {
            return None;
        }
        let pdf = pdf_uv / jacobian / stretch;
        Some(LightSample { li: self.radiance_at(uv, w), wi, pdf, p_light: Vec3::ZERO, dist: f32::INFINITY })
    }

    /// A direction drawn by importance sampling (world space) with its solid-angle density, for
    /// tests of the sampling routine; `None` where the map is black.
    pub fn sample_direction(&self, u: Vec2) -> Option<(Vec3, f32)> {
        let w = SampledWavelengths::sample_uniform(0.5);
        self.sample_li(u, &w).map(|s| (s.wi, s.pdf))
    }

    /// Solid-angle density [1/sr] of `sample_li` choosing the world direction `wi`.
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        let (uv, jacobian) = self.light_uv(wi);
        if jacobian == 0.0 {
            return 0.0;
        }
        self.distribution.pdf(uv) / jacobian
    }

    pub(super) fn power(&self, scene_radius: f32) -> f32 {
        // Φ ≈ π r² ∫ L dω (pbrt-v4's `ImageInfiniteLight::Phi`), with the texels' spectra as
        // their luminance times the white, weighed as the other lights' (`selection_flux`).
        let white = super::selection_flux::visible_flux(&self.white);
        PI * scene_radius * scene_radius * self.scale * self.luminance_integral as f32 * white
    }
}

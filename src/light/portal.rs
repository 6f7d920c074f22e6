//! An environment map seen through a portal: pbrt-v4's `PortalImageInfiniteLight` (PBR 4th ed.
//! §12.5.3; Bitterli, Novák & Jarosz 2015, "Portal-Masked Environment Map Sampling"). Light
//! reaches the scene only through a rectangle (a window): radiance arrives only along rays whose
//! origin sees the sky through it, and light sampling draws directions through the rectangle
//! only.
//!
//! The map is resampled at load into the portal's *rectified* parameterisation: in the portal's
//! frame (x, y along its edges, z out through it toward the sky) a direction ω with ω_z > 0 has
//! (u, v) = (α + π/2, β + π/2)/π with α = atan2(ω_x, ω_z), β = atan2(ω_y, ω_z). Lines of constant
//! α (or β) are planes through the portal's y (or x) axis, so from any point the portal covers an
//! axis-aligned box of (u, v): the box spanned by two opposite corners. Sampling is a windowed
//! piecewise-constant density over that box ([`WindowedDistribution2D`]) ∝ the mean RGB times
//! the Jacobian dω/(du dv) = π² (1 − ω_x²)(1 − ω_y²)/ω_z at the texel centre, which nearly
//! cancels in the solid-angle density, so samples carry radiance ∝ their weight.

use super::envmap::image_rgb;
use super::texel_spectrum::TexelSpectrum;
use super::LightSample;
use crate::image::Image;
use crate::math::{equal_area, PI};
use crate::sampling::{Window, WindowedDistribution2D};
use crate::spectrum::{ColorSpace, SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Mat3, Vec2, Vec3};
use rayon::prelude::*;
use std::sync::Arc;

/// An image infinite light restricted to a rectangular portal.
#[derive(Clone, Debug)]
pub struct PortalLight {
    /// The portal's corners (world space), in the order given.
    corners: [Vec3; 4],
    /// Portal frame → world: columns x = (p₃ − p₀)/|…|, y = (p₁ − p₀)/|…|, z = x × y.
    world_from_portal: Mat3,
    portal_from_world: Mat3,
    /// The rectified image (n × n, the equal-area map's size), row-major from v = 0.
    size: usize,
    texels: Arc<Vec<TexelSpectrum>>,
    distribution: Arc<WindowedDistribution2D>,
    /// Φ / scale: the flux through the portal [luminance units · m²] (for choosing lights).
    flux: f64,
    white: Arc<Spectrum>,
    /// Multiplier on the image's radiance.
    pub scale: f32,
}

/// Whether four points are a rectangle, to the tolerance pbrt-v4 accepts (opposite edges
/// parallel and adjacent edges perpendicular, each within 10⁻³ in cosine).
pub fn is_rectangle(p: &[Vec3; 4]) -> bool {
    let e = |a: usize, b: usize| (p[b] - p[a]).normalize_or_zero();
    let (e01, e12, e32, e03) = (e(0, 1), e(1, 2), e(3, 2), e(0, 3));
    let parallel = (e01.dot(e32) - 1.0).abs() <= 1e-3 && (e12.dot(e03) - 1.0).abs() <= 1e-3;
    let perpendicular = [e01.dot(e12), e12.dot(e32), e32.dot(e03), e03.dot(e01)].iter().all(|c| c.abs() <= 1e-3);
    parallel && perpendicular
}

/// The unit direction (portal frame) at rectified (u, v), and dω/(du dv) there [sr].
fn rectified_direction(uv: Vec2) -> (Vec3, f32) {
    let (alpha, beta) = ((uv.x - 0.5) * PI, (uv.y - 0.5) * PI);
    let w = Vec3::new(alpha.tan(), beta.tan(), 1.0).normalize();
    (w, jacobian(w))
}

/// dω/(du dv) of the rectified map at the portal-frame direction `w` (w_z > 0).
fn jacobian(w: Vec3) -> f32 {
    PI * PI * (1.0 - w.x * w.x) * (1.0 - w.y * w.y) / w.z
}

/// Rectified (u, v) of the portal-frame unit direction `w`; `None` unless w_z > 0.
fn rectified_uv(w: Vec3) -> Option<Vec2> {
    (w.z > 0.0).then(|| {
        let uv = Vec2::new(w.x.atan2(w.z), w.y.atan2(w.z)) / PI + Vec2::splat(0.5);
        uv.clamp(Vec2::ZERO, Vec2::ONE)
    })
}

/// Bilinear lookup of a square equal-area image at `uv`, across its edges by the octahedral
/// wrap (pbrt-v4's `BilerpChannel` with `OctahedralSphere`).
fn bilerp_equal_area(rgb: &[[f32; 3]], n: usize, uv: Vec2) -> [f32; 3] {
    let (x, y) = (uv.x * n as f32 - 0.5, uv.y * n as f32 - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (tx, ty) = (x - x0, y - y0);
    let mut out = [0f32; 3];
    for (dx, dy, weight) in
        [(0, 0, (1.0 - tx) * (1.0 - ty)), (1, 0, tx * (1.0 - ty)), (0, 1, (1.0 - tx) * ty), (1, 1, tx * ty)]
    {
        let (px, py) = equal_area::wrap_pixel(x0 as i64 + dx, y0 as i64 + dy, n);
        for (o, v) in out.iter_mut().zip(rgb[py * n + px]) {
            *o += weight * v;
        }
    }
    out
}

impl PortalLight {
    /// The equal-area map `image` (square) seen through the rectangle `corners` (world space),
    /// the map oriented by `world_from_light` (a rotation), its RGB an illuminant of `space`
    /// times `scale`. The caller checks that the image is square and the corners a rectangle.
    pub fn new(
        image: &Image,
        corners: [Vec3; 4],
        world_from_light: Mat3,
        scale: f32,
        space: &'static ColorSpace,
    ) -> Self {
        let n = image.width.max(1) as usize;
        let source = image_rgb(image);
        let x = (corners[3] - corners[0]).normalize();
        let y = (corners[1] - corners[0]).normalize();
        let world_from_portal = Mat3::from_cols(x, y, x.cross(y).normalize());
        let light_from_portal = world_from_light.transpose() * world_from_portal;
        // Each rectified texel centre's direction (portal frame) and dω/(du dv) there.
        let centres: Vec<(Vec3, f32)> = (0..n * n)
            .map(|i| {
                rectified_direction(Vec2::new(((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32))
            })
            .collect();
        let rectified: Vec<[f32; 3]> = centres
            .par_iter()
            .map(|&(w, _)| {
                bilerp_equal_area(&source, n, equal_area::sphere_to_square((light_from_portal * w).normalize()))
            })
            .collect();
        let texels = TexelSpectrum::from_rgbs(&rectified, space);
        let weights: Vec<f32> =
            rectified.iter().zip(&centres).map(|(rgb, &(_, jac))| rgb.iter().sum::<f32>() / 3.0 * jac).collect();
        // Φ = A ∫ L cos θ dω over the directions through the portal, by the midpoint rule.
        let area = (corners[1] - corners[0]).length() * (corners[3] - corners[0]).length();
        let flux = rectified
            .iter()
            .zip(&centres)
            .map(|(&rgb, &(w, jac))| (space.rgb_to_xyz(Vec3::from(rgb)).y.max(0.0) * jac * w.z) as f64)
            .sum::<f64>()
            * area as f64
            / (n * n) as f64;
        Self {
            corners,
            world_from_portal,
            portal_from_world: world_from_portal.transpose(),
            size: n,
            texels: Arc::new(texels),
            distribution: Arc::new(WindowedDistribution2D::new(&weights, n, n)),
            flux,
            white: Arc::new(space.illuminant.clone()),
            scale,
        }
    }

    /// The box of rectified (u, v) through which `p` sees the sky; `None` for points on the
    /// portal's plane or beyond it.
    fn window(&self, p: Vec3) -> Option<Window> {
        let uv = |corner: Vec3| rectified_uv((self.portal_from_world * (corner - p)).normalize_or_zero());
        Some(Window::spanning(uv(self.corners[0])?, uv(self.corners[2])?))
    }

    fn radiance_at(&self, uv: Vec2, w: &SampledWavelengths) -> SampledSpectrum {
        let n = self.size;
        let (x, y) = (((uv.x * n as f32) as usize).min(n - 1), ((uv.y * n as f32) as usize).min(n - 1));
        self.texels[y * n + x].sample(w) * self.white.sample(w) * self.scale
    }

    /// Radiance arriving along a ray from `o` with direction `d` that left the scene: the map's
    /// where the ray passed through the portal, else 0.
    pub fn le(&self, o: Vec3, d: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        match (rectified_uv((self.portal_from_world * d).normalize_or_zero()), self.window(o)) {
            (Some(uv), Some(window)) if window.contains(uv) => self.radiance_at(uv, w),
            _ => SampledSpectrum::zero(),
        }
    }

    pub(super) fn sample_li(&self, p: Vec3, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let window = self.window(p)?;
        let (uv, pdf_uv) = self.distribution.sample(u, &window)?;
        let (d, jac) = rectified_direction(uv);
        if jac.is_nan() || jac <= 0.0 {
            return None;
        }
        let wi = (self.world_from_portal * d).normalize();
        Some(LightSample {
            li: self.radiance_at(uv, w),
            wi,
            pdf: pdf_uv / jac,
            p_light: Vec3::ZERO,
            dist: f32::INFINITY,
        })
    }

    /// Solid-angle density [1/sr] of `sample_li` at `p` choosing the world direction `wi`.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3) -> f32 {
        let d = (self.portal_from_world * wi).normalize_or_zero();
        match (rectified_uv(d), self.window(p)) {
            (Some(uv), Some(window)) => {
                let jac = jacobian(d);
                if jac > 0.0 {
                    self.distribution.pdf(uv, &window) / jac
                } else {
                    0.0
                }
            }
            _ => 0.0,
        }
    }

    /// A direction of emitted light drawn over the whole rectified map (not a window: the
    /// emitter is not at a point), with `u`: the direction the light travels (world, into the
    /// scene), its radiance and its solid-angle density [1/sr] (pbrt-v4 `SampleLe`).
    pub(super) fn sample_emitted(&self, u: Vec2, w: &SampledWavelengths) -> Option<(Vec3, SampledSpectrum, f32)> {
        let whole = Window::spanning(Vec2::ZERO, Vec2::ONE);
        let (uv, pdf_uv) = self.distribution.sample(u, &whole)?;
        let (d, jac) = rectified_direction(uv);
        if jac.is_nan() || jac <= 0.0 {
            return None;
        }
        Some((-(self.world_from_portal * d).normalize(), self.radiance_at(uv, w), pdf_uv / jac))
    }

    /// Solid-angle density [1/sr] of [`Self::sample_emitted`] drawing the world direction
    /// `to_sky` (pointing from the scene toward the sky).
    pub(super) fn pdf_emitted(&self, to_sky: Vec3) -> f32 {
        let d = (self.portal_from_world * to_sky).normalize_or_zero();
        match rectified_uv(d) {
            Some(uv) if jacobian(d) > 0.0 => {
                self.distribution.pdf(uv, &Window::spanning(Vec2::ZERO, Vec2::ONE)) / jacobian(d)
            }
            _ => 0.0,
        }
    }

    /// Where the line through `p` with direction `d` crosses the portal's rectangle, if it does:
    /// light sent along `d` enters the scene there.
    pub(super) fn crossing(&self, p: Vec3, d: Vec3) -> Option<Vec3> {
        let local = |q: Vec3| self.portal_from_world * (q - self.corners[0]);
        let (o, dir) = (local(p), self.portal_from_world * d);
        if dir.z == 0.0 {
            return None;
        }
        let q = o - dir * (o.z / dir.z);
        let (w, h) = ((self.corners[3] - self.corners[0]).length(), (self.corners[1] - self.corners[0]).length());
        ((0.0..=w).contains(&q.x) && (0.0..=h).contains(&q.y)).then(|| p + d * (-o.z / dir.z))
    }

    pub(super) fn power(&self) -> f32 {
        // The texels' spectra as their luminance times the white, weighed as the other lights'
        // (`selection_flux`).
        let white = super::selection_flux::visible_flux(&self.white);
        (self.flux * self.scale as f64 * white as f64) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rectified_map_and_its_jacobian_are_consistent() {
        // (u, v) → ω → (u, v) is the identity, and dω/(du dv) matches finite differences of the
        // direction map (the area of the parallelogram spanned by ∂ω/∂u, ∂ω/∂v).
        for &(u, v) in &[(0.5, 0.5), (0.2, 0.7), (0.9, 0.15), (0.05, 0.5)] {
            let uv = Vec2::new(u, v);
            let (w, jac) = rectified_direction(uv);
            assert!((rectified_uv(w).unwrap() - uv).length() < 1e-5);
            let h = 1e-3;
            let d = |du: f32, dv: f32| {
                rectified_direction(uv + Vec2::new(du, dv)).0.as_dvec3()
                    - rectified_direction(uv - Vec2::new(du, dv)).0.as_dvec3()
            };
            let area = d(h, 0.0).cross(d(0.0, h)).length() / (4.0 * (h as f64).powi(2));
            assert!((area / jac as f64 - 1.0).abs() < 2e-3, "({u}, {v}): {area} vs {jac}");
        }
        assert!(rectified_uv(Vec3::new(0.0, 0.3, -0.1)).is_none());
    }

    #[test]
    fn rectangles_are_told_from_other_quadrilaterals() {
        let r = [Vec3::ZERO, Vec3::Y, Vec3::new(2.0, 1.0, 0.0), Vec3::X * 2.0];
        assert!(is_rectangle(&r));
        let skew = [Vec3::ZERO, Vec3::Y, Vec3::new(2.5, 1.0, 0.0), Vec3::X * 2.0];
        assert!(!is_rectangle(&skew));
    }
}

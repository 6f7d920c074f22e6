//! pbrt-v4's `measured` material: a BRDF from the RGL database in Dupuy & Jakob's adaptive
//! parameterisation ("An Adaptive Parameterization for Efficient Material Acquisition and
//! Rendering", SIGGRAPH Asia 2018).
//!
//! The model is a microfacet BRDF with every term tabulated: for the conditioning direction ω₁
//! (the one the data were measured from) and the other ω₂, with half vector ω_m,
//!
//!   f(ω₁, ω₂) = R(s; ω₁, λ) D(ω_m) / (4 σ(ω₁) |cos θ₂|),
//!
//! where D is the distribution of normals, σ(ω₁) = ∫ D(ω) ⟨ω₁·ω⟩ dω the projected microfacet
//! area (so D⟨ω₁·ω_m⟩/σ(ω₁) is the visible-normal density D_ω₁), s ∈ [0, 1]² the point of the
//! visible normals' warp that maps to ω_m, and R the measured ratio (F G₂/G₁ for a microfacet
//! surface). Sampling follows R's luminance in s, then the warp to ω_m, then reflects ω₁ about
//! it, so the density is ∝ f cos θ₂ up to R's colour. As in pbrt-v4, ω₁ = ωo in `f`, `pdf` and
//! `sample_f`; the data are then used reciprocally for ωi, exact only where the tabulation is.

mod data;
pub mod tabulate;
pub mod tensor_file;

pub use data::{MeasuredBrdf, MeasuredError};

use super::local::{abs_cos_theta, reflect, same_hemisphere};
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Vec2, Vec3, PI};
use crate::spectrum::SampledSpectrum;
use std::sync::Arc;

/// u_θ of a zenith angle: √(2θ/π).
#[inline]
pub fn theta_to_u(theta: f32) -> f32 {
    (theta * (2.0 / PI)).max(0.0).sqrt()
}
/// u_φ of an azimuth in [−π, π]: (φ + π)/(2π).
#[inline]
pub fn phi_to_u(phi: f32) -> f32 {
    (phi + PI) * (0.5 / PI)
}
/// θ = u² π/2.
#[inline]
pub fn u_to_theta(u: f32) -> f32 {
    u * u * (0.5 * PI)
}
/// φ = (2u − 1)π.
#[inline]
pub fn u_to_phi(u: f32) -> f32 {
    (2.0 * u - 1.0) * PI
}

/// θ of a unit vector, accurate near the pole (2 asin(|ω − z|/2), as Mitsuba's `elevation`).
#[inline]
fn elevation(w: Vec3) -> f32 {
    let d = (w.x * w.x + w.y * w.y + (w.z - 1.0) * (w.z - 1.0)).sqrt();
    2.0 * (0.5 * d).clamp(-1.0, 1.0).asin()
}

/// The measured BRDF at the path's four wavelengths.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The file's tables.
    pub brdf: Arc<MeasuredBrdf>,
    /// The path's wavelengths [nm].
    pub lambda: [f32; 4],
}

impl PartialEq for Measured {
    fn eq(&self, o: &Self) -> bool {
        Arc::ptr_eq(&self.brdf, &o.brdf) && self.lambda == o.lambda
    }
}

/// A direction in (u_θ, u_φ) with its spherical angles.
struct Angles {
    theta: f32,
    phi: f32,
}

impl Angles {
    fn of(w: Vec3) -> Self {
        Self { theta: elevation(w), phi: w.y.atan2(w.x) }
    }
    fn u(&self) -> Vec2 {
        Vec2::new(theta_to_u(self.theta), phi_to_u(self.phi))
    }
    fn params(&self) -> [f32; 2] {
        [self.phi, self.theta]
    }
}

impl Measured {
    /// The BRDF of `brdf` at wavelengths `lambda`.
    pub fn new(brdf: Arc<MeasuredBrdf>, lambda: [f32; 4]) -> Self {
        Self { brdf, lambda }
    }

    /// (u_θ, u_φ) of the half vector `wm` seen from `w1` (azimuth relative to it when isotropic).
    fn u_of_half_vector(&self, w1: &Angles, wm: Vec3) -> Vec2 {
        let m = Angles::of(wm);
        let phi = if self.brdf.isotropic { m.phi - w1.phi } else { m.phi };
        let u = Vec2::new(theta_to_u(m.theta), phi_to_u(phi));
        Vec2::new(u.x, u.y - u.y.floor())
    }

    /// f = R D / (4 σ(ω₁) |cos θ₂|) at sample-space point `s`, half vector (u) `u_wm`.
    fn value(&self, w1: &Angles, s: Vec2, u_wm: Vec2, cos2: f32) -> SampledSpectrum {
        let b = &self.brdf;
        let p = w1.params();
        let r = SampledSpectrum::new(self.lambda.map(|l| b.spectra.eval(s, &[p[0], p[1], l]).max(0.0)));
        if !b.jacobian {
            // The file holds f cos θ₂ directly.
            return r / cos2;
        }
        let sigma = b.sigma.eval(w1.u(), &[]);
        if sigma.is_nan() || sigma <= 0.0 {
            return SampledSpectrum::zero();
        }
        r * (b.ndf.eval(u_wm, &[]) / (4.0 * sigma * cos2))
    }

    /// The density [1/sr] of ω₂ given ω₁ from the sample-space density `lum_pdf × vndf_pdf` of
    /// ω_m: / (2π² u_θ sin θ_m) for (u_θ, u_φ) → solid angle, / (4 ω₁·ω_m) for the reflection.
    fn solid_angle_pdf(pdf_u: f32, u_theta: f32, sin_theta_m: f32, w1_dot_wm: f32) -> f32 {
        pdf_u / (4.0 * w1_dot_wm * (2.0 * PI * PI * u_theta * sin_theta_m).max(1e-6))
    }

    /// f(ωo, ωi) [1/sr] for ωo and ωi on the same side (mirrored to the upper side when below).
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) {
            return SampledSpectrum::zero();
        }
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return SampledSpectrum::zero();
        }
        let wo_angles = Angles::of(wo);
        let u_wm = self.u_of_half_vector(&wo_angles, wm.normalize());
        let s = self.brdf.vndf.invert(u_wm, &wo_angles.params()).p;
        self.value(&wo_angles, s, u_wm, abs_cos_theta(wi))
    }

    /// Samples ωi: luminance in the sample space, the visible-normal warp to ω_m, reflection.
    pub fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo = if flip { -wo } else { wo };
        let wo_angles = Angles::of(wo);
        let params = wo_angles.params();
        // (u.y, u.x) as pbrt-v4, so its sample streams map to the same directions.
        let lum = self.brdf.luminance.sample(Vec2::new(u.y, u.x), &params);
        let vndf = self.brdf.vndf.sample(lum.p, &params);
        let u_wm = vndf.p;
        let mut phi_m = u_to_phi(u_wm.y);
        if self.brdf.isotropic {
            phi_m += wo_angles.phi;
        }
        let theta_m = u_to_theta(u_wm.x);
        let (sin_t, cos_t) = theta_m.sin_cos();
        let (sin_p, cos_p) = phi_m.sin_cos();
        let wm = Vec3::new(sin_t * cos_p, sin_t * sin_p, cos_t);
        let wi = reflect(wo, wm);
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = Self::solid_angle_pdf(lum.pdf * vndf.pdf, u_wm.x, sin_t, wo.dot(wm));
        let f = self.value(&wo_angles, lum.p, u_wm, wi.z);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let wi = if flip { -wi } else { wi };
        Some(BsdfSample::new(f, wi, pdf, BxdfFlags::GLOSSY_REFLECTION))
    }

    /// Density of [`Self::sample_f`] [1/sr].
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        if !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        let wo_angles = Angles::of(wo);
        let params = wo_angles.params();
        let u_wm = self.u_of_half_vector(&wo_angles, wm);
        let inv = self.brdf.vndf.invert(u_wm, &params);
        let lum = self.brdf.luminance.eval(inv.p, &params);
        let sin_theta_m = (wm.x * wm.x + wm.y * wm.y).sqrt();
        let pdf = Self::solid_angle_pdf(lum * inv.pdf, u_wm.x, sin_theta_m, wo.dot(wm));
        if pdf.is_finite() {
            pdf.max(0.0)
        } else {
            0.0
        }
    }

    /// Glossy reflection.
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::GLOSSY_REFLECTION
    }
}

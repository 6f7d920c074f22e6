//! Lambertian reflection: f = ρ/π (Lambert 1760), sampled by the cosine-weighted hemisphere.

use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::warp::cosine_hemisphere;
use crate::simd::{Real, V3};
use crate::spectrum::SampledSpectrum;
use crate::spectrum::S4;

/// Lambertian BRDF with reflectance `r` ∈ [0, 1] per wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    /// Hemispherical reflectance ρ (albedo).
    pub r: SampledSpectrum,
}

impl Diffuse {
    /// A Lambertian surface of albedo `r`.
    pub fn new(r: SampledSpectrum) -> Self {
        Self { r }
    }

    /// f(wo, wi) = ρ/π on the same side, 0 otherwise.
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        self.lanes().f(wo.into(), wi.into()).into()
    }

    /// Cosine-weighted sample on the side of `wo`.
    pub fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let s = self.lanes().sample_f(wo.into(), u.x, u.y);
        s.valid.then(|| BsdfSample::new(s.f.into(), s.wi.into(), s.pdf, BxdfFlags::DIFFUSE_REFLECTION))
    }

    /// Density of [`Self::sample_f`].
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        self.lanes().pdf(wo.into(), wi.into())
    }

    fn lanes(&self) -> DiffuseLanes<f32> {
        DiffuseLanes { r: self.r.into() }
    }

    /// Lobes present.
    pub fn flags(&self) -> BxdfFlags {
        if self.r.is_black() {
            BxdfFlags::UNSET
        } else {
            BxdfFlags::DIFFUSE_REFLECTION
        }
    }
}

/// [`Diffuse`] for every lane: one Lambertian surface per path (the same model; the scalar
/// methods above are these with one lane).
#[derive(Clone, Copy, Debug)]
pub struct DiffuseLanes<R> {
    /// Hemispherical reflectance ρ per lane and wavelength.
    pub r: S4<R>,
}

/// A sampled direction per lane (local frame) with f, its density and which lanes hold one.
#[derive(Clone, Copy, Debug)]
pub struct LaneSample<R: Real> {
    /// f(wo, wi) [1/sr].
    pub f: S4<R>,
    /// Sampled incident direction.
    pub wi: V3<R>,
    /// Density of `wi` [1/sr].
    pub pdf: R,
    /// Lanes with a sample.
    pub valid: R::Mask,
}

impl<R: Real> DiffuseLanes<R> {
    /// f = ρ/π where wo and wi are on the same side.
    #[inline(always)]
    pub fn f(&self, wo: V3<R>, wi: V3<R>) -> S4<R> {
        let same = R::splat(0.0).lt(wo.z * wi.z);
        S4::select(same, self.r.scale(R::splat(INV_PI)), S4::splat(0.0))
    }

    /// Cosine-weighted sample on the side of `wo`; no sample where ρ = 0.
    #[inline(always)]
    pub fn sample_f(&self, wo: V3<R>, ux: R, uy: R) -> LaneSample<R> {
        let mut wi = cosine_hemisphere(ux, uy);
        wi.z = R::select(wo.z.lt(R::splat(0.0)), -wi.z, wi.z);
        let pdf = wi.z.abs() * R::splat(INV_PI);
        LaneSample { f: self.r.scale(R::splat(INV_PI)), wi, pdf, valid: !self.r.is_black() }
    }

    /// Density of [`Self::sample_f`]: |cos θi|/π on the side of `wo`.
    #[inline(always)]
    pub fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let ok = R::splat(0.0).lt(wo.z * wi.z) & !self.r.is_black();
        R::select(ok, wi.z.abs() * R::splat(INV_PI), R::splat(0.0))
    }
}

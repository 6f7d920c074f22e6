//! The world-space BSDF at a hit: shading frame + geometric normal + a [`Bxdf`]
//! (pbrt-v4 `bsdf.h`).

use super::{BsdfSample, Bxdf, BxdfFlags, DiffuseLanes, LaneSample, TransportMode};
use crate::math::FrameLanes;
use crate::math::{Frame, Vec2, Vec3};
use crate::simd::{Real, V3};
use crate::spectrum::SampledSpectrum;
use crate::spectrum::S4;

/// A [`Bxdf`] placed in the world. Rejects `wo` in the shading tangent plane, zero pdfs and
/// non-finite values, so the integrator never sees a NaN from here.
#[derive(Clone, Debug, PartialEq)]
pub struct Bsdf {
    /// Shading frame (n = shading normal).
    pub frame: Frame,
    /// Geometric normal (unit).
    pub ng: Vec3,
    /// The local scattering model.
    pub bxdf: Bxdf,
}

impl Bsdf {
    /// From the shading normal `ns`, the tangent `dpdu` (first frame axis after Gram–Schmidt),
    /// the geometric normal `ng` and the model.
    pub fn new(ns: Vec3, dpdu: Vec3, ng: Vec3, bxdf: Bxdf) -> Self {
        Self { frame: Frame::from_normal_tangent(ns, dpdu), ng, bxdf }
    }

    /// The shading normal: the frame's z axis, which bump and normal maps may have turned away
    /// from the surface's interpolated normal. Cosine factors of the reflection equation are
    /// taken against it.
    #[inline]
    pub fn ns(&self) -> Vec3 {
        self.frame.n
    }

    /// World → local shading frame.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        self.frame.to_local(v)
    }

    /// Local shading frame → world.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.frame.to_world(v)
    }

    /// Lobes of the model.
    #[inline]
    pub fn flags(&self) -> BxdfFlags {
        self.bxdf.flags()
    }

    /// f(ωo, ωi) for world directions [1/sr]; 0 when ωo lies in the shading tangent plane or
    /// the value is not finite.
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        let (wo, wi) = (self.to_local(wo), self.to_local(wi));
        if wo.z == 0.0 {
            return SampledSpectrum::zero();
        }
        let f = self.bxdf.f(wo, wi, mode);
        if f.is_finite() {
            f
        } else {
            SampledSpectrum::zero()
        }
    }

    /// Samples a world-space ωi; `None` when ωo is in the tangent plane, the sample is black,
    /// has zero or non-finite density or value, or ωi lies in the tangent plane.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let wo_l = self.to_local(wo);
        if wo_l.z == 0.0 || self.bxdf.flags().is_empty() {
            return None;
        }
        let mut s = self.bxdf.sample_f(wo_l, uc, u, mode)?;
        if s.f.is_black() || s.pdf.is_nan() || s.pdf <= 0.0 || s.wi.z == 0.0 || !s.f.is_finite() || !s.pdf.is_finite() {
            return None;
        }
        s.wi = self.to_world(s.wi);
        if !s.wi.is_finite() {
            return None;
        }
        Some(s)
    }

    /// Density of [`Self::sample_f`] for world directions [1/sr]; 0 when ωo lies in the
    /// tangent plane or the density is not finite.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        let (wo, wi) = (self.to_local(wo), self.to_local(wi));
        if wo.z == 0.0 {
            return 0.0;
        }
        let p = self.bxdf.pdf(wo, wi, mode);
        if p.is_finite() {
            p
        } else {
            0.0
        }
    }
}

/// A [`Bsdf`] per lane, for the path loop that advances several paths together. Its model is
/// Lambertian: the lane loop is a prototype that renders scenes of diffuse surfaces only.
#[derive(Clone, Copy, Debug)]
pub struct BsdfLanes<R> {
    /// Shading frame per lane.
    pub frame: FrameLanes<R>,
    /// The model per lane.
    pub bxdf: DiffuseLanes<R>,
}

impl<R: Real> BsdfLanes<R> {
    /// [`Bsdf::f`] for every lane.
    #[inline(always)]
    pub fn f(&self, wo: V3<R>, wi: V3<R>) -> S4<R> {
        let (wo, wi) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let ok = !wo.z.eq(R::splat(0.0));
        S4::select(ok, self.bxdf.f(wo, wi), S4::splat(0.0))
    }

    /// [`Bsdf::pdf`] for every lane.
    #[inline(always)]
    pub fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let (wo, wi) = (self.frame.to_local(wo), self.frame.to_local(wi));
        R::select(wo.z.eq(R::splat(0.0)), R::splat(0.0), self.bxdf.pdf(wo, wi))
    }

    /// [`Bsdf::sample_f`] for every lane: `valid` is false where it would return `None`.
    #[inline(always)]
    pub fn sample_f(&self, wo: V3<R>, ux: R, uy: R) -> LaneSample<R> {
        let wo_l = self.frame.to_local(wo);
        let mut s = self.bxdf.sample_f(wo_l, ux, uy);
        let zero = R::splat(0.0);
        s.valid = s.valid & !wo_l.z.eq(zero) & !s.f.is_black() & zero.lt(s.pdf) & s.pdf.is_finite() & !s.wi.z.eq(zero);
        s.wi = self.frame.to_world(s.wi);
        s
    }
}

//! The closed set of BxDF models, an enum, dispatched by `match`.

use super::{
    BsdfSample, BxdfFlags, CoatedDiffuse, Conductor, Dielectric, Diffuse, DiffuseTransmission, Hair, LayeredConductor,
    LayeredDiffuse, Measured, NormalizedFresnel, ThinDielectric, TransportMode,
};
use crate::math::{Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// A BxDF built per hit from values at the path's four wavelengths, on the stack; the large
/// layered models live on the heap so that every BSDF stays small enough (with its frame, at
/// most 128 bytes) to be moved without a `memcpy` call. All directions are in the local
/// shading frame (z = shading normal).
#[derive(Clone, Debug, PartialEq)]
pub enum Bxdf {
    /// Lambertian reflection.
    Diffuse(Diffuse),
    /// Lambertian reflection + transmission.
    DiffuseTransmission(DiffuseTransmission),
    /// Rough or smooth metal.
    Conductor(Conductor),
    /// Rough or smooth dielectric interface.
    Dielectric(Dielectric),
    /// Thin smooth dielectric slab.
    ThinDielectric(ThinDielectric),
    /// Dielectric coat over a Lambertian base, analytic (Kelemen/Weidlich–Wilkie).
    CoatedDiffuse(CoatedDiffuse),
    /// Dielectric coat over a Lambertian base, stochastic layered (pbrt-v4 `coateddiffuse`).
    LayeredDiffuse(Box<LayeredDiffuse>),
    /// Dielectric coat over a metal, stochastic layered (pbrt-v4 `coatedconductor`).
    LayeredConductor(Box<LayeredConductor>),
    /// The entry-point lobe S_ω of a diffusion BSSRDF.
    NormalizedFresnel(NormalizedFresnel),
    /// A hair fibre (Chiang et al. 2016; local x along the fibre).
    Hair(Hair),
    /// A tabulated BRDF (pbrt-v4 `measured`; Dupuy & Jakob 2018).
    Measured(Measured),
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            Bxdf::Diffuse($b) => $e,
            Bxdf::DiffuseTransmission($b) => $e,
            Bxdf::Conductor($b) => $e,
            Bxdf::Dielectric($b) => $e,
            Bxdf::ThinDielectric($b) => $e,
            Bxdf::CoatedDiffuse($b) => $e,
            Bxdf::LayeredDiffuse($b) => $e,
            Bxdf::LayeredConductor($b) => $e,
            Bxdf::NormalizedFresnel($b) => $e,
            Bxdf::Hair($b) => $e,
            Bxdf::Measured($b) => $e,
        }
    };
}

impl Bxdf {
    /// f(ωo, ωi) [1/sr] excluding delta lobes; cosine not included.
    #[inline]
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        dispatch!(self, b => b.f(wo, wi, mode))
    }

    /// Samples ωi from `uc` (lobe choice) and `u` (direction), both uniform in [0, 1).
    #[inline]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        dispatch!(self, b => b.sample_f(wo, uc, u, mode))
    }

    /// Density [1/sr] with which [`Self::sample_f`] produces ωi (0 for delta lobes).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi, mode))
    }

    /// Lobes present.
    #[inline]
    pub fn flags(&self) -> BxdfFlags {
        dispatch!(self, b => b.flags())
    }

    /// Widens every microfacet lobe ([`super::TrowbridgeReitz::regularize`]); lobes without a
    /// microfacet distribution (diffuse, thin dielectric, hair, the BSSRDF entry lobe) and the
    /// tabulated measured one stay as they are, as in pbrt-v4.
    pub fn regularize(&mut self) {
        match self {
            Bxdf::Conductor(b) => b.distrib.regularize(),
            Bxdf::Dielectric(b) => b.distrib.regularize(),
            Bxdf::CoatedDiffuse(b) => b.distrib.regularize(),
            Bxdf::LayeredDiffuse(b) => b.top.distrib.regularize(),
            Bxdf::LayeredConductor(b) => {
                b.top.distrib.regularize();
                b.bottom.distrib.regularize();
            }
            Bxdf::Diffuse(_)
            | Bxdf::DiffuseTransmission(_)
            | Bxdf::ThinDielectric(_)
            | Bxdf::NormalizedFresnel(_)
            | Bxdf::Hair(_)
            | Bxdf::Measured(_) => {}
        }
    }
}

impl From<Diffuse> for Bxdf {
    fn from(b: Diffuse) -> Self {
        Bxdf::Diffuse(b)
    }
}
impl From<DiffuseTransmission> for Bxdf {
    fn from(b: DiffuseTransmission) -> Self {
        Bxdf::DiffuseTransmission(b)
    }
}
impl From<Conductor> for Bxdf {
    fn from(b: Conductor) -> Self {
        Bxdf::Conductor(b)
    }
}
impl From<Dielectric> for Bxdf {
    fn from(b: Dielectric) -> Self {
        Bxdf::Dielectric(b)
    }
}
impl From<ThinDielectric> for Bxdf {
    fn from(b: ThinDielectric) -> Self {
        Bxdf::ThinDielectric(b)
    }
}
impl From<CoatedDiffuse> for Bxdf {
    fn from(b: CoatedDiffuse) -> Self {
        Bxdf::CoatedDiffuse(b)
    }
}
impl From<NormalizedFresnel> for Bxdf {
    fn from(b: NormalizedFresnel) -> Self {
        Bxdf::NormalizedFresnel(b)
    }
}
impl From<Hair> for Bxdf {
    fn from(b: Hair) -> Self {
        Bxdf::Hair(b)
    }
}
impl From<Measured> for Bxdf {
    fn from(b: Measured) -> Self {
        Bxdf::Measured(b)
    }
}
impl From<LayeredDiffuse> for Bxdf {
    fn from(b: LayeredDiffuse) -> Self {
        Bxdf::LayeredDiffuse(Box::new(b))
    }
}
impl From<LayeredConductor> for Bxdf {
    fn from(b: LayeredConductor) -> Self {
        Bxdf::LayeredConductor(Box::new(b))
    }
}

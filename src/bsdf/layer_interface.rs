//! What a layered BSDF asks of the BxDFs that bound its slab: values, densities and samples
//! restricted to reflection or to transmission (pbrt-v4 §14.3, `BxDFReflTransFlags`).

use super::{BsdfSample, BxdfFlags, Conductor, Dielectric, Diffuse, Lobes, TransportMode};
use crate::math::{Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// A BxDF that can bound a layer: the top (entrance) or bottom interface of a slab.
pub trait LayerInterface: Copy {
    /// f(ωo, ωi) [1/sr], delta lobes excluded.
    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum;
    /// A sample of ωi among `lobes` only.
    fn sample_lobes(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode, lobes: Lobes) -> Option<BsdfSample>;
    /// Density [1/sr] of [`Self::sample_lobes`] with the same `lobes`.
    fn pdf_lobes(&self, wo: Vec3, wi: Vec3, mode: TransportMode, lobes: Lobes) -> f32;
    /// Lobes present.
    fn flags(&self) -> BxdfFlags;
}

impl LayerInterface for Dielectric {
    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        Dielectric::f(self, wo, wi, mode)
    }
    fn sample_lobes(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode, lobes: Lobes) -> Option<BsdfSample> {
        Dielectric::sample_lobes(self, wo, uc, u, mode, lobes)
    }
    fn pdf_lobes(&self, wo: Vec3, wi: Vec3, mode: TransportMode, lobes: Lobes) -> f32 {
        Dielectric::pdf_lobes(self, wo, wi, mode, lobes)
    }
    fn flags(&self) -> BxdfFlags {
        Dielectric::flags(self)
    }
}

/// Opaque interfaces: reflection is all they have, so a transmission request finds nothing.
macro_rules! reflector {
    ($t:ty) => {
        impl LayerInterface for $t {
            fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
                <$t>::f(self, wo, wi, mode)
            }
            fn sample_lobes(
                &self,
                wo: Vec3,
                uc: f32,
                u: Vec2,
                mode: TransportMode,
                lobes: Lobes,
            ) -> Option<BsdfSample> {
                if lobes.reflection() {
                    <$t>::sample_f(self, wo, uc, u, mode)
                } else {
                    None
                }
            }
            fn pdf_lobes(&self, wo: Vec3, wi: Vec3, mode: TransportMode, lobes: Lobes) -> f32 {
                if lobes.reflection() {
                    <$t>::pdf(self, wo, wi, mode)
                } else {
                    0.0
                }
            }
            fn flags(&self) -> BxdfFlags {
                <$t>::flags(self)
            }
        }
    };
}

reflector!(Diffuse);
reflector!(Conductor);

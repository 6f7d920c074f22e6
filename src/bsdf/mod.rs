//! Scattering functions: BxDFs in the local shading frame (z = normal), enum-dispatched through
//! [`Bxdf`], and the world-space [`Bsdf`] wrapper the integrator calls at each hit.
//!
//! Conventions follow pbrt-v4 (`src/pbrt/bxdfs.h`, `bsdf.h`): `wo` and `wi` both point away
//! from the surface, `f` excludes the cosine, pdfs are per steradian, delta lobes return
//! `pdf` 0 from [`Bxdf::pdf`] and are only reachable through [`Bxdf::sample_f`].

mod bxdf;
mod coated;
mod conductor;
mod dielectric;
mod diffuse;
mod diffuse_transmission;
mod flags;
pub mod fresnel;
pub mod hair;
pub mod ior;
mod layer_interface;
mod layered;
pub mod local;
pub mod measured;
pub mod metals;
mod microfacet;
pub mod named_spectra;
mod normalized_fresnel;
mod phase;
mod sample;
mod thin_dielectric;
mod world;

#[cfg(test)]
mod tests;

pub use bxdf::Bxdf;
pub use coated::CoatedDiffuse;
pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use diffuse::{Diffuse, DiffuseLanes, LaneSample};
pub use diffuse_transmission::DiffuseTransmission;
pub use flags::{BxdfFlags, Lobes, TransportMode};
pub use hair::Hair;
pub use layer_interface::LayerInterface;
pub use layered::{Layered, LayeredConductor, LayeredDiffuse, Slab};
pub use measured::{Measured, MeasuredBrdf, MeasuredError};
pub use microfacet::TrowbridgeReitz;
pub use normalized_fresnel::NormalizedFresnel;
pub use phase::{hg_density, HenyeyGreenstein};
pub use sample::BsdfSample;
pub use thin_dielectric::ThinDielectric;
pub use world::{Bsdf, BsdfLanes};

//! A wavefront path tracer (Laine, Karras & Aila 2013, "Megakernels Considered Harmful:
//! Wavefront Path Tracing on GPUs"; pbrt-v4's GPU integrator): a batch of thousands of camera
//! paths advances stage by stage, each stage one loop over its queue, instead of one path at a
//! time from camera to end. The stages of one bounce:
//!
//! 1. camera rays (scalar: the sampler, the filter and the camera per path);
//! 2. closest hits of every active ray ([`crate::accel::Accel::intersect_batch`]: Embree
//!    `rtcIntersect16` packets);
//! 3. surface (scalar): the interaction, emission found, the material's BSDF with its textures,
//!    the light chosen and the vertex's sampler dimensions; paths are binned by BSDF kind;
//! 4. the Lambertian queue (vector, [`diffuse`]): light sample, BSDF value and density, MIS
//!    weight, shadow-ray origin, BSDF sample and throughput, 16 paths per instruction through
//!    the lane-generic physics of [`crate::simd`] (`DiffuseLanes`, `TriangleLightLanes`,
//!    `offset_ray_origin_lanes`: the scalar renderer runs the same code with one lane);
//! 5. every other BSDF kind (scalar, [`other_kinds`]), through the scalar loop's own steps;
//! 6. shadow rays ([`crate::accel::Accel::occluded_batch`]: `rtcOccluded16`);
//! 7. Russian roulette and the next rays (scalar);
//! 8. film (scalar, in path order, so that each pixel adds its samples in index order).
//!
//! Each path draws its sampler's dimensions in the scalar loop's order, so it is the scalar
//! loop's path up to rounding, and the image is the same for any thread count.
//!
//! A prototype for measuring the design (docs/benchmarks.md, "Wavefront prototype and its
//! gate"): `prism render --wavefront` renders scenes of surfaces lit by triangle area lights;
//! [`check`] refuses others.

mod band;
mod clock;
mod columns;
mod diffuse;
mod other_kinds;
mod paths;
mod surface;

pub use band::{render_band, BandJob};
pub use clock::{Stage, STAGES};

use super::{DirectStrategy, Integrator, IntegratorKind};
use crate::light::{AreaLight, Light};
use crate::scene::Scene;

/// Why the wavefront loop cannot render a scene with some settings.
#[derive(Debug, thiserror::Error)]
#[error("the wavefront prototype renders only the path integrator over surfaces lit by area lights; {0}")]
pub struct Unsupported(String);

/// Ok when the wavefront loop renders `scene` with `integrator` (after
/// [`Integrator::for_scene`]) as the scalar loop would.
pub fn check(scene: &Scene, integrator: &Integrator) -> Result<(), Unsupported> {
    let no = |why: &str| Err(Unsupported(why.into()));
    if integrator.kind != IntegratorKind::Path {
        return no(&format!("integrator \"{}\" was chosen", integrator.kind.name()));
    }
    if integrator.strategy != DirectStrategy::Mis || integrator.regularize {
        return no("another direct-light strategy or regularisation was chosen");
    }
    if scene.has_subsurface() || scene.has_media() {
        return no("this scene has media or subsurface materials");
    }
    if scene.has_interfaces_or_cut_outs() {
        return no("this scene has interface materials or alpha cut-outs");
    }
    if scene.lights().iter().any(|l| !matches!(l, Light::Area(AreaLight { image: None, .. }))) {
        return no("this scene has lights other than untextured triangle area lights");
    }
    Ok(())
}

#[cfg(test)]
mod tests;

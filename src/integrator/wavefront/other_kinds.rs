//! The queue of every BSDF kind but the Lambertian one, shaded path by path through the scalar
//! loop's own steps (`light_sample`, `sample_bsdf`): conductors, dielectrics and the layered
//! models have no lane-generic form yet.

use super::super::state::PathState;
use super::super::Integrator;
use super::paths::Paths;
use crate::bsdf::Bsdf;
use crate::geometry::Ray;
use crate::light::Light;
use crate::scene::SurfaceInteraction;
use crate::spectrum::SampledSpectrum;
use glam::Vec2;

/// A vertex of another kind: its interaction, BSDF and the light chosen (with its probability
/// and the rest of the draw).
pub(super) struct OtherVertex<'s> {
    pub path: u32,
    pub si: SurfaceInteraction<'s>,
    pub bsdf: Bsdf,
    pub light: Option<(&'s Light, f32, Vec2)>,
}

/// The vertices of other kinds in one bounce.
#[derive(Default)]
pub(super) struct OtherQueue<'s>(pub Vec<OtherVertex<'s>>);

impl<'s> OtherQueue<'s> {
    pub fn push(&mut self, v: OtherVertex<'s>) {
        self.0.push(v);
    }

    /// Next-event estimation and BSDF sampling for every vertex: pushes its shadow ray with
    /// the light it brings (times β) to `shadows`, and the paths that continue, whose next ray
    /// and state it sets, to `next`.
    pub fn shade(
        &mut self,
        integrator: &Integrator,
        paths: &mut Paths,
        shadows: &mut Vec<Ray>,
        shadow_light: &mut Vec<(u32, SampledSpectrum)>,
        next: &mut Vec<u32>,
    ) {
        for v in self.0.drain(..) {
            let k = v.path as usize;
            let state: &mut PathState = &mut paths.state[k];
            let w = &paths.lambdas[k];
            if let Some((light, pmf, u)) = v.light {
                if let Some((ray, ld)) = integrator.light_sample(&v.si, &v.bsdf, light, pmf, u, w) {
                    shadows.push(ray);
                    shadow_light.push((v.path, state.beta * ld));
                }
            }
            let Some(bs) = integrator.sample_bsdf(&v.si, &v.bsdf, &mut paths.sampler[k], state) else { continue };
            paths.ray[k] = v.si.spawn_ray(bs.wi);
            if bs.is_transmission() {
                state.eta_scale *= bs.eta * bs.eta;
            }
            next.push(v.path);
        }
    }
}

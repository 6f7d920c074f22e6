//! pbrt-v4's `randomwalk`: the reflection equation estimated by the plainest Monte Carlo walk,
//! every direction drawn uniformly over the sphere (pdf 1/4π) and emission counted only where a
//! path finds it — no light sampling, no BSDF importance sampling, no Russian roulette. An
//! unbiased reference for the other estimators, and a lesson in why they exist.

use super::interface::Integrator;
use super::state::{escaped_radiance, next_surface};
use super::Stats;
use crate::bsdf::TransportMode;
use crate::film::VisibleSurface;
use crate::geometry::Ray;
use crate::math::PI;
use crate::sampling::warp::sample_uniform_sphere;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{Footprint, RayDifferentials};

impl Integrator {
    /// Radiance along `ray` by a uniform random walk of at most `max_depth` scattering events.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn random_walk(
        &self,
        scene: &Scene,
        mut ray: Ray,
        differentials: Option<&RayDifferentials>,
        mut visible: Option<&mut Option<VisibleSurface>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let (mut l, mut beta) = (SampledSpectrum::zero(), SampledSpectrum::one());
        let mut depth = 0;
        loop {
            let Some(si) = next_surface(scene, ray, stats) else {
                l += beta * escaped_radiance(scene, &ray, w);
                break;
            };
            l += beta * si.emitted(w);
            if depth >= self.max_depth {
                break;
            }
            depth += 1;
            let footprint = Footprint::of_vertex(self.footprint.as_ref(), differentials, depth == 1);
            let Some(bsdf) = si.bsdf(w, footprint) else { break };
            if let Some(v) = visible.take() {
                *v = Some(super::visible_surface::visible_surface(&si, &bsdf, footprint));
            }
            let wi = sample_uniform_sphere(sampler.get_2d());
            let f = bsdf.f(si.wo, wi, TransportMode::Radiance) * wi.dot(bsdf.ns()).abs();
            if f.is_black() {
                break;
            }
            beta *= f * (4.0 * PI);
            ray = si.spawn_ray(wi);
        }
        stats.last_depth = depth;
        l
    }
}

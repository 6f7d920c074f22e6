//! pbrt-v4's `simplepath`: path tracing without multiple importance sampling or Russian
//! roulette. With `samplelights`, each vertex takes one light sample and emission found by
//! the path counts only after a delta lobe (or at the camera); without it, emission counts
//! wherever it is found. With `samplebsdf` the path continues by BSDF sampling, without it
//! uniformly over the sphere. Every combination estimates the same radiance as `path`.

use super::interface::{DirectStrategy, Integrator};
use super::options::SimplePath;
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
    /// Radiance along `ray` by [`SimplePath`]'s estimator, at most `max_depth` scattering events.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn simple_path(
        &self,
        scene: &Scene,
        mut ray: Ray,
        differentials: Option<&RayDifferentials>,
        mut visible: Option<&mut Option<VisibleSurface>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let SimplePath { sample_lights, sample_bsdf } = self.simple;
        // Light samples unweighted: emission they also find is not counted.
        let nee = Integrator { strategy: DirectStrategy::LightOnly, ..*self };
        let (mut l, mut beta) = (SampledSpectrum::zero(), SampledSpectrum::one());
        let (mut depth, mut specular) = (0, true);
        loop {
            let counts_emission = !sample_lights || specular;
            let Some(si) = next_surface(scene, ray, stats) else {
                if counts_emission {
                    l += beta * escaped_radiance(scene, &ray, w);
                }
                break;
            };
            if counts_emission {
                l += beta * si.emitted(w);
            }
            if depth >= self.max_depth {
                break;
            }
            depth += 1;
            let footprint = Footprint::of_vertex(self.footprint.as_ref(), differentials, depth == 1);
            let Some(bsdf) = si.bsdf(w, footprint) else { break };
            if let Some(v) = visible.take() {
                *v = Some(super::visible_surface::visible_surface(&si, &bsdf, footprint));
            }
            if sample_lights && bsdf.flags().is_non_specular() {
                l += beta * nee.sample_light(scene, &si, &bsdf, w, sampler, stats);
            }
            let wi = if sample_bsdf {
                let Some(bs) = bsdf.sample_f(si.wo, sampler.get_1d(), sampler.get_2d(), TransportMode::Radiance) else {
                    break;
                };
                beta *= bs.f * (bs.wi.dot(bsdf.ns()).abs() / bs.pdf);
                specular = bs.is_specular();
                bs.wi
            } else {
                let wi = sample_uniform_sphere(sampler.get_2d());
                beta *= bsdf.f(si.wo, wi, TransportMode::Radiance) * (wi.dot(bsdf.ns()).abs() * 4.0 * PI);
                specular = false;
                wi
            };
            if beta.is_black() {
                break;
            }
            ray = si.spawn_ray(wi);
        }
        stats.last_depth = depth;
        l
    }
}

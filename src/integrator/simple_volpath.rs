//! pbrt-v4's `simplevolpath` (`SimpleVolPathIntegrator`; Pharr, Jakob & Humphreys, *Physically
//! Based Rendering*, 4th ed., §14.1.5): the delta-tracking estimator of the volumetric
//! rendering equation at the hero wavelength alone, with no light sampling. At each tentative
//! collision (density σ_maj T_maj) the path is absorbed with probability σ_a/σ_maj — gathering
//! the medium's emission L_e there, which estimates ∫ T σ_a L_e — scatters with σ_s/σ_maj by
//! sampling the phase function (exactly, so the throughput stays 1), or goes on through a null
//! collision. A ray that reaches a surface unscattered gathers its emission (or, escaping, the
//! infinite lights'); surfaces that only bound media are crossed, and a surface that scatters
//! ends the path (pbrt-v4 stops with an error there: the estimator has no surface scattering).

use super::collision::Event;
use super::interface::Integrator;
use super::state::escaped_radiance;
use super::transmittance::{distance, ray_rng};
use super::Stats;
use crate::bsdf::HenyeyGreenstein;
use crate::geometry::Ray;
use crate::media::sample_t_maj;
use crate::sampling::Sampler;
use crate::scene::{Crossings, Scene};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

impl Integrator {
    /// Radiance at the hero wavelength of `w` (the others are terminated) arriving along `ray`,
    /// which starts in the camera's medium.
    pub(super) fn simple_volpath(
        &self,
        scene: &Scene,
        ray: Ray,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        w.terminate_secondary();
        let mut l = SampledSpectrum::zero();
        let mut depth = 0;
        let mut ray = Ray::new(ray.o, ray.d.normalize()).at_time(ray.time);
        let mut medium = scene.camera_medium();
        let mut crossings = Crossings::default();
        loop {
            stats.rays += 1;
            let si = scene.intersect(&ray);
            if let Some(m) = medium.and_then(|i| scene.media().get(i as usize)) {
                let t_hit = si.as_ref().map_or(f32::INFINITY, |s| distance(&ray, s.p));
                let uniform = m.uniform_point(w);
                let mut rng = ray_rng(sampler);
                let u = sampler.get_1d();
                let (mut scattered, mut terminated) = (None, false);
                sample_t_maj(m, &uniform, ray.o, ray.d, t_hit, u, &mut rng, w, |c, rng| {
                    match Event::choose(&c, rng.uniform()) {
                        Event::Absorb => {
                            l += c.mp.le;
                            terminated = true;
                            false
                        }
                        Event::Scatter => {
                            if depth >= self.max_depth {
                                terminated = true;
                            } else {
                                depth += 1;
                                scattered = Some((c.p, c.mp.g));
                            }
                            false
                        }
                        Event::Null => true,
                    }
                });
                if terminated {
                    break;
                }
                if let Some((p, g)) = scattered {
                    let wi = HenyeyGreenstein::new(g).sample(ray.d, sampler.get_2d());
                    ray = Ray::new(p, wi).at_time(ray.time);
                    continue;
                }
            }
            let Some(si) = si else {
                l += escaped_radiance(scene, &ray, w);
                break;
            };
            if si.area_light().is_some() {
                l += si.emitted(w);
            }
            if !si.is_passthrough() {
                break;
            }
            if !crossings.allow_another() {
                break;
            }
            (ray, medium) = si.pass_through(&ray, medium);
        }
        stats.last_depth = depth;
        l
    }
}

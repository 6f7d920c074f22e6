//! Unidirectional path tracing of the reflection equation L_o = L_e + ∫ f_r L_i cos θ_i dω_i
//! (Kajiya 1986), with next-event estimation and BSDF sampling combined by multiple importance
//! sampling (Veach 1997, power heuristic β = 2) and Russian roulette: the surface loop of
//! [`Integrator`], for scenes without media.

use super::interface::{DirectStrategy, Integrator};
use super::state::PathState;
use super::subsurface;
use super::Stats;
use crate::bsdf::{Bsdf, TransportMode};
use crate::film::VisibleSurface;
use crate::geometry::Ray;
use crate::light::{Light, LightSampleContext};
use crate::sampling::mis::power_heuristic;
use crate::sampling::Sampler;
use crate::scene::{Crossings, Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::RayDifferentials;
use glam::Vec2;

impl Integrator {
    /// MIS weight of emission found by BSDF sampling, given the light's solid-angle pdf.
    pub(super) fn emission_weight(&self, state: &PathState, p_light: f32) -> f32 {
        if state.specular_bounce || self.strategy == DirectStrategy::BsdfOnly {
            1.0
        } else if self.strategy == DirectStrategy::LightOnly {
            0.0
        } else {
            power_heuristic(1, state.prev_pdf, 1, p_light)
        }
    }

    /// The surface `ray` meets (`None`: it escapes), with the light it finds added to
    /// `state.l`: the lights at infinity if it escapes, else the area light it hits, each
    /// weighted by MIS against the previous vertex's light sample.
    pub(super) fn next_hit_with_emission<'s>(
        &self,
        scene: &'s Scene,
        ray: &Ray,
        state: &mut PathState,
        w: &SampledWavelengths,
        stats: &mut Stats,
    ) -> Option<SurfaceInteraction<'s>> {
        stats.rays += 1;
        let Some(si) = scene.intersect(ray) else {
            let d = ray.d.normalize();
            for (id, light) in scene.infinite_lights() {
                let weight = self.emission_weight(state, scene.light_pdf(id, &state.prev, d));
                state.l += state.beta * light.escaped_radiance(ray.o, d, w) * weight;
            }
            return None;
        };
        if let Some((id, _)) = si.area_light() {
            let le = si.emitted(w);
            if !le.is_black() {
                let weight = self.emission_weight(state, scene.light_pdf(id, &state.prev, -si.wo));
                state.l += state.beta * le * weight;
            }
        }
        Some(si)
    }

    /// The surface path loop. `differentials` are the camera ray's, `pending` is a vertex found
    /// without tracing the current ray (the irradiance sensor; a diffusion exit), whose BSDF is
    /// given; `visible`, when given, receives the first surface vertex.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn path_trace<'s>(
        &self,
        scene: &'s Scene,
        mut ray: Ray,
        differentials: Option<&RayDifferentials>,
        mut pending: Option<(SurfaceInteraction<'s>, Bsdf)>,
        mut visible: Option<&mut Option<VisibleSurface>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let mut state = PathState::new(ray.o);
        let use_nee = self.strategy != DirectStrategy::BsdfOnly;
        let mut crossings = Crossings::default();
        loop {
            // The next vertex, and the emission the ray finds there.
            let (si, given_bsdf) = match pending.take() {
                Some((si, bsdf)) => (si, Some(bsdf)),
                None => {
                    let Some(si) = self.next_hit_with_emission(scene, &ray, &mut state, w, stats) else { break };
                    if si.is_passthrough() {
                        // No surface: the same ray goes on, and the previous vertex stays the
                        // one MIS weights refer to.
                        if !crossings.allow_another() {
                            break;
                        }
                        ray = si.spawn_ray(ray.d);
                        continue;
                    }
                    (si, None)
                }
            };
            if !self.next_vertex(&mut state) {
                break;
            }
            // The BSDF is borrowed where it was built, not moved (it is larger than the
            // compiler copies without a `memcpy` call).
            let computed;
            let bsdf = match &given_bsdf {
                Some(b) => b,
                None => {
                    computed = self.vertex_bsdf(&si, w, differentials, &state);
                    match &computed {
                        Some(b) => b,
                        None => break,
                    }
                }
            };
            self.record_visible(&mut visible, &si, bsdf, differentials, &state);
            let flags = bsdf.flags();
            if flags.is_empty() {
                break;
            }

            // Next-event estimation (not for purely specular BSDFs, whose f is zero off the delta).
            if use_nee && flags.is_non_specular() {
                state.l += state.beta * self.sample_light(scene, &si, bsdf, w, sampler, stats);
            }

            // Continue the path by sampling the BSDF.
            let Some(bs) = self.sample_bsdf(&si, bsdf, sampler, &mut state) else { break };
            ray = si.spawn_ray(bs.wi);
            if bs.is_transmission() {
                // Refraction into a subsurface medium: continue where light leaves it. Entering and
                // leaving scale radiance by 1/η² and η², so eta_scale is left alone.
                if let Some(m) = subsurface::entered(&si, &bs, bsdf.ns()) {
                    let (interior, walks) = subsurface::interior(self.sss, scene, m, &si, w);
                    // The surface loop has no medium step: `Integrator::for_scene` gives scenes
                    // whose subsurface objects may be walked to the volumetric loop.
                    debug_assert!(!walks, "a random walk in the surface loop");
                    if walks {
                        break;
                    }
                    match subsurface::diffusion(scene, m, &interior, &si, &mut state.beta, sampler, stats) {
                        Some(vertex) => {
                            pending = Some(vertex);
                            continue;
                        }
                        None => break,
                    }
                } else {
                    state.eta_scale *= bs.eta * bs.eta;
                }
            }
            if state.beta.is_black() || !self.roulette(&mut state, sampler) {
                break;
            }
        }
        stats.last_depth = state.depth;
        state.l
    }

    /// One light sample at `si`, MIS-weighted against BSDF sampling (pbrt-v4 `SampleLd`).
    pub(super) fn sample_light(
        &self,
        scene: &Scene,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        w: &SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let ctx = LightSampleContext::surface(si.p, bsdf.ns());
        let Some((_, light, pmf, u)) = scene.sample_light(&ctx, sampler.get_2d()) else {
            return SampledSpectrum::zero();
        };
        let Some((shadow, ld)) = self.light_sample(si, bsdf, light, pmf, u, w) else {
            return SampledSpectrum::zero();
        };
        stats.rays += 1;
        if scene.occluded(&shadow) {
            return SampledSpectrum::zero();
        }
        ld
    }

    /// The part of [`Self::sample_light`] after the light is chosen (`light`, picked with
    /// probability `pmf`; `u` the rest of the draw): the shadow ray to the point sampled on it
    /// and the light it brings when nothing blocks that ray. `None`: nothing to trace.
    pub(super) fn light_sample(
        &self,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        light: &Light,
        pmf: f32,
        u: Vec2,
        w: &SampledWavelengths,
    ) -> Option<(Ray, SampledSpectrum)> {
        let ctx = LightSampleContext::surface(si.p, bsdf.ns());
        let ls = light.sample_li(&ctx, u, w)?;
        if ls.pdf <= 0.0 || ls.li.is_black() {
            return None;
        }
        let f = bsdf.f(si.wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(bsdf.ns()).abs();
        if f.is_black() {
            return None;
        }
        let shadow = if ls.dist.is_finite() { si.spawn_ray_to(ls.p_light) } else { si.spawn_ray(ls.wi) };
        let p_light = pmf * ls.pdf;
        let weight = if light.is_delta() || self.strategy == DirectStrategy::LightOnly {
            1.0
        } else {
            power_heuristic(1, p_light, 1, bsdf.pdf(si.wo, ls.wi, TransportMode::Radiance))
        };
        Some((shadow, f * ls.li * (weight / p_light)))
    }
}

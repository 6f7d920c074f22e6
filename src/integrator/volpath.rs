//! Volumetric path tracing with null scattering and spectral MIS (Miller, Georgiev & Jarosz
//! 2019, "A null-scattering path integral formulation of light transport"; pbrt-v4's
//! `VolPathIntegrator`, Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed., §14.2).
//!
//! Free flights are sampled by delta tracking against a majorant σ_maj ≥ σ_t at the hero
//! wavelength (channel 0). At a tentative collision the path absorbs with probability σ_a/σ_maj,
//! scatters with σ_s/σ_maj, or continues through a null collision (σ_n = σ_maj − σ_t). The path
//! carries, besides its throughput β, the *rescaled path probabilities* r_u (of the
//! unidirectional sampling at each wavelength, divided by the hero wavelength's) and r_l (of
//! light sampling): dividing by the average of r_u over the four wavelengths is the one-sample
//! MIS (balance heuristic) over which wavelength drew the distances, and (r_u + r_l) the MIS
//! between BSDF/phase sampling and next-event estimation. Shadow rays estimate transmittance by
//! ratio tracking (Novák et al. 2014) with Russian roulette once it is small, through any number
//! of media and interface surfaces. Media emit σ_a L_e, gathered at every tentative collision.
//! Paths that refract into a subsurface material continue by [`super::subsurface::enter`].
//! The volumetric loop of [`Integrator`], for scenes with media; its surface vertices take the
//! steps the surface loop takes ([`super::state`]).

use super::collision::{self, Event};
use super::interface::{DirectStrategy, Integrator};
use super::state::PathState;
use super::subsurface::{self, Interior};
use super::transmittance::{distance, ray_rng, transmittance};
use super::Stats;
use crate::bsdf::{Bsdf, TransportMode};
use crate::film::VisibleSurface;
use crate::geometry::Ray;
use crate::light::LightSampleContext;
use crate::media::{sample_t_maj, sample_t_maj_homogeneous, HenyeyGreenstein};
use crate::sampling::Sampler;
use crate::scene::{Crossings, Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::RayDifferentials;
use glam::Vec3;

/// Where a random walk's step leaves the path.
enum WalkStep {
    /// Absorbed, rouletted, or out of depth or events.
    End,
    /// Still inside, along this ray.
    Inside(Ray),
    /// Refracted out along this ray.
    Left(Ray),
}

/// Where a light sample is taken from.
enum Scatterer<'a, 's> {
    /// A surface point with its BSDF.
    Surface(&'a SurfaceInteraction<'s>, &'a Bsdf),
    /// A point in a medium: `d` is the propagation direction of the arriving ray, `time` its
    /// instant.
    Medium { p: Vec3, d: Vec3, phase: HenyeyGreenstein, time: f32 },
}

impl Integrator {
    /// The volumetric path loop: radiance arriving along `ray`, which starts in the camera's
    /// medium. `differentials` are the camera ray's (the texture footprint at the first surface
    /// vertex, through interfaces and null collisions, which do not scatter it); `pending` is a
    /// vertex found without tracing the ray (the irradiance sensor; a diffusion exit), whose BSDF
    /// is given; `visible`, when given, receives the first surface vertex.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn volpath_trace<'s>(
        &self,
        scene: &'s Scene,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        mut pending: Option<(SurfaceInteraction<'s>, Bsdf)>,
        mut visible: Option<&mut Option<VisibleSurface>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let mut state = PathState::new(ray.o);
        let use_nee = self.strategy != DirectStrategy::BsdfOnly;
        let mut ray = Ray::new(ray.o, ray.d.normalize()).at_time(ray.time);
        let mut medium = scene.camera_medium();
        // The subsurface object a random walk is in; its interior is the medium then.
        let mut interior: Option<Interior> = None;
        let mut crossings = Crossings::default();
        loop {
            let (si, given_bsdf) = match pending.take() {
                Some((si, bsdf)) => (si, Some(bsdf)),
                None => {
                    stats.rays += 1;
                    if let Some(inside) = &mut interior {
                        match self.walk_step(scene, inside, &ray, &mut state, use_nee, w, sampler, stats) {
                            WalkStep::End => break,
                            WalkStep::Inside(next) => ray = next,
                            WalkStep::Left(next) => {
                                (ray, medium, interior) = (next, inside.outside, None);
                                if state.beta.is_black() || !self.roulette(&mut state, sampler) {
                                    break;
                                }
                            }
                        }
                        continue;
                    }
                    let si = scene.intersect(&ray);
                    if let Some(m) = medium.and_then(|i| scene.media().get(i as usize)) {
                        let t_hit = si.as_ref().map_or(f32::INFINITY, |s| distance(&ray, s.p));
                        let uniform = m.uniform_point(w);
                        let mut rng = ray_rng(sampler);
                        let u = sampler.get_1d();
                        let (mut scattered, mut terminated) = (None, false);
                        let st = &mut state;
                        let t_maj = sample_t_maj(m, &uniform, ray.o, ray.d, t_hit, u, &mut rng, w, |c, rng| {
                            let s0 = c.sigma_maj[0];
                            // Emission σ_a L_e, estimated at every tentative collision.
                            if st.depth < self.max_depth && !c.mp.le.is_black() {
                                let pdf = s0 * c.t_maj[0];
                                let r_e = st.r_u * c.sigma_maj * c.t_maj / pdf;
                                if !r_e.is_black() {
                                    st.l += st.beta * c.t_maj / pdf * c.mp.sigma_a * c.mp.le / r_e.average();
                                }
                            }
                            match Event::choose(&c, rng.uniform()) {
                                Event::Absorb => {
                                    terminated = true;
                                    false
                                }
                                Event::Scatter => {
                                    if !self.next_vertex(st) {
                                        terminated = true;
                                        return false;
                                    }
                                    collision::scatter(&c, &mut st.beta, &mut st.r_u);
                                    scattered = Some((c.p, c.mp.g));
                                    false
                                }
                                Event::Null => collision::null(&c, &mut st.beta, &mut st.r_u, &mut st.r_l),
                            }
                        });
                        if terminated || state.beta.is_black() || state.r_u.is_black() || !state.beta.is_finite() {
                            break;
                        }
                        if let Some((p, g)) = scattered {
                            let phase = HenyeyGreenstein::new(g);
                            if use_nee {
                                let at = Scatterer::Medium { p, d: ray.d, phase, time: ray.time };
                                state.l += self.sample_ld(scene, &at, medium, state.beta, state.r_u, w, sampler, stats);
                            }
                            let wi = phase.sample(ray.d, sampler.get_2d());
                            let pdf = phase.p(ray.d, wi);
                            // β ·= p/pdf = 1: HG is sampled exactly.
                            state.r_l = state.r_u / pdf;
                            state.prev = LightSampleContext::medium(p);
                            state.prev_pdf = pdf;
                            state.specular_bounce = false;
                            state.any_non_specular = true;
                            ray = Ray::new(p, wi).at_time(ray.time);
                            // A medium vertex is a vertex like any other: roulette applies.
                            if !self.roulette(&mut state, sampler) {
                                break;
                            }
                            continue;
                        }
                        let t0 = t_maj[0];
                        if t0.is_nan() || t0 <= 0.0 {
                            break;
                        }
                        state.beta *= t_maj / t0;
                        state.r_u *= t_maj / t0;
                        state.r_l *= t_maj / t0;
                    }

                    let Some(si) = si else {
                        for (id, light) in scene.infinite_lights() {
                            let le = light.escaped_radiance(ray.o, ray.d, w);
                            state.l += self.found_emission(scene, id, le, &state, ray.d);
                        }
                        break;
                    };
                    if let Some((id, _)) = si.area_light() {
                        let le = si.emitted(w);
                        if !le.is_black() {
                            state.l += self.found_emission(scene, id, le, &state, ray.d);
                        }
                    }
                    if si.is_passthrough() {
                        // A boundary between media only: the ray goes on in the medium behind it.
                        if !crossings.allow_another() {
                            break;
                        }
                        (ray, medium) = si.pass_through(&ray, medium);
                        continue;
                    }
                    (si, None)
                }
            };
            if !self.next_vertex(&mut state) {
                break;
            }
            let bsdf = match given_bsdf {
                Some(b) => b,
                None => match self.vertex_bsdf(&si, w, differentials, &state) {
                    Some(b) => b,
                    None => break,
                },
            };
            self.record_visible(&mut visible, &si, &bsdf, differentials, &state);
            let flags = bsdf.flags();
            if flags.is_empty() {
                break;
            }
            if use_nee && flags.is_non_specular() {
                let at = Scatterer::Surface(&si, &bsdf);
                state.l += self.sample_ld(scene, &at, medium, state.beta, state.r_u, w, sampler, stats);
            }
            let Some(bs) = self.sample_bsdf(&si, &bsdf, sampler, &mut state) else { break };
            let wi = bs.wi.normalize();
            // Refraction into a subsurface material: the path goes on where light leaves it, in
            // the medium it came from (entering and leaving scale radiance by 1/η² and η², so
            // eta_scale is left alone).
            if let Some(m) = subsurface::entered(&si, &bs, bsdf.ns()) {
                let outside = si.medium_interface().medium_toward(si.wo, si.shading.ng, medium);
                medium = outside;
                let (inside, walks) = subsurface::interior(self.sss, scene, m, &si, w);
                if walks {
                    interior = Some(Interior { medium: inside, material: m, outside, scatterings: 0, events: 0 });
                    ray = si.spawn_ray(wi);
                } else {
                    match subsurface::diffusion(scene, m, &inside, &si, &mut state.beta, sampler, stats) {
                        Some(vertex) => {
                            pending = Some(vertex);
                            continue;
                        }
                        None => break,
                    }
                }
            } else {
                if bs.is_transmission() {
                    state.eta_scale *= bs.eta * bs.eta;
                }
                medium = si.medium_interface().medium_toward(wi, si.shading.ng, medium);
                ray = si.spawn_ray(wi);
            }
            if state.beta.is_black() || !self.roulette(&mut state, sampler) {
                break;
            }
        }
        stats.last_depth = state.depth;
        state.l
    }

    /// One event of a random walk through the subsurface object `inside` along `ray` (unit
    /// direction): delta tracking in its interior up to the object's surface, then either a
    /// real scattering (the phase function's new ray) or the boundary, where light is sampled
    /// through it and its BSDF sampled: reflection stays inside, refraction leaves, and leaving
    /// counts as one vertex of the path. A hit inside the object is taken as its boundary. The
    /// walk's scatterings are not path vertices: after [`subsurface::WALK_RR_EVENTS`] of them
    /// roulette may end a dim walk, and [`subsurface::MAX_WALK_EVENTS`] events end any.
    #[allow(clippy::too_many_arguments)]
    fn walk_step(
        &self,
        scene: &Scene,
        inside: &mut Interior,
        ray: &Ray,
        state: &mut PathState,
        use_nee: bool,
        w: &SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> WalkStep {
        inside.events += 1;
        if inside.events > subsurface::MAX_WALK_EVENTS {
            return WalkStep::End;
        }
        let hit = scene.closest_hit(ray);
        let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
        let mut rng = ray_rng(sampler);
        let u = sampler.get_1d();
        let (mut scattered, mut absorbed) = (None, false);
        let st = &mut *state;
        let t_maj = sample_t_maj_homogeneous(&inside.medium, ray.o, ray.d, t_hit, u, &mut rng, |c, rng| {
            match Event::choose(&c, rng.uniform()) {
                Event::Absorb => {
                    absorbed = true;
                    false
                }
                Event::Scatter => {
                    collision::scatter(&c, &mut st.beta, &mut st.r_u);
                    scattered = Some(c.p);
                    false
                }
                Event::Null => collision::null(&c, &mut st.beta, &mut st.r_u, &mut st.r_l),
            }
        });
        if absorbed || state.beta.is_black() || state.r_u.is_black() {
            return WalkStep::End;
        }
        let next = if let Some(p) = scattered {
            inside.scatterings += 1;
            let phase = HenyeyGreenstein::new(inside.medium.g);
            Ray::new(p, phase.sample(ray.d, sampler.get_2d())).at_time(ray.time)
        } else {
            // No collision before the boundary: β, r_u ·= T_maj / T_maj,hero.
            let t0 = t_maj[0];
            let Some(h) = hit.filter(|_| t0 > 0.0) else { return WalkStep::End };
            state.beta *= t_maj / t0;
            state.r_u *= t_maj / t0;
            let b = scene.interaction(ray, &h);
            let bsdf = inside.material.boundary_bsdf(&b.shading_point(None));
            if use_nee && bsdf.flags().is_non_specular() {
                let at = Scatterer::Surface(&b, &bsdf);
                state.l += self.sample_ld(scene, &at, inside.outside, state.beta, state.r_u, w, sampler, stats);
            }
            let Some(bs) = self.sample_bsdf(&b, &bsdf, sampler, state) else { return WalkStep::End };
            let next = b.spawn_ray(bs.wi);
            if bs.wi.dot(b.shading.ns) > 0.0 {
                return if self.next_vertex(state) { WalkStep::Left(next) } else { WalkStep::End };
            }
            next
        };
        if state.beta.is_black() {
            return WalkStep::End;
        }
        // Russian roulette once the walk is long and dim, on β with spectral MIS's
        // normalisation undone.
        let survival = (state.beta / state.r_u.average()).max_value();
        if inside.scatterings >= subsurface::WALK_RR_EVENTS && survival < 1.0 {
            let q = (1.0 - survival).max(0.0);
            if sampler.get_1d() < q {
                return WalkStep::End;
            }
            state.beta /= 1.0 - q;
        }
        WalkStep::Inside(next)
    }

    /// Emission `le` of light `id` found by the path in `state` (whose r_l does not yet hold
    /// the light's density), MIS-weighted against next-event estimation as the strategy says.
    #[inline]
    fn found_emission(
        &self,
        scene: &Scene,
        id: u32,
        le: SampledSpectrum,
        state: &PathState,
        d: Vec3,
    ) -> SampledSpectrum {
        let by_bsdf_alone = state.beta * le / state.r_u.average();
        match self.strategy {
            _ if state.specular_bounce => by_bsdf_alone,
            DirectStrategy::BsdfOnly => by_bsdf_alone,
            DirectStrategy::LightOnly => SampledSpectrum::zero(),
            DirectStrategy::Mis => {
                let r_l = state.r_l * scene.light_pdf(id, &state.prev, d);
                state.beta * le / (state.r_u + r_l).average()
            }
        }
    }

    /// Next-event estimation from `at` (pbrt-v4 `VolPathIntegrator::SampleLd`): one light sample,
    /// its transmittance through media and interfaces by ratio tracking, weighted by MIS against
    /// scattering. `medium` is the medium the path is in, `r_p` its r_u.
    #[allow(clippy::too_many_arguments)]
    fn sample_ld(
        &self,
        scene: &Scene,
        at: &Scatterer,
        medium: Option<u32>,
        beta: SampledSpectrum,
        r_p: SampledSpectrum,
        w: &SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let zero = SampledSpectrum::zero();
        let ctx = match at {
            Scatterer::Surface(si, bsdf) => LightSampleContext::surface(si.p, bsdf.ns()),
            Scatterer::Medium { p, .. } => LightSampleContext::medium(*p),
        };
        let Some((_, light, pmf, u)) = scene.sample_light(&ctx, sampler.get_2d()) else { return zero };
        let Some(ls) = light.sample_li(&ctx, u, w) else { return zero };
        if ls.pdf <= 0.0 || ls.li.is_black() {
            return zero;
        }
        let (f_hat, scatter_pdf) = match at {
            Scatterer::Surface(si, bsdf) => (
                bsdf.f(si.wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(bsdf.ns()).abs(),
                bsdf.pdf(si.wo, ls.wi, TransportMode::Radiance),
            ),
            Scatterer::Medium { d, phase, .. } => {
                let p = phase.p(*d, ls.wi);
                (SampledSpectrum::splat(p), p)
            }
        };
        if f_hat.is_black() {
            return zero;
        }
        let (ray, medium) = match at {
            Scatterer::Surface(si, _) => (
                if ls.dist.is_finite() { si.spawn_ray_to(ls.p_light) } else { si.spawn_ray(ls.wi) },
                si.medium_interface().medium_toward(ls.wi, si.shading.ng, medium),
            ),
            Scatterer::Medium { p, time, .. } => (
                if ls.dist.is_finite() { Ray::segment(*p, ls.p_light - *p, 1.0 - 1e-4) } else { Ray::new(*p, ls.wi) }
                    .at_time(*time),
                medium,
            ),
        };
        let Some((t_ray, r_l, r_u)) = transmittance(scene, ray, medium, w, sampler, stats) else { return zero };
        let p_l = pmf * ls.pdf;
        let r_l = r_l * r_p * p_l;
        let f = beta * f_hat * t_ray * ls.li;
        if light.is_delta() || self.strategy == DirectStrategy::LightOnly {
            f / r_l.average()
        } else {
            f / (r_l + r_u * r_p * scatter_pdf).average()
        }
    }
}

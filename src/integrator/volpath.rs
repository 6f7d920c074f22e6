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

use super::subsurface::{self, Exit, SubsurfaceMethod};
use super::transmittance::{distance, ray_rng, transmittance};
use super::{PathIntegrator, Stats};
use crate::bsdf::{Bsdf, TransportMode};
use crate::geometry::Ray;
use crate::light::LightSampleContext;
use crate::media::{sample_t_maj, HenyeyGreenstein};
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction, MAX_INTERFACE_CROSSINGS};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{Footprint, RayDifferentials, TextureFootprint};
use glam::Vec3;

/// The volumetric path tracer's settings.
#[derive(Clone, Copy, Debug)]
pub struct VolPathIntegrator {
    /// Maximum number of scattering events (surface and medium).
    pub max_depth: u32,
    /// The camera's pixel footprint for filtered texture lookups.
    pub footprint: Option<TextureFootprint>,
    /// Widen microfacet lobes after the first non-specular bounce (`PathIntegrator::regularize`).
    pub regularize: bool,
    /// How paths entering subsurface materials continue.
    pub sss: SubsurfaceMethod,
}

impl VolPathIntegrator {
    /// The settings of the surface path tracer that apply (depth limit, texture footprint,
    /// regularisation, subsurface method).
    pub fn from_path(p: &PathIntegrator) -> Self {
        Self { max_depth: p.max_depth, footprint: p.footprint, regularize: p.regularize, sss: p.sss }
    }
}

/// Where a light sample is taken from.
enum Scatterer<'a, 's> {
    /// A surface point with its BSDF.
    Surface(&'a SurfaceInteraction<'s>, &'a Bsdf),
    /// A point in a medium: `d` is the propagation direction of the arriving ray, `time` its
    /// instant.
    Medium { p: Vec3, d: Vec3, phase: HenyeyGreenstein, time: f32 },
}

impl VolPathIntegrator {
    /// Radiance arriving along `ray` (which starts in the camera's medium) at the wavelengths `w`.
    pub fn li(
        &self,
        scene: &Scene,
        ray: Ray,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        self.li_camera(scene, ray, None, w, sampler, stats)
    }

    /// [`Self::li`] for a camera ray with its differentials, which give the texture footprint
    /// at its first surface vertex (through interfaces and null collisions, which do not
    /// scatter it).
    pub fn li_camera(
        &self,
        scene: &Scene,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let mut l = SampledSpectrum::zero();
        let mut beta = SampledSpectrum::one();
        let (mut r_u, mut r_l) = (SampledSpectrum::one(), SampledSpectrum::one());
        let mut specular_bounce = true;
        let mut any_non_specular = false;
        let mut eta_scale = 1.0f32;
        let mut depth = 0u32;
        let mut prev = LightSampleContext::medium(ray.o);
        let mut ray = Ray::new(ray.o, ray.d.normalize()).at_time(ray.time);
        let mut medium = scene.camera_medium();
        let mut crossings = 0;
        // A vertex found without tracing a ray (a subsurface exit) with its BSDF.
        let mut pending: Option<(SurfaceInteraction, Bsdf)> = None;
        loop {
            let (si, given_bsdf) = match pending.take() {
                Some((si, bsdf)) => (si, Some(bsdf)),
                None => {
                    stats.rays += 1;
                    let si = scene.intersect(&ray);
                    if let Some(m) = medium.and_then(|i| scene.media().get(i as usize)) {
                        let t_hit = si.as_ref().map_or(f32::INFINITY, |s| distance(&ray, s.p));
                        let uniform = m.uniform_point(w);
                        let mut rng = ray_rng(sampler);
                        let u = sampler.get_1d();
                        let (mut scattered, mut terminated) = (None, false);
                        let t_maj = sample_t_maj(m, &uniform, ray.o, ray.d, t_hit, u, &mut rng, w, |c, rng| {
                            let s0 = c.sigma_maj[0];
                            // Emission σ_a L_e, estimated at every tentative collision.
                            if depth < self.max_depth && !c.mp.le.is_black() {
                                let pdf = s0 * c.t_maj[0];
                                let r_e = r_u * c.sigma_maj * c.t_maj / pdf;
                                if !r_e.is_black() {
                                    l += beta * c.t_maj / pdf * c.mp.sigma_a * c.mp.le / r_e.average();
                                }
                            }
                            let (p_absorb, p_scatter) = (c.mp.sigma_a[0] / s0, c.mp.sigma_s[0] / s0);
                            let um = rng.uniform();
                            if um < p_absorb {
                                terminated = true;
                                false
                            } else if um < p_absorb + p_scatter {
                                if depth >= self.max_depth {
                                    terminated = true;
                                    return false;
                                }
                                depth += 1;
                                let pdf = c.t_maj[0] * c.mp.sigma_s[0];
                                beta *= c.t_maj * c.mp.sigma_s / pdf;
                                r_u *= c.t_maj * c.mp.sigma_s / pdf;
                                scattered = Some((c.p, c.mp.g));
                                false
                            } else {
                                let sigma_n = (c.sigma_maj - c.mp.sigma_a - c.mp.sigma_s).map(|x| x.max(0.0));
                                let pdf = c.t_maj[0] * sigma_n[0];
                                if pdf <= 0.0 {
                                    beta = SampledSpectrum::zero();
                                } else {
                                    beta *= c.t_maj * sigma_n / pdf;
                                    r_u *= c.t_maj * sigma_n / pdf;
                                    r_l *= c.t_maj * c.sigma_maj / pdf;
                                }
                                !beta.is_black() && !r_u.is_black()
                            }
                        });
                        if terminated || beta.is_black() || r_u.is_black() || !beta.is_finite() {
                            break;
                        }
                        if let Some((p, g)) = scattered {
                            let phase = HenyeyGreenstein::new(g);
                            let at = Scatterer::Medium { p, d: ray.d, phase, time: ray.time };
                            l += self.sample_ld(scene, &at, medium, beta, r_u, w, sampler, stats);
                            let wi = phase.sample(ray.d, sampler.get_2d());
                            let pdf = phase.p(ray.d, wi);
                            // β ·= p/pdf = 1: HG is sampled exactly.
                            r_l = r_u / pdf;
                            prev = LightSampleContext::medium(p);
                            specular_bounce = false;
                            any_non_specular = true;
                            ray = Ray::new(p, wi).at_time(ray.time);
                            continue;
                        }
                        let t0 = t_maj[0];
                        if t0.is_nan() || t0 <= 0.0 {
                            break;
                        }
                        beta *= t_maj / t0;
                        r_u *= t_maj / t0;
                        r_l *= t_maj / t0;
                    }

                    let Some(si) = si else {
                        for (id, light) in scene.infinite_lights() {
                            let le = light.escaped_radiance(ray.o, ray.d, w);
                            l += self.found_emission(scene, id, le, beta, r_u, r_l, specular_bounce, &prev, ray.d);
                        }
                        break;
                    };
                    if let Some((id, _)) = si.area_light() {
                        let le = si.emitted(w);
                        if !le.is_black() {
                            l += self.found_emission(scene, id, le, beta, r_u, r_l, specular_bounce, &prev, ray.d);
                        }
                    }
                    if si.is_passthrough() {
                        // A boundary between media only: the ray goes on in the medium behind it.
                        crossings += 1;
                        if crossings > MAX_INTERFACE_CROSSINGS {
                            break;
                        }
                        medium = si.medium_interface().medium_toward(ray.d, si.shading.ng, medium);
                        ray = si.spawn_ray(ray.d);
                        continue;
                    }
                    (si, None)
                }
            };
            if depth >= self.max_depth {
                break;
            }
            depth += 1;
            let bsdf = match given_bsdf {
                Some(b) => b,
                None => {
                    let footprint = Footprint::of_vertex(self.footprint.as_ref(), differentials, depth == 1);
                    let Some(mut b) = si.bsdf(w, footprint) else { break };
                    if self.regularize && any_non_specular {
                        b.bxdf.regularize();
                    }
                    b
                }
            };
            let flags = bsdf.flags();
            if flags.is_empty() {
                break;
            }
            if flags.is_non_specular() {
                l += self.sample_ld(scene, &Scatterer::Surface(&si, &bsdf), medium, beta, r_u, w, sampler, stats);
            }
            prev = LightSampleContext::surface(si.p, bsdf.ns());
            let uc = sampler.get_1d();
            let Some(bs) = bsdf.sample_f(si.wo, uc, sampler.get_2d(), TransportMode::Radiance) else { break };
            beta *= bs.f * (bs.wi.dot(bsdf.ns()).abs() / bs.pdf);
            let pdf = if bs.pdf_is_proportional { bsdf.pdf(si.wo, bs.wi, TransportMode::Radiance) } else { bs.pdf };
            r_l = r_u / pdf;
            specular_bounce = bs.is_specular();
            any_non_specular |= !bs.is_specular();
            let wi = bs.wi.normalize();
            // Refraction into a subsurface material: the path goes on where light leaves it, in
            // the medium it came from (entering and leaving scale radiance by 1/η² and η², so
            // eta_scale is left alone).
            if let Some(m) = subsurface::entered(&si, &bs, bsdf.ns()) {
                let outside = si.medium_interface().medium_toward(si.wo, si.shading.ng, medium);
                let (w, r_p): (&SampledWavelengths, _) = (w, r_u);
                let mut light = |b: &SurfaceInteraction, b_bsdf: &Bsdf, sampler: &mut Sampler, stats: &mut Stats| {
                    let at = Scatterer::Surface(b, b_bsdf);
                    self.sample_ld(scene, &at, outside, SampledSpectrum::one(), r_p, w, sampler, stats)
                };
                let nee = Some(&mut light as subsurface::BoundaryNee);
                medium = outside;
                match subsurface::enter(self.sss, nee, scene, m, &si, wi, (&mut beta, &mut l), w, sampler, stats) {
                    None => break,
                    Some(Exit::Vertex(vsi, vbsdf)) => {
                        pending = Some((vsi, vbsdf));
                        continue;
                    }
                    Some(Exit::Ray(exit, origin, pdf)) => {
                        // The walk's last boundary vertex sampled light and chose the way out.
                        if depth >= self.max_depth {
                            break;
                        }
                        depth += 1;
                        (ray, prev, specular_bounce) = (exit, origin, pdf.is_none());
                        any_non_specular |= pdf.is_some();
                        r_l = r_u / pdf.unwrap_or(1.0);
                    }
                }
            } else {
                if bs.is_transmission() {
                    eta_scale *= bs.eta * bs.eta;
                }
                medium = si.medium_interface().medium_toward(wi, si.shading.ng, medium);
                ray = si.spawn_ray(wi);
            }
            if beta.is_black() {
                break;
            }
            // Russian roulette on β/avg(r_u) with refraction's radiance scaling undone (pbrt-v4).
            let rr_beta = beta * eta_scale / r_u.average();
            let u_rr = sampler.get_1d();
            let m = rr_beta.max_value();
            if m < 1.0 && depth > 1 {
                let q = (1.0 - m).max(0.0);
                if u_rr < q {
                    break;
                }
                beta /= 1.0 - q;
            }
        }
        stats.last_depth = depth;
        l
    }

    /// Emission `le` of light `id` found by a path whose last sample had probabilities r_u,
    /// r_l (r_l still without the light's density), MIS-weighted against next-event estimation.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn found_emission(
        &self,
        scene: &Scene,
        id: u32,
        le: SampledSpectrum,
        beta: SampledSpectrum,
        r_u: SampledSpectrum,
        r_l: SampledSpectrum,
        specular_bounce: bool,
        prev: &LightSampleContext,
        d: Vec3,
    ) -> SampledSpectrum {
        if specular_bounce {
            return beta * le / r_u.average();
        }
        let r_l = r_l * scene.light_pdf(id, prev, d);
        beta * le / (r_u + r_l).average()
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
        if light.is_delta() {
            f / r_l.average()
        } else {
            f / (r_l + r_u * r_p * scatter_pdf).average()
        }
    }
}

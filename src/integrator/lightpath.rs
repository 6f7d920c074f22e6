//! Light tracing (pbrt-v4's `lightpath`; Arvo & Kirk 1990, Veach 1997 §10.2 with t = 1): a
//! path starts at a light chosen in proportion to its power, at a point and direction sampled
//! from its emission, walks the scene by sampling the adjoint BSDFs, and connects every vertex —
//! the light's own included — to a point on the camera's lens. Each connection lands at a film
//! position of its own and is splatted there: the estimator of every pixel is
//! (M / N) Σ h_j W_e β f |cos θ| / p(lens point), M the image's pixels, N the light paths.
//!
//! It sees what path tracing sees but for specular chains ending at the camera (a mirror or
//! glass seen directly shows nothing of the light it reflects or refracts), point or
//! pinhole-camera singularities and lights at infinity seen directly (their paths start on a
//! disk outside the scene, [`crate::light::Light::sample_le`]): its strengths are caustics seen
//! on diffuse surfaces.
//!
//! In participating media (pbrt-v4's `LightPathIntegrator` walks them as its BDPT does) the
//! path samples free flights by delta tracking ([`super::free_flight`]); a real scattering is a
//! vertex connected to the lens like a surface's, its phase function in place of the BSDF and
//! no cosine, and every lens connection carries the transmittance of its segment. Interface
//! surfaces are passed through; media do not emit here, and a subsurface material scatters as
//! its boundary BSDF.

use super::free_flight::{free_flight, segment_transmittance, spectral_mis, Flight};
use super::interface::Integrator;
use super::state::PathState;
use super::{SplatSample, Stats};
use crate::bsdf::TransportMode;
use crate::camera::{Camera, CameraWiSample};
use crate::geometry::Ray;
use crate::math::offset_ray_origin;
use crate::sampling::Sampler;
use crate::scene::{Crossings, Scene};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// A conservative bound on the rounding error of a point sampled on a light [scene units]:
/// rays leaving it start past this.
pub(super) fn light_point_error(p: Vec3) -> Vec3 {
    (p.abs() + Vec3::ONE) * 4e-6
}

impl Integrator {
    /// One light path at the wavelengths `w` and time `time`, its camera connections pushed to
    /// `splats`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn light_trace(
        &self,
        scene: &Scene,
        camera: &Camera,
        time: f32,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
        splats: &mut Vec<SplatSample>,
    ) {
        let Some((id, light, pmf, _)) = scene.sample_emitter(sampler.get_1d()) else { return };
        let (u_pos, u_dir) = (sampler.get_2d(), sampler.get_2d());
        let Some(les) = light.sample_le(u_pos, u_dir, &scene.sphere(), w) else { return };
        let cos_light = if les.n == Vec3::ZERO { 1.0 } else { les.n.dot(les.d).abs() };

        // The light seen directly: its point connected to the lens. Only lights with a surface
        // (a point light seen directly is a point of infinite radiance, which neither pbrt-v4's
        // `lightpath` nor the other estimators show; a light at infinity starts its paths on a
        // disk that is no part of the scene, and is not seen either, as in pbrt-v4).
        let u_lens = sampler.get_2d();
        let seen = les.n != Vec3::ZERO && !light.is_at_infinity();
        if let Some(cs) = camera.sample_wi(les.p, u_lens, time).filter(|_| seen) {
            let le = light.emitted_toward(&les, cs.wi, w);
            let cos = les.n.dot(cs.wi).abs();
            if !le.is_black() {
                let shadow = Ray::segment(cs.p_lens, les.p - cs.p_lens, 1.0 - 1e-4).at_time(time);
                let tr = segment_transmittance(scene, shadow, scene.camera_medium(), w, sampler, stats);
                if let Some((tr, r_l)) = tr {
                    let l = spectral_mis(le * tr * (cs.we * cos / (pmf * les.pdf_pos * cs.pdf)), r_l);
                    splats.push(SplatSample { p_raster: Some(cs.p_raster), l, lambdas: *w, strategy: None });
                }
            }
        }

        let origin = offset_ray_origin(les.p, light_point_error(les.p), les.n, les.d);
        let mut ray = Ray::new(origin, les.d.normalize()).at_time(time);
        let mut medium = scene.light_medium(id, les.n, les.d);
        let mut state = PathState::new(origin);
        state.beta = les.le * (cos_light / (pmf * les.pdf_pos * les.pdf_dir));
        let mut crossings = Crossings::default();
        loop {
            stats.rays += 1;
            let hit = scene.intersect(&ray);
            match free_flight(scene, &ray, hit.as_ref(), medium, &mut state.beta, &mut state.r_u, w, sampler) {
                Flight::Absorbed => break,
                Flight::Scattered(p, phase) => {
                    if !self.next_vertex(&mut state) {
                        break;
                    }
                    // Connect to the lens: the phase function's value, no cosine.
                    if let Some(cs) = camera.sample_wi(p, sampler.get_2d(), time) {
                        let f = SampledSpectrum::splat(phase.p(ray.d, cs.wi));
                        let shadow = Ray::segment(p, cs.p_lens - p, 1.0 - 1e-4).at_time(time);
                        self.splat_at_lens(scene, &state, f, shadow, medium, &cs, w, sampler, stats, splats);
                    }
                    // β ·= p / pdf = 1: HG is sampled exactly.
                    ray = Ray::new(p, phase.sample(ray.d, sampler.get_2d())).at_time(time);
                }
                Flight::Passed => {
                    let Some(si) = hit else { break };
                    if si.is_passthrough() {
                        // A boundary between media only: the ray goes on in the medium behind it.
                        if !crossings.allow_another() {
                            break;
                        }
                        (ray, medium) = si.pass_through(&ray, medium);
                        continue;
                    }
                    if !self.next_vertex(&mut state) {
                        break;
                    }
                    let Some(bsdf) = si.bsdf(w, None) else { break };
                    let flags = bsdf.flags();
                    if flags.is_empty() {
                        break;
                    }
                    // Connect to the lens (not through a purely specular BSDF, whose f is zero there).
                    if flags.is_non_specular() {
                        if let Some(cs) = camera.sample_wi(si.p, sampler.get_2d(), time) {
                            let f = bsdf.f(si.wo, cs.wi, TransportMode::Importance) * cs.wi.dot(bsdf.ns()).abs();
                            let toward = si.medium_interface().medium_toward(cs.wi, si.shading.ng, medium);
                            let shadow = si.spawn_ray_to(cs.p_lens);
                            self.splat_at_lens(scene, &state, f, shadow, toward, &cs, w, sampler, stats, splats);
                        }
                    }
                    let Some(bs) = bsdf.sample_f(si.wo, sampler.get_1d(), sampler.get_2d(), TransportMode::Importance)
                    else {
                        break;
                    };
                    state.beta *= bs.f * (bs.wi.dot(bsdf.ns()).abs() / bs.pdf);
                    if bs.is_transmission() {
                        state.eta_scale *= bs.eta * bs.eta;
                    }
                    let wi = bs.wi.normalize();
                    medium = si.medium_interface().medium_toward(wi, si.shading.ng, medium);
                    ray = si.spawn_ray(wi);
                }
            }
            if state.beta.is_black() || !self.roulette(&mut state, sampler) {
                break;
            }
        }
    }

    /// Splats the light path's vertex in `state`, scattering `f` (times |cos θ| at a surface)
    /// toward the lens sample `cs`, along the shadow ray `shadow` that starts in `medium`.
    #[allow(clippy::too_many_arguments)]
    fn splat_at_lens(
        &self,
        scene: &Scene,
        state: &PathState,
        f: SampledSpectrum,
        shadow: Ray,
        medium: Option<u32>,
        cs: &CameraWiSample,
        w: &SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
        splats: &mut Vec<SplatSample>,
    ) {
        if f.is_black() {
            return;
        }
        let Some((tr, r_l)) = segment_transmittance(scene, shadow, medium, w, sampler, stats) else { return };
        let l = spectral_mis(state.beta * f * tr * (cs.we / cs.pdf), state.r_u * r_l);
        splats.push(SplatSample { p_raster: Some(cs.p_raster), l, lambdas: *w, strategy: None });
    }
}

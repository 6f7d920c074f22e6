//! The two kinds of path of stochastic progressive photon mapping (Hachisuka & Jensen 2009;
//! PBR 3rd ed. §16.2; pbrt-v4 `SPPMIntegrator`): a camera path, which gathers emission and
//! direct light (next-event estimation and BSDF sampling weighted by MIS, as the path tracer)
//! up to its first diffuse vertex — the visible point, where the light arriving by one bounce
//! or more is left to photons — and a photon path, which leaves a light chosen by power and
//! offers every surface it reaches after the first to the visible points nearby. The passes
//! and the density estimate are [`crate::sppm_render`]'s.

use super::interface::Integrator;
use super::lightpath::light_point_error;
use super::state::{next_surface, PathState};
use super::Stats;
use crate::bsdf::{Bsdf, TransportMode};
use crate::geometry::Ray;
use crate::math::offset_ray_origin;
use crate::sampling::Sampler;
use crate::scene::{Crossings, Scene};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::RayDifferentials;
use glam::Vec3;

/// Where a camera path ends and gathers photons (pbrt-v4 `VisiblePoint`).
#[derive(Clone, Debug)]
pub struct VisiblePoint {
    /// Position [scene units].
    pub p: Vec3,
    /// Direction towards the camera along the path (unit).
    pub wo: Vec3,
    /// The BSDF there.
    pub bsdf: Bsdf,
    /// The camera path's throughput up to the point (camera and filter weight included).
    pub beta: SampledSpectrum,
    /// The camera path kept only the hero wavelength (a dispersive interface).
    pub secondary_terminated: bool,
}

impl VisiblePoint {
    /// The camera's measurement of a photon of throughput `beta` (at wavelengths `w`) arriving
    /// from `wi`, before the density estimate's 1/(N π r²): β_vp f(wo, wi) β, at the
    /// wavelengths both paths kept.
    pub fn photon(
        &self,
        wi: Vec3,
        beta: &SampledSpectrum,
        w: &SampledWavelengths,
    ) -> (SampledSpectrum, SampledWavelengths) {
        let mut w = *w;
        if self.secondary_terminated {
            w.terminate_secondary();
        }
        (self.beta * self.bsdf.f(self.wo, wi, TransportMode::Radiance) * *beta, w)
    }
}

impl Integrator {
    /// Follows a camera ray of throughput `beta` (the camera's and the filter's weight) to its
    /// visible point: the emission and direct light gathered on the way, and the point (`None`
    /// when the path ends before a diffuse vertex, or at a glossy one only at the depth limit).
    /// After the visible point the path takes one more BSDF-sampled step, for the emission its
    /// light sampling is weighted against.
    #[allow(clippy::too_many_arguments)]
    pub fn sppm_camera_path(
        &self,
        scene: &Scene,
        mut ray: Ray,
        beta: SampledSpectrum,
        differentials: Option<&RayDifferentials>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> (SampledSpectrum, Option<VisiblePoint>) {
        let mut state = PathState::new(ray.o);
        state.beta = beta;
        let mut visible = None;
        let mut crossings = Crossings::default();
        while let Some(si) = self.next_hit_with_emission(scene, &ray, &mut state, w, stats) {
            if si.is_passthrough() {
                if !crossings.allow_another() {
                    break;
                }
                ray = si.spawn_ray(ray.d);
                continue;
            }
            if visible.is_some() || !self.next_vertex(&mut state) {
                break;
            }
            let Some(bsdf) = self.vertex_bsdf(&si, w, differentials, &state) else { break };
            let flags = bsdf.flags();
            if flags.is_empty() {
                break;
            }
            if flags.is_non_specular() {
                state.l += state.beta * self.sample_light(scene, &si, &bsdf, w, sampler, stats);
            }
            if flags.is_diffuse() || (flags.is_glossy() && state.depth == self.max_depth) {
                visible = Some(VisiblePoint {
                    p: si.p,
                    wo: si.wo,
                    bsdf: bsdf.clone(),
                    beta: state.beta,
                    secondary_terminated: w.secondary_terminated(),
                });
            }
            let Some(bs) = self.sample_bsdf(&si, &bsdf, sampler, &mut state) else { break };
            if bs.is_transmission() {
                state.eta_scale *= bs.eta * bs.eta;
            }
            ray = si.spawn_ray(bs.wi);
            if state.beta.is_black() || !self.roulette(&mut state, sampler) {
                break;
            }
        }
        stats.last_depth = state.depth;
        (state.l, visible)
    }

    /// One photon path at the wavelengths `w`: from a light chosen in proportion to its power,
    /// through at most `max_depth` surfaces, each found after the first offered to
    /// `deposit(p, wi, β, w)` (its position, the direction the photon came from, its
    /// throughput [W/nm per photon path] and wavelengths). It continues by sampling the adjoint
    /// BSDF, and Russian roulette keeps its throughput about constant (survival = the ratio of
    /// the new throughput's largest component to the old one's, as pbrt-v4).
    pub fn sppm_photon_path(
        &self,
        scene: &Scene,
        mut w: SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
        mut deposit: impl FnMut(Vec3, Vec3, &SampledSpectrum, &SampledWavelengths),
    ) {
        let Some((_, light, pmf, _)) = scene.sample_emitter(sampler.get_1d()) else { return };
        let (u_pos, u_dir) = (sampler.get_2d(), sampler.get_2d());
        let time = scene.shutter.map_or(0.0, |(open, close)| open + (close - open) * sampler.get_1d());
        let Some(les) =
            light.sample_le(u_pos, u_dir, &scene.sphere(), &w).filter(|l| l.pdf_pos > 0.0 && l.pdf_dir > 0.0)
        else {
            return;
        };
        let cos_light = if les.n == Vec3::ZERO { 1.0 } else { les.n.dot(les.d).abs() };
        let mut beta = les.le * (cos_light / (pmf * les.pdf_pos * les.pdf_dir));
        let origin = offset_ray_origin(les.p, light_point_error(les.p), les.n, les.d);
        let mut ray = Ray::new(origin, les.d).at_time(time);
        for depth in 0..self.max_depth {
            if beta.is_black() {
                break;
            }
            let Some(si) = next_surface(scene, ray, stats) else { break };
            // The first surface's light is the camera paths' direct light.
            if depth > 0 {
                deposit(si.p, si.wo, &beta, &w);
            }
            let Some(bsdf) = si.bsdf(&mut w, None) else { break };
            let Some(bs) = bsdf.sample_f(si.wo, sampler.get_1d(), sampler.get_2d(), TransportMode::Importance) else {
                break;
            };
            let next = beta * bs.f * (bs.wi.dot(bsdf.ns()).abs() / bs.pdf);
            let q = (1.0 - next.max_value() / beta.max_value()).max(0.0);
            if sampler.get_1d() < q {
                break;
            }
            beta = next / (1.0 - q);
            ray = si.spawn_ray(bs.wi);
        }
    }
}

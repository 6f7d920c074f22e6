//! Unidirectional path tracing of the reflection equation L_o = L_e + ∫ f_r L_i cos θ_i dω_i
//! (lecture: "BRDF"), with next-event estimation and BSDF sampling combined by multiple importance
//! sampling (Veach 1997, power heuristic β = 2) and Russian roulette.

use super::subsurface::{self, Exit, SubsurfaceMethod};
use super::Stats;
use crate::bsdf::{Bsdf, Diffuse, TransportMode};
use crate::geometry::Ray;
use crate::light::Light;
use crate::material::Material;
use crate::math::PI;
use crate::sampling::mis::power_heuristic;
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// Which estimators of direct light to use (for validating MIS: all three must agree).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectStrategy {
    /// NEE and BSDF sampling, weighted by the power heuristic.
    Mis,
    /// Only light sampling (emission found by BSDF sampling is ignored, except via delta lobes).
    LightOnly,
    /// Only BSDF sampling (no shadow rays).
    BsdfOnly,
}

/// A `max_depth` of no limit: Russian roulette alone ends paths.
pub const UNBOUNDED_DEPTH: u32 = u32::MAX;

/// The path tracer's settings.
#[derive(Clone, Copy, Debug)]
pub struct PathIntegrator {
    /// Maximum number of scattering events, or [`UNBOUNDED_DEPTH`].
    pub max_depth: u32,
    /// Depth from which Russian roulette may end paths.
    pub rr_depth: u32,
    /// Direct-light estimator.
    pub strategy: DirectStrategy,
    /// How paths entering subsurface materials continue.
    pub sss: SubsurfaceMethod,
}

impl Default for PathIntegrator {
    fn default() -> Self {
        Self { max_depth: 8, rr_depth: 3, strategy: DirectStrategy::Mis, sss: SubsurfaceMethod::default() }
    }
}

impl PathIntegrator {
    /// Radiance [W/(sr·m²·nm)] arriving along `ray` at its origin, at the wavelengths `w` (which a
    /// dispersive interface may reduce to the hero wavelength).
    pub fn li(
        &self,
        scene: &Scene,
        ray: Ray,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        self.trace(scene, ray, None, w, sampler, stats)
    }

    /// Irradiance E [W/(m²·nm)] at `p` on a surface with unit normal `n`, by the full integrator:
    /// an ideal white Lambertian sensor at `p` reflects L_o = E/π (lecture: E = ∫ L_i cos θ dω),
    /// so E = π L_o, with L_o estimated by NEE + BSDF sampling + MIS like any other surface.
    pub fn irradiance(
        &self,
        scene: &Scene,
        p: Vec3,
        n: Vec3,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let si = SurfaceInteraction::sensor(p, n);
        let bsdf = Bsdf::new(n, Vec3::ZERO, n, Diffuse::new(SampledSpectrum::one()).into());
        let probe = Ray::new(p + n, -n); // only its origin matters for MIS bookkeeping
        self.trace(scene, probe, Some((si, bsdf)), w, sampler, stats) * PI
    }

    fn trace(
        &self,
        scene: &Scene,
        mut ray: Ray,
        mut first: Option<(SurfaceInteraction, Bsdf)>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let mut l = SampledSpectrum::zero();
        let mut beta = SampledSpectrum::one();
        let mut specular_bounce = true; // the camera ray counts as a delta event
        let mut prev_pdf = 0.0f32; // solid-angle pdf of the BSDF sample that made `ray`
        let mut prev_p = ray.o;
        let mut eta_scale = 1.0f32;
        let use_nee = self.strategy != DirectStrategy::BsdfOnly;
        let use_bsdf_hits = self.strategy != DirectStrategy::LightOnly;
        // MIS weight of emission found by BSDF sampling, given the light's solid-angle pdf.
        let hit_weight = |specular: bool, prev_pdf: f32, p_light: f32| {
            if specular || !use_nee {
                1.0
            } else if !use_bsdf_hits {
                0.0
            } else {
                power_heuristic(1, prev_pdf, 1, p_light)
            }
        };

        let mut depth = 0u32;
        loop {
            let (si, bsdf, material) = match first.take() {
                Some((si, bsdf)) => (si, bsdf, None),
                None => {
                    stats.rays += 1;
                    let Some(hit) = scene.accel.intersect(&ray) else {
                        let d = ray.d.normalize();
                        for &li in &scene.infinite_lights {
                            let light = &scene.lights[li];
                            let p_light = scene.light_sampler.pmf(li) * light.pdf_li(prev_p, d, prev_p, d);
                            l += beta * light.escaped_radiance(d, w) * hit_weight(specular_bounce, prev_pdf, p_light);
                        }
                        break;
                    };
                    let si = SurfaceInteraction::new(scene, &ray, &hit);
                    if let Some(li) = scene.area_light_index(hit.geom_id, hit.prim_id) {
                        if let Light::Area(area) = &scene.lights[li] {
                            let le = area.radiance(si.wo, w);
                            if !le.is_black() {
                                let p_light =
                                    scene.light_sampler.pmf(li) * area.pdf_li(prev_p, -si.wo, si.p, si.shading.ng);
                                l += beta * le * hit_weight(specular_bounce, prev_pdf, p_light);
                            }
                        }
                    }
                    if depth == self.max_depth {
                        break;
                    }
                    let material = &scene.materials[scene.mesh_material[si.mesh as usize] as usize];
                    let bsdf = material.bsdf(&si.shading, w);
                    (si, bsdf, Some(material))
                }
            };
            depth += 1;
            let flags = bsdf.flags();
            if flags.is_empty() {
                break;
            }

            // Next-event estimation (not for purely specular BSDFs, whose f is zero off the delta).
            if use_nee && flags.is_non_specular() {
                l += beta * self.sample_light(scene, &si, &bsdf, w, sampler, stats);
            }

            // Continue the path by sampling the BSDF.
            let uc = sampler.get_1d();
            let u = sampler.get_2d();
            let Some(bs) = bsdf.sample_f(si.wo, uc, u, TransportMode::Radiance) else { break };
            let cos = bs.wi.dot(si.shading.ns).abs();
            beta *= bs.f * (cos / bs.pdf);
            prev_pdf = if bs.pdf_is_proportional { bsdf.pdf(si.wo, bs.wi, TransportMode::Radiance) } else { bs.pdf };
            specular_bounce = bs.is_specular();
            ray = si.spawn_ray(bs.wi);
            prev_p = si.p;
            if bs.is_transmission() {
                // Refraction into a subsurface medium: continue where light leaves it. Entering and
                // leaving scale radiance by 1/η² and η², so eta_scale is left alone.
                if let (Some(Material::Subsurface(m)), true) = (material, bs.wi.dot(si.shading.ns) < 0.0) {
                    match subsurface::enter(self, scene, m, &si, bs.wi, (&mut beta, &mut l), w, sampler, stats) {
                        None => break,
                        Some(Exit::Vertex(vsi, vbsdf)) => {
                            first = Some((vsi, vbsdf));
                            continue;
                        }
                        Some(Exit::Ray(exit, origin, pdf)) => {
                            (ray, prev_p, specular_bounce, prev_pdf) =
                                (exit, origin, pdf.is_none(), pdf.unwrap_or(0.0));
                        }
                    }
                } else {
                    eta_scale *= bs.eta * bs.eta;
                }
            }
            if beta.is_black() {
                break;
            }

            // Russian roulette on the throughput with the radiance-scaling of refraction undone:
            // survival min(max β, 1) (pbrt-v4). With no depth limit, a path whose throughput
            // stays ≥ 1 (a closed white room) must still end, so survival is at most 0.95 there
            // (Mitsuba 3's rule).
            let rr_beta = beta * eta_scale;
            let cap = if self.max_depth == UNBOUNDED_DEPTH { 0.95 } else { 1.0 };
            let survival = rr_beta.max_value().min(cap);
            if depth >= self.rr_depth && survival < 1.0 {
                let q = (1.0 - survival).max(0.0);
                if sampler.get_1d() < q {
                    break;
                }
                beta /= 1.0 - q;
            }
        }
        stats.last_depth = depth;
        l
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
        let ul = sampler.get_1d();
        let u = sampler.get_2d();
        let Some((li, pmf)) = scene.light_sampler.sample(ul) else { return SampledSpectrum::zero() };
        let light = &scene.lights[li];
        let Some(ls) = light.sample_li(si.p, u, w) else { return SampledSpectrum::zero() };
        if ls.pdf <= 0.0 || ls.li.is_black() {
            return SampledSpectrum::zero();
        }
        let f = bsdf.f(si.wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(si.shading.ns).abs();
        if f.is_black() {
            return SampledSpectrum::zero();
        }
        stats.rays += 1;
        let shadow = if ls.dist.is_finite() { si.spawn_ray_to(ls.p_light) } else { si.spawn_ray(ls.wi) };
        if scene.accel.occluded(&shadow) {
            return SampledSpectrum::zero();
        }
        let p_light = pmf * ls.pdf;
        let weight = if light.is_delta() || self.strategy == DirectStrategy::LightOnly {
            1.0
        } else {
            power_heuristic(1, p_light, 1, bsdf.pdf(si.wo, ls.wi, TransportMode::Radiance))
        };
        f * ls.li * (weight / p_light)
    }
}

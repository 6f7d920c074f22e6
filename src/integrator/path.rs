//! Unidirectional path tracing of the reflection equation L_o = L_e + ∫ f_r L_i cos θ_i dω_i
//! (Kajiya 1986), with next-event estimation and BSDF sampling combined by multiple importance
//! sampling (Veach 1997, power heuristic β = 2) and Russian roulette.

use super::subsurface::{self, Exit, SubsurfaceMethod};
use super::Stats;
use crate::bsdf::{Bsdf, Diffuse, TransportMode};
use crate::geometry::Ray;
use crate::light::LightSampleContext;
use crate::math::PI;
use crate::sampling::mis::power_heuristic;
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction, MAX_INTERFACE_CROSSINGS};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{Footprint, RayDifferentials, TextureFootprint};
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

pub use crate::settings::UNBOUNDED_DEPTH;

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
    /// The camera's pixel footprint, for filtered texture lookups (`None`: unfiltered, the
    /// finest texture detail everywhere).
    pub footprint: Option<TextureFootprint>,
    /// pbrt-v4's `regularize`: after the first non-specular bounce every microfacet lobe is
    /// widened ([`crate::bsdf::TrowbridgeReitz::regularize`]), trading bias for caustics that
    /// light sampling can find.
    pub regularize: bool,
}

impl Default for PathIntegrator {
    fn default() -> Self {
        Self {
            max_depth: 8,
            rr_depth: 3,
            strategy: DirectStrategy::Mis,
            sss: SubsurfaceMethod::default(),
            footprint: None,
            regularize: false,
        }
    }
}

/// What the path loop carries from one vertex to the next (the locals of pbrt-v4's
/// `PathIntegrator::Li`, §13.4).
#[derive(Clone, Copy, Debug)]
struct PathState {
    /// Radiance gathered so far.
    l: SampledSpectrum,
    /// Throughput β: the path's weight per unit radiance arriving along the current ray.
    beta: SampledSpectrum,
    /// Product of η² over the refractions so far, undone for Russian roulette (pbrt-v4
    /// `etaScale`): radiance scaled by refraction is not a reason to end a path.
    eta_scale: f32,
    /// The vertex the current ray left (point and shading normal): the reference of the light's
    /// pdf when the ray finds emission, for MIS against next-event estimation.
    prev: LightSampleContext,
    /// Solid-angle pdf of the sample that made the current ray.
    prev_pdf: f32,
    /// The current ray came from a delta lobe (or is the camera ray): emission it finds was not
    /// sampled by next-event estimation.
    specular_bounce: bool,
    /// Scattering vertices so far; every vertex counts, subsurface exits included.
    depth: u32,
    /// Some earlier vertex sampled a non-delta lobe (pbrt-v4 `anyNonSpecularBounces`).
    any_non_specular: bool,
}

impl PathState {
    fn new(origin: Vec3) -> Self {
        Self {
            l: SampledSpectrum::zero(),
            beta: SampledSpectrum::one(),
            eta_scale: 1.0,
            prev: LightSampleContext::medium(origin),
            prev_pdf: 0.0,
            specular_bounce: true,
            depth: 0,
            any_non_specular: false,
        }
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
        self.trace(scene, ray, None, None, w, sampler, stats)
    }

    /// [`Self::li`] for a camera ray with its differentials, which give the texture footprint
    /// at its first hit.
    pub fn li_camera(
        &self,
        scene: &Scene,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        self.trace(scene, ray, differentials, None, w, sampler, stats)
    }

    /// Irradiance E [W/(m²·nm)] at `p` on a surface with unit normal `n`, by the full integrator:
    /// an ideal white Lambertian sensor at `p` reflects L_o = E/π (E = ∫ L_i cos θ dω), so
    /// E = π L_o, with L_o estimated by NEE + BSDF sampling + MIS like any other surface.
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
        self.trace(scene, probe, None, Some((si, bsdf)), w, sampler, stats) * PI
    }

    /// MIS weight of emission found by BSDF sampling, given the light's solid-angle pdf.
    fn emission_weight(&self, state: &PathState, p_light: f32) -> f32 {
        if state.specular_bounce || self.strategy == DirectStrategy::BsdfOnly {
            1.0
        } else if self.strategy == DirectStrategy::LightOnly {
            0.0
        } else {
            power_heuristic(1, state.prev_pdf, 1, p_light)
        }
    }

    /// The path loop. `differentials` are the camera ray's, `pending` is a vertex found without
    /// tracing the current ray (the irradiance sensor; a subsurface exit), whose BSDF is given.
    #[allow(clippy::too_many_arguments)]
    fn trace<'s>(
        &self,
        scene: &'s Scene,
        mut ray: Ray,
        differentials: Option<&RayDifferentials>,
        mut pending: Option<(SurfaceInteraction<'s>, Bsdf)>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let mut state = PathState::new(ray.o);
        let use_nee = self.strategy != DirectStrategy::BsdfOnly;
        let mut crossings = 0;
        loop {
            // The next vertex, and the emission the ray finds there.
            let (si, given_bsdf) = match pending.take() {
                Some((si, bsdf)) => (si, Some(bsdf)),
                None => {
                    stats.rays += 1;
                    let Some(si) = scene.intersect(&ray) else {
                        let d = ray.d.normalize();
                        for (id, light) in scene.infinite_lights() {
                            let weight = self.emission_weight(&state, scene.light_pdf(id, &state.prev, d));
                            state.l += state.beta * light.escaped_radiance(ray.o, d, w) * weight;
                        }
                        break;
                    };
                    if let Some((id, _)) = si.area_light() {
                        let le = si.emitted(w);
                        if !le.is_black() {
                            let weight = self.emission_weight(&state, scene.light_pdf(id, &state.prev, -si.wo));
                            state.l += state.beta * le * weight;
                        }
                    }
                    if si.is_passthrough() {
                        // No surface: the same ray goes on, and the previous vertex stays the
                        // one MIS weights refer to.
                        crossings += 1;
                        if crossings > MAX_INTERFACE_CROSSINGS {
                            break;
                        }
                        ray = si.spawn_ray(ray.d);
                        continue;
                    }
                    (si, None)
                }
            };
            // Every vertex counts toward the depth limit, a subsurface exit included.
            if state.depth == self.max_depth {
                break;
            }
            state.depth += 1;
            // The BSDF is borrowed where it was built, not moved (it is larger than the
            // compiler copies without a `memcpy` call).
            let mut computed;
            let bsdf = match &given_bsdf {
                Some(b) => b,
                None => {
                    let footprint = Footprint::of_vertex(self.footprint.as_ref(), differentials, state.depth == 1);
                    computed = si.bsdf(w, footprint);
                    if let Some(b) = computed.as_mut().filter(|_| self.regularize && state.any_non_specular) {
                        b.bxdf.regularize();
                    }
                    match &computed {
                        Some(b) => b,
                        None => break,
                    }
                }
            };
            let flags = bsdf.flags();
            if flags.is_empty() {
                break;
            }

            // Next-event estimation (not for purely specular BSDFs, whose f is zero off the delta).
            if use_nee && flags.is_non_specular() {
                state.l += state.beta * self.sample_light(scene, &si, bsdf, w, sampler, stats);
            }

            // Continue the path by sampling the BSDF.
            let uc = sampler.get_1d();
            let u = sampler.get_2d();
            let Some(bs) = bsdf.sample_f(si.wo, uc, u, TransportMode::Radiance) else { break };
            let cos = bs.wi.dot(bsdf.ns()).abs();
            state.beta *= bs.f * (cos / bs.pdf);
            state.prev_pdf =
                if bs.pdf_is_proportional { bsdf.pdf(si.wo, bs.wi, TransportMode::Radiance) } else { bs.pdf };
            state.specular_bounce = bs.is_specular();
            state.any_non_specular |= !bs.is_specular();
            ray = si.spawn_ray(bs.wi);
            state.prev = LightSampleContext::surface(si.p, bsdf.ns());
            if bs.is_transmission() {
                // Refraction into a subsurface medium: continue where light leaves it. Entering and
                // leaving scale radiance by 1/η² and η², so eta_scale is left alone.
                if let Some(m) = subsurface::entered(&si, &bs, bsdf.ns()) {
                    let w: &SampledWavelengths = w;
                    let mut light = |b: &SurfaceInteraction, bsdf: &Bsdf, sampler: &mut Sampler, stats: &mut Stats| {
                        self.sample_light(scene, b, bsdf, w, sampler, stats)
                    };
                    match subsurface::enter(
                        self.sss,
                        use_nee.then_some(&mut light as subsurface::BoundaryNee),
                        scene,
                        m,
                        &si,
                        bs.wi,
                        (&mut state.beta, &mut state.l),
                        w,
                        sampler,
                        stats,
                    ) {
                        None => break,
                        Some(Exit::Vertex(vsi, vbsdf)) => {
                            pending = Some((vsi, vbsdf));
                            continue;
                        }
                        Some(Exit::Ray(exit, origin, pdf)) => {
                            // The walk's last boundary vertex did its own light sampling and
                            // chose the way out: it counts as a vertex like the diffusion exit.
                            if state.depth == self.max_depth {
                                break;
                            }
                            state.depth += 1;
                            (ray, state.prev, state.specular_bounce, state.prev_pdf) =
                                (exit, origin, pdf.is_none(), pdf.unwrap_or(0.0));
                        }
                    }
                } else {
                    state.eta_scale *= bs.eta * bs.eta;
                }
            }
            if state.beta.is_black() {
                break;
            }

            // Russian roulette on the throughput with the radiance-scaling of refraction undone:
            // survival min(max β, 1) (pbrt-v4). With no depth limit, a path whose throughput
            // stays ≥ 1 (a closed white room) must still end, so survival is at most 0.95 there
            // (Mitsuba 3's rule).
            let rr_beta = state.beta * state.eta_scale;
            let cap = if self.max_depth == UNBOUNDED_DEPTH { 0.95 } else { 1.0 };
            let survival = rr_beta.max_value().min(cap);
            if state.depth >= self.rr_depth && survival < 1.0 {
                let q = (1.0 - survival).max(0.0);
                if sampler.get_1d() < q {
                    break;
                }
                state.beta /= 1.0 - q;
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
        let Some(ls) = light.sample_li(&ctx, u, w) else { return SampledSpectrum::zero() };
        if ls.pdf <= 0.0 || ls.li.is_black() {
            return SampledSpectrum::zero();
        }
        let f = bsdf.f(si.wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(bsdf.ns()).abs();
        if f.is_black() {
            return SampledSpectrum::zero();
        }
        stats.rays += 1;
        let shadow = if ls.dist.is_finite() { si.spawn_ray_to(ls.p_light) } else { si.spawn_ray(ls.wi) };
        if scene.occluded(&shadow) {
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

//! The path state both path loops carry, and the per-vertex steps they share: counting a
//! vertex, the vertex's BSDF, continuing by BSDF sampling, and Russian roulette. The
//! surface loop ([`super::path`]) and the volumetric loop ([`super::volpath`]) differ only in
//! the medium step and in how they weight emission against light sampling (the power heuristic
//! on solid-angle densities, or the balance heuristic on the rescaled path probabilities of
//! spectral MIS).

use super::interface::Integrator;
use super::visible_surface::visible_surface;
use super::Stats;
use crate::bsdf::{Bsdf, BsdfSample, TransportMode};
use crate::film::VisibleSurface;
use crate::geometry::Ray;
use crate::light::LightSampleContext;
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction, MAX_INTERFACE_CROSSINGS};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{Footprint, RayDifferentials};
use glam::Vec3;

/// What a path loop carries from one vertex to the next (the locals of pbrt-v4's
/// `VolPathIntegrator::Li`, §14.2).
#[derive(Clone, Copy, Debug)]
pub(super) struct PathState {
    /// Radiance gathered so far.
    pub l: SampledSpectrum,
    /// Throughput β: the path's weight per unit radiance arriving along the current ray.
    pub beta: SampledSpectrum,
    /// Rescaled unidirectional path probability r_u per wavelength (the path's density at
    /// each wavelength over the hero wavelength's; spectral MIS divides by its average). One at
    /// every wavelength in the surface loop, whose distances do not depend on wavelength.
    pub r_u: SampledSpectrum,
    /// Rescaled light-sampling path probability r_l (the volumetric loop's MIS).
    pub r_l: SampledSpectrum,
    /// Product of η² over the refractions so far, undone for Russian roulette (pbrt-v4
    /// `etaScale`): radiance scaled by refraction is not a reason to end a path.
    pub eta_scale: f32,
    /// The vertex the current ray left (point and shading normal): the reference of the light's
    /// pdf when the ray finds emission, for MIS against next-event estimation.
    pub prev: LightSampleContext,
    /// Solid-angle pdf of the sample that made the current ray.
    pub prev_pdf: f32,
    /// The current ray came from a delta lobe (or is the camera ray): emission it finds was not
    /// sampled by next-event estimation.
    pub specular_bounce: bool,
    /// Scattering vertices so far; every vertex counts, medium scattering and subsurface exits
    /// included.
    pub depth: u32,
    /// Some earlier vertex sampled a non-delta lobe (pbrt-v4 `anyNonSpecularBounces`).
    pub any_non_specular: bool,
}

impl PathState {
    /// A path starting at `origin` (the camera, or a probe's origin).
    pub fn new(origin: Vec3) -> Self {
        Self {
            l: SampledSpectrum::zero(),
            beta: SampledSpectrum::one(),
            r_u: SampledSpectrum::one(),
            r_l: SampledSpectrum::one(),
            eta_scale: 1.0,
            prev: LightSampleContext::medium(origin),
            prev_pdf: 0.0,
            specular_bounce: true,
            depth: 0,
            any_non_specular: false,
        }
    }
}

/// A depth limit from which a path's survival probability is capped at 0.95, as without a
/// limit: a path whose throughput stays ≥ 1 (a closed lossless room) would otherwise run to the
/// limit, and no estimate needs paths this long (0.95^1024 ≈ 10⁻²³).
pub(super) const ROULETTE_CAP_DEPTH: u32 = 1024;

impl Integrator {
    /// Counts a new scattering vertex; false when the depth limit ends the path there.
    #[inline(always)]
    pub(super) fn next_vertex(&self, state: &mut PathState) -> bool {
        if state.depth >= self.max_depth {
            return false;
        }
        state.depth += 1;
        true
    }

    /// The BSDF at a surface vertex: textures filtered over the footprint (the camera ray's
    /// own differentials at the first vertex), microfacet lobes widened when regularising
    /// after a non-specular bounce. `None`: the surface does not scatter.
    #[inline(always)]
    pub(super) fn vertex_bsdf(
        &self,
        si: &SurfaceInteraction,
        w: &mut SampledWavelengths,
        differentials: Option<&RayDifferentials>,
        state: &PathState,
    ) -> Option<Bsdf> {
        let footprint = Footprint::of_vertex(self.footprint.as_ref(), differentials, state.depth == 1);
        let mut bsdf = si.bsdf(w, footprint)?;
        if self.regularize && state.any_non_specular {
            bsdf.bxdf.regularize();
        }
        Some(bsdf)
    }

    /// Records the camera ray's first surface vertex for the geometry buffers, when they are
    /// asked for (`visible`) and this is that vertex.
    pub(super) fn record_visible(
        &self,
        visible: &mut Option<&mut Option<VisibleSurface>>,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        differentials: Option<&RayDifferentials>,
        state: &PathState,
    ) {
        if let Some(v) = visible.as_deref_mut().filter(|_| state.depth == 1) {
            let footprint = Footprint::of_vertex(self.footprint.as_ref(), differentials, true);
            *v = Some(visible_surface(si, bsdf, footprint));
        }
    }

    /// Continues the path by sampling the BSDF at `si`: β ·= f |cos θ| / pdf, and the MIS and
    /// roulette bookkeeping of the new ray (its density, whether it is specular, its origin).
    /// `None`: the BSDF sampled nothing and the path ends.
    #[inline(always)]
    pub(super) fn sample_bsdf(
        &self,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        sampler: &mut Sampler,
        state: &mut PathState,
    ) -> Option<BsdfSample> {
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let bs = bsdf.sample_f(si.wo, uc, u, TransportMode::Radiance)?;
        let cos = bs.wi.dot(bsdf.ns()).abs();
        state.beta *= bs.f * (cos / bs.pdf);
        state.prev_pdf = if bs.pdf_is_proportional { bsdf.pdf(si.wo, bs.wi, TransportMode::Radiance) } else { bs.pdf };
        state.r_l = state.r_u / state.prev_pdf;
        state.specular_bounce = bs.is_specular();
        state.any_non_specular |= !bs.is_specular();
        state.prev = LightSampleContext::surface(si.p, bsdf.ns());
        Some(bs)
    }

    /// Russian roulette: true when the path survives (its throughput then divided by the
    /// survival probability), false when it ends. The survival probability is
    /// min(max(β η_scale / avg r_u), 1) while that maximum is below `rr_threshold`, and at most
    /// 0.95 without a depth limit or with one of at least [`ROULETTE_CAP_DEPTH`]; paths
    /// shallower than `rr_depth` always survive.
    #[inline(always)]
    pub(super) fn roulette(&self, state: &mut PathState, sampler: &mut Sampler) -> bool {
        let rr_beta = (state.beta * state.eta_scale / state.r_u.average()).max_value();
        let cap = if self.max_depth >= ROULETTE_CAP_DEPTH { 0.95 } else { 1.0 };
        let survival = if rr_beta < self.rr_threshold { rr_beta.min(cap) } else { cap };
        if state.depth >= self.rr_depth && survival < 1.0 {
            let q = (1.0 - survival).max(0.0);
            if sampler.get_1d() < q {
                return false;
            }
            state.beta /= 1.0 - q;
        }
        true
    }
}

/// The first surface along `ray` that is not only a boundary between media (the estimators
/// that ignore media look through those), or `None` when the ray escapes.
pub(super) fn next_surface<'s>(scene: &'s Scene, mut ray: Ray, stats: &mut Stats) -> Option<SurfaceInteraction<'s>> {
    for _ in 0..=MAX_INTERFACE_CROSSINGS {
        stats.rays += 1;
        let si = scene.intersect(&ray)?;
        if !si.is_passthrough() {
            return Some(si);
        }
        ray = si.spawn_ray(ray.d);
    }
    None
}

/// The radiance of every infinite light along `ray`, which escaped the scene (unweighted: for
/// the estimators that do not weigh emission against light sampling).
pub(super) fn escaped_radiance(scene: &Scene, ray: &Ray, w: &SampledWavelengths) -> SampledSpectrum {
    let d = ray.d.normalize();
    scene.infinite_lights().fold(SampledSpectrum::zero(), |l, (_, light)| l + light.escaped_radiance(ray.o, d, w))
}

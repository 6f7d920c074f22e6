//! The one integrator interface: which estimator renders the scene and the settings every
//! estimator shares (depth limit, Russian roulette, direct-light strategy, subsurface method,
//! texture footprint, regularisation). `render`, `measure`, `bench` and the reports all take an
//! [`Integrator`] from the render settings and call [`Integrator::li_camera`],
//! [`Integrator::li`] or [`Integrator::irradiance`]; which loop runs is decided here.

use super::options::{AmbientOcclusion, FunctionOptions, Mlt, SimplePath, Sppm, StrategyImageKind};
use super::subsurface::SubsurfaceMethod;
use super::{SplatSample, Stats};
use crate::bsdf::{Bsdf, Diffuse};
use crate::camera::Camera;
use crate::film::VisibleSurface;
use crate::geometry::Ray;
use crate::math::PI;
use crate::media::Medium;
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{RayDifferentials, TextureFootprint};
use glam::Vec3;

pub use crate::settings::UNBOUNDED_DEPTH;

/// The estimators prism renders with, by pbrt-v4's `Integrator` names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    /// `path`: unidirectional path tracing of surfaces (pbrt-v4 `Integrator`).
    #[default]
    Path,
    /// `volpath`: path tracing with participating media by null scattering (pbrt-v4
    /// `VolPathIntegrator`).
    VolPath,
    /// `ambientocclusion`: the open fraction of the first surface's hemisphere (pbrt-v4
    /// `AOIntegrator`).
    AmbientOcclusion,
    /// `randomwalk`: uniform directions, emission only where found (pbrt-v4
    /// `RandomWalkIntegrator`).
    RandomWalk,
    /// `simplepath`: path tracing without MIS or Russian roulette (pbrt-v4
    /// `SimplePathIntegrator`).
    SimplePath,
    /// `simplevolpath`: delta tracking at the hero wavelength, without light sampling (pbrt-v4
    /// `SimpleVolPathIntegrator`).
    SimpleVolPath,
    /// `lightpath`: light tracing, every light-path vertex connected to the camera and splatted
    /// onto the film (pbrt-v4 `LightPathIntegrator`).
    LightPath,
    /// `bdpt`: bidirectional path tracing, every connection of a camera and a light subpath
    /// weighted by the balance heuristic (pbrt-v4 `BDPTIntegrator`).
    Bdpt,
    /// `mlt`: Metropolis light transport in primary sample space over bdpt's strategies
    /// (pbrt-v4 `MLTIntegrator`).
    Mlt,
    /// `sppm`: stochastic progressive photon mapping (Hachisuka & Jensen 2009; pbrt-v4
    /// `SPPMIntegrator`): passes of camera paths ending at visible points and of photon paths
    /// whose hits near them estimate the light they reflect. Its loop is its own
    /// (`crate::sppm_render`); per camera sample it estimates as `path`.
    Sppm,
    /// `function`: pbrt-v4's test of the samplers (`FunctionIntegrator`), which integrates a
    /// fixed function of the pixel samples, not the scene ([`super::FunctionTest`]; the command
    /// line runs it instead of a render). Asked for a camera sample's radiance, it estimates as
    /// `path`.
    Function,
}

crate::named::name_table!(IntegratorKind, "integrator", {
    "path" => IntegratorKind::Path,
    "volpath" => IntegratorKind::VolPath,
    "ambientocclusion" => IntegratorKind::AmbientOcclusion,
    "randomwalk" => IntegratorKind::RandomWalk,
    "simplepath" => IntegratorKind::SimplePath,
    "simplevolpath" => IntegratorKind::SimpleVolPath,
    "lightpath" => IntegratorKind::LightPath,
    "bdpt" => IntegratorKind::Bdpt,
    "mlt" => IntegratorKind::Mlt,
    "sppm" => IntegratorKind::Sppm,
    "function" => IntegratorKind::Function,
});

impl IntegratorKind {
    /// True for the estimators that splat light onto arbitrary film positions (the film then
    /// needs a [`crate::film::SplatBuffer`]).
    pub fn splats(self) -> bool {
        matches!(self, IntegratorKind::LightPath | IntegratorKind::Bdpt | IntegratorKind::Mlt)
    }
}

/// Which estimators of direct light to use (for validating MIS: all three must agree).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectStrategy {
    /// NEE and BSDF sampling, weighted by MIS.
    Mis,
    /// Only light sampling (emission found by BSDF sampling is ignored, except via delta lobes).
    LightOnly,
    /// Only BSDF sampling (no shadow rays).
    BsdfOnly,
}

/// An integrator: the estimator and the settings all estimators share.
#[derive(Clone, Copy, Debug)]
pub struct Integrator {
    /// The estimator. [`Self::for_scene`] resolves it against the scene.
    pub kind: IntegratorKind,
    /// Maximum number of scattering events (surface, medium and subsurface exits alike), or
    /// [`UNBOUNDED_DEPTH`].
    pub max_depth: u32,
    /// Depth from which Russian roulette may end paths. The survival probability is
    /// min(max β', 1), β' the throughput with refraction's radiance scaling (and, in media,
    /// the spectral MIS normalisation) undone, as pbrt-v4; with [`UNBOUNDED_DEPTH`], or any depth
    /// limit of 1024 or more, it is at most 0.95, so a path whose throughput stays ≥ 1 (a closed
    /// white room) still ends (Mitsuba 3's rule).
    pub rr_depth: u32,
    /// pbrt's `rrthreshold`: roulette plays only while max β' is below it (1 by default, where
    /// it changes nothing; 0 turns roulette off but for the unbounded-depth cap).
    pub rr_threshold: f32,
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
    /// The parameters of `ambientocclusion`.
    pub ao: AmbientOcclusion,
    /// The parameters of `simplepath`.
    pub simple: SimplePath,
    /// The parameters of `mlt`.
    pub mlt: Mlt,
    /// `bdpt`'s per-strategy images.
    pub strategy_images: StrategyImageKind,
    /// The parameters of `sppm`.
    pub sppm: Sppm,
    /// The parameters of `function`.
    pub function: FunctionOptions,
}

impl Default for Integrator {
    fn default() -> Self {
        Self {
            kind: IntegratorKind::Path,
            max_depth: 8,
            rr_depth: 3,
            rr_threshold: 1.0,
            strategy: DirectStrategy::Mis,
            sss: SubsurfaceMethod::default(),
            footprint: None,
            regularize: false,
            ao: AmbientOcclusion::default(),
            simple: SimplePath::default(),
            mlt: Mlt::default(),
            strategy_images: StrategyImageKind::Off,
            sppm: Sppm::default(),
            function: FunctionOptions::default(),
        }
    }
}

impl Integrator {
    /// The integrator a scene file asks for (its `Integrator` directive's type, "maxdepth",
    /// "rrthreshold", "regularize", the small estimators' parameters and `bdpt`'s
    /// "visualizestrategies" and "visualizeweights"), prism's defaults for what the file leaves
    /// out.
    pub fn from_file(file: &crate::pbrt::FileSettings) -> Self {
        let d = Self::default();
        Self {
            kind: file.integrator.as_deref().and_then(|n| IntegratorKind::parse(n).ok()).unwrap_or(d.kind),
            max_depth: file.max_depth.unwrap_or(d.max_depth),
            rr_threshold: file.rr_threshold.unwrap_or(d.rr_threshold),
            regularize: file.regularize.unwrap_or(d.regularize),
            ao: AmbientOcclusion {
                cos_sample: file.ao_cos_sample.unwrap_or(d.ao.cos_sample),
                max_distance: file.ao_max_distance.unwrap_or(d.ao.max_distance),
                ..d.ao
            },
            simple: SimplePath {
                sample_lights: file.sample_lights.unwrap_or(d.simple.sample_lights),
                sample_bsdf: file.sample_bsdf.unwrap_or(d.simple.sample_bsdf),
            },
            mlt: Mlt {
                bootstrap_samples: file.mlt_bootstrap_samples.map_or(d.mlt.bootstrap_samples, |n| n.max(1) as u32),
                chains: file.mlt_chains.map_or(d.mlt.chains, |n| n.max(1) as u32),
                mutations_per_pixel: file
                    .mlt_mutations_per_pixel
                    .map_or(d.mlt.mutations_per_pixel, |n| n.max(1) as u64),
                large_step_probability: file.mlt_large_step_probability.map_or(d.mlt.large_step_probability, |p| {
                    if p.is_nan() {
                        0.0
                    } else {
                        p.clamp(0.0, 1.0)
                    }
                }),
                sigma: file.mlt_sigma.map_or(d.mlt.sigma, |s| if s.is_finite() { s.abs() } else { d.mlt.sigma }),
            },
            strategy_images: match (file.visualize_weights, file.visualize_strategies) {
                (Some(true), _) => StrategyImageKind::Weighted,
                (_, Some(true)) => StrategyImageKind::Unweighted,
                _ => StrategyImageKind::Off,
            },
            sppm: Sppm {
                photons_per_iteration: file.sppm_photons_per_iteration,
                radius: file.sppm_radius.unwrap_or(d.sppm.radius),
                seed: file.sppm_seed.unwrap_or(d.sppm.seed),
            },
            function: FunctionOptions {
                function: file.function.unwrap_or(d.function.function),
                skip_bad: file.function_skip_bad.unwrap_or(d.function.skip_bad),
            },
            ..d
        }
    }

    /// The rays one camera sample of this estimator traces at most, counting a path of
    /// `max_depth` scattering events as its camera ray and, per event, one continuation and one
    /// shadow ray (2·max_depth + 1; `randomwalk` has no shadow rays, ambient occlusion traces
    /// one ray past the first hit). `None` for an unbounded depth and for the estimators whose
    /// rays do not follow the camera samples (light tracing, bdpt, mlt, sppm). An estimate for
    /// choosing how to build the accelerator: rays through media interfaces and subsurface
    /// probes are not counted, Russian roulette and escaping paths make it an upper bound.
    pub fn rays_per_sample(&self) -> Option<u64> {
        let depth = u64::from(self.max_depth);
        match self.kind {
            _ if self.max_depth == UNBOUNDED_DEPTH => None,
            IntegratorKind::Path | IntegratorKind::VolPath | IntegratorKind::SimplePath | IntegratorKind::Function => {
                Some(2 * depth + 1)
            }
            IntegratorKind::SimpleVolPath | IntegratorKind::RandomWalk => Some(depth + 1),
            IntegratorKind::AmbientOcclusion => Some(2),
            IntegratorKind::LightPath | IntegratorKind::Bdpt | IntegratorKind::Mlt | IntegratorKind::Sppm => None,
        }
    }

    /// The estimator that renders `scene` as the named one would: `path` and `volpath` are one
    /// estimator family, whose volumetric loop is taken exactly when the scene has a medium to
    /// step through — participating media, or a subsurface material a path may walk (the random
    /// walk, or diffusion on an optically thin object). A scene without either gives `volpath`
    /// nothing to do but the path tracer's work; `path` cannot step through media (pbrt-v4's
    /// `path` ignores them). The estimators that start paths at the lights need a camera with
    /// an importance function (a perspective one without a lens system); they step through
    /// media, and take a subsurface material for its boundary alone, as pbrt-v4's do
    /// ([`Self::bidirectional_ignores`]). Where they cannot run, the path tracer (or, with
    /// media, the volumetric one) renders instead ([`Self::fallback_reason`] says why). `sppm`
    /// ignores media and subsurface scattering, as pbrt-v4's does ([`Self::sppm_ignores`]).
    pub fn for_scene(self, scene: &Scene) -> Self {
        let walks =
            scene.has_subsurface() && (self.sss == SubsurfaceMethod::RandomWalk || scene.may_have_thin_subsurface());
        let kind = match self.kind {
            IntegratorKind::Path | IntegratorKind::VolPath if scene.has_media() || walks => IntegratorKind::VolPath,
            IntegratorKind::Path | IntegratorKind::VolPath => IntegratorKind::Path,
            IntegratorKind::LightPath | IntegratorKind::Bdpt | IntegratorKind::Mlt
                if Self::fallback_reason(scene).is_none() =>
            {
                self.kind
            }
            IntegratorKind::LightPath | IntegratorKind::Bdpt | IntegratorKind::Mlt if scene.has_media() || walks => {
                IntegratorKind::VolPath
            }
            IntegratorKind::LightPath | IntegratorKind::Bdpt | IntegratorKind::Mlt => IntegratorKind::Path,
            other => other,
        };
        Self { kind, ..self }
    }

    /// Why the estimators that start paths at the lights cannot render `scene` (`None`: they
    /// can).
    pub fn fallback_reason(scene: &Scene) -> Option<&'static str> {
        if !scene.camera.camera((1, 1)).has_importance() {
            Some("only a perspective camera without a lens system has an importance function here")
        } else {
            None
        }
    }

    /// What the estimators that start paths at the lights leave out of `scene`'s light
    /// transport, as pbrt-v4's do (`None`: nothing): subsurface scattering, and the emission of
    /// media (pbrt-v4's random walks for them record a medium vertex's scattering alone, and its
    /// lights are the scene's light sources).
    pub fn bidirectional_ignores(scene: &Scene) -> Option<String> {
        let mut reasons = Vec::new();
        if scene.has_subsurface() {
            reasons.push("it ignores subsurface scattering: a subsurface material scatters as its boundary BSDF alone (as in pbrt-v4)");
        }
        if scene.media().iter().any(Medium::emits) {
            reasons.push("it ignores the emission of participating media (as pbrt-v4's does; volpath renders it)");
        }
        (!reasons.is_empty()).then(|| reasons.join("; "))
    }

    /// What `sppm` leaves out of `scene`'s light transport, as pbrt-v4's does (`None`: nothing):
    /// it traces camera and photon paths from surface to surface through media and it takes a
    /// subsurface material's boundary for a smooth dielectric.
    pub fn sppm_ignores(scene: &Scene) -> Option<&'static str> {
        if scene.has_media() {
            Some("it ignores participating media (as pbrt-v4's does)")
        } else if scene.has_subsurface() {
            Some("it ignores subsurface scattering: light crosses a subsurface material's boundary as glass (as in pbrt-v4)")
        } else {
            None
        }
    }

    /// Radiance [W/(sr·m²·nm)] arriving along `ray` at its origin (in the camera's medium), at
    /// the wavelengths `w` (which a dispersive interface may reduce to the hero wavelength).
    pub fn li(
        &self,
        scene: &Scene,
        ray: Ray,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        self.li_camera(scene, ray, None, None, w, sampler, stats)
    }

    /// [`Self::li`] for a camera ray with its differentials, which give the texture footprint
    /// at its first surface vertex; `visible`, when given, receives that vertex for the
    /// geometry buffers (it stays `None` when the ray sees no surface).
    #[allow(clippy::too_many_arguments)]
    pub fn li_camera(
        &self,
        scene: &Scene,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        visible: Option<&mut Option<VisibleSurface>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        match self.kind {
            IntegratorKind::VolPath => self.volpath_trace(scene, ray, differentials, None, visible, w, sampler, stats),
            IntegratorKind::AmbientOcclusion => {
                self.ambient_occlusion(scene, ray, differentials, visible, w, sampler, stats)
            }
            IntegratorKind::RandomWalk => self.random_walk(scene, ray, differentials, visible, w, sampler, stats),
            IntegratorKind::SimplePath => self.simple_path(scene, ray, differentials, visible, w, sampler, stats),
            IntegratorKind::SimpleVolPath => self.simple_volpath(scene, ray, w, sampler, stats),
            // lightpath, bdpt and mlt estimate without their splats (`li_splatting`) as the path
            // tracer, and so does sppm per camera sample (its passes are `crate::sppm_render`),
            // and the function test, which renders no scene.
            IntegratorKind::Path
            | IntegratorKind::LightPath
            | IntegratorKind::Bdpt
            | IntegratorKind::Mlt
            | IntegratorKind::Sppm
            | IntegratorKind::Function => self.path_trace(scene, ray, differentials, None, visible, w, sampler, stats),
        }
    }

    /// The estimate of a camera sample for the estimators that splat ([`IntegratorKind::splats`]):
    /// the radiance the camera `ray` (with its differentials, and the geometry-buffer record
    /// `visible`) brings to its own pixel, and the light that the sample's light path brings to
    /// film positions of their own, pushed to `splats`. The other estimators push nothing.
    #[allow(clippy::too_many_arguments)]
    pub fn li_splatting(
        &self,
        scene: &Scene,
        camera: &Camera,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        visible: Option<&mut Option<VisibleSurface>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
        splats: &mut Vec<SplatSample>,
    ) -> SampledSpectrum {
        match self.kind {
            // Light tracing uses the camera sample for its time and wavelengths only (and
            // records no geometry buffers).
            IntegratorKind::LightPath => {
                self.light_trace(scene, camera, ray.time, w, sampler, stats, splats);
                SampledSpectrum::zero()
            }
            // (No geometry buffers either.) mlt renders the image as a whole
            // (`crate::render::render_range`); a single camera sample is one of bdpt's.
            IntegratorKind::Bdpt | IntegratorKind::Mlt => {
                self.bdpt_trace(scene, camera, ray, differentials, w, sampler, stats, splats)
            }
            _ => self.li_camera(scene, ray, differentials, visible, w, sampler, stats),
        }
    }

    /// Irradiance E [W/(m²·nm)] at `p` (in the camera's medium) on a surface with unit normal
    /// `n`, by the full integrator: an ideal white Lambertian sensor at `p` reflects
    /// L_o = E/π (E = ∫ L_i cos θ dω), so E = π L_o, with L_o estimated by NEE + BSDF sampling +
    /// MIS like any other surface.
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
        let sensor = Some((si, bsdf));
        let lo = match self.kind {
            // The path tracers measure for every estimator (the others start at a camera ray).
            IntegratorKind::VolPath => self.volpath_trace(scene, probe, None, sensor, None, w, sampler, stats),
            _ => self.path_trace(scene, probe, None, sensor, None, w, sampler, stats),
        };
        lo * PI
    }
}

#[cfg(test)]
mod tests {
    use super::{Integrator, IntegratorKind, UNBOUNDED_DEPTH};
    use crate::accel::AccelKind;
    use crate::render::{render, RenderSettings};
    use crate::scene::SceneBuilder;

    /// The rays counted while rendering the Cornell box at depth 3 (before Russian roulette
    /// starts) stay within the estimate and not far below it: paths end early only by leaving
    /// through the open front (uniform directions of `randomwalk` leave most often).
    #[test]
    fn rays_per_sample_bounds_the_rays_traced() {
        let scene = SceneBuilder::cornell_box().build(AccelKind::default_available()).unwrap();
        let kinds = [
            IntegratorKind::Path,
            IntegratorKind::SimplePath,
            IntegratorKind::RandomWalk,
            IntegratorKind::AmbientOcclusion,
        ];
        for kind in kinds {
            let integrator = Integrator { kind, max_depth: 3, ..Default::default() };
            let settings = RenderSettings { resolution: (8, 8), spp: 4, integrator, ..Default::default() };
            let (_, stats) = render(&scene, &settings, |_| {}).unwrap();
            let bound = stats.samples * integrator.rays_per_sample().unwrap();
            assert!(stats.rays <= bound && stats.rays * 3 > bound, "{kind:?}: {} rays, estimate {bound}", stats.rays);
        }
        let unbounded = Integrator { max_depth: UNBOUNDED_DEPTH, ..Default::default() };
        assert_eq!(unbounded.rays_per_sample(), None);
        assert_eq!(Integrator { kind: IntegratorKind::Bdpt, ..Default::default() }.rays_per_sample(), None);
    }
}

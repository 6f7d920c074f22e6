//! From a parsed pbrt-v4 scene ([`SceneDesc`]) to prism's [`SceneBuilder`]: materials, textures,
//! lights, shapes, camera and the render settings the file asks for.
//!
//! Light spectra follow pbrt-v4: a light's spectrum is normalised to unit luminance (Y = 1 in the
//! ∫ȳ normalisation of `spectrum::cie`, so `"rgb L" [1 1 1]` looks white with value 1), then multiplied by
//! `scale`. `power` and `illuminance` scale it exactly as pbrt-v4's `lights.cpp` does, so a pbrt-v4
//! scene renders as bright as in pbrt-v4; prism's own `lumens`/`lux` (K_m = 683 lm/W) and
//! `watts`/`irradiance` give SI photometric and radiometric targets instead (docs/radiometry.md).

mod definitions;
mod inputs;
mod lights;
mod load;
mod materials;
mod media;
mod nanovdb;
mod realistic;
mod subsurface;
mod textures;

pub use inputs::{input_stamps, InputStamp};
pub use load::{load_file, LoadedScene};

use definitions::{ByMaterial, Definitions};
use lights::{brightness_factor, FLUX};

use super::desc::{MaterialDesc, MaterialRef, ObjectDesc, SceneDesc, ShapeDesc, ShapeGeometry};
use super::error::{Location, SceneError, Warning};
use super::params::{ParamSet, SpectrumParam};
use super::QuadricMode;
use crate::bsdf::named_spectra::named_spectrum;
use crate::camera::Projection;
use crate::film::Crop;
use crate::geometry::quadric::similarity_scale;
use crate::geometry::{AnimatedTransform, Curves, Mesh, Motion, PlacedQuadric, Quadric};
use crate::light::{EmissionImage, LightSamplerKind};
use crate::material::{BumpedMaterial, Ior, Material, Roughness};
use crate::sampling::{Randomize, SamplerKind};
use crate::scene::{CameraDesc, Emission, SceneBuilder};
use crate::spectrum::{ColorSpace, RgbKind, SpdError, Spectrum};
use glam::Mat4;
use rustc_hash::FxHashMap as HashMap;
use std::sync::Arc;

/// What the file asks of the render (the command line may override each).
#[derive(Clone, Debug, Default)]
pub struct FileSettings {
    /// Film resolution.
    pub resolution: Option<(u32, u32)>,
    /// Film "filename".
    pub filename: Option<std::path::PathBuf>,
    /// Sampler "pixelsamples".
    pub spp: Option<u64>,
    /// Integrator "maxdepth" ([`PBRT_DEFAULT_MAX_DEPTH`] when the file gives none).
    pub max_depth: Option<u32>,
    /// The Integrator's type, one prism renders (the parser substitutes the others).
    pub integrator: Option<String>,
    /// Integrator "rrthreshold" (default 1): roulette only below this throughput.
    pub rr_threshold: Option<f32>,
    /// Integrator "regularize" (pbrt-v4's default false).
    pub regularize: Option<bool>,
    /// Integrator "ambientocclusion": "cossample" and "maxdistance".
    pub ao_cos_sample: Option<bool>,
    pub ao_max_distance: Option<f32>,
    /// Integrator "simplepath": "samplelights" and "samplebsdf".
    pub sample_lights: Option<bool>,
    pub sample_bsdf: Option<bool>,
    /// Integrator "mlt": "bootstrapsamples", "chains", "mutationsperpixel",
    /// "largestepprobability", "sigma".
    pub mlt_bootstrap_samples: Option<i32>,
    pub mlt_chains: Option<i32>,
    pub mlt_mutations_per_pixel: Option<i32>,
    pub mlt_large_step_probability: Option<f32>,
    pub mlt_sigma: Option<f32>,
    /// Integrator "bdpt": "visualizestrategies" and "visualizeweights".
    pub visualize_strategies: Option<bool>,
    pub visualize_weights: Option<bool>,
    /// Integrator "sppm": "iterations", "photonsperiteration" (−1: `None`), "radius", "seed".
    pub sppm_iterations: Option<u64>,
    pub sppm_photons_per_iteration: Option<u64>,
    pub sppm_radius: Option<f32>,
    pub sppm_seed: Option<u64>,
    /// Integrator "function": "function", "skipbad", "filename" (the MSE text file) and
    /// "imagefilename" (an image of the function).
    pub function: Option<crate::sampling::TestFunction>,
    pub function_skip_bad: Option<bool>,
    pub function_filename: Option<std::path::PathBuf>,
    pub function_image_filename: Option<std::path::PathBuf>,
    /// PixelFilter with its parameters.
    pub filter: Option<crate::filter::Filter>,
    /// The Sampler with its parameters.
    pub sampler: Option<SamplerKind>,
    /// Sampler/Option "seed".
    pub seed: Option<u64>,
    /// ColorSpace / film colour space.
    pub color_space: Option<String>,
    /// Film "cropwindow" or "pixelbounds".
    pub crop: Option<crate::film::Crop>,
    /// Film "iso" (pbrt-v4's default 100).
    pub iso: Option<f32>,
    /// Camera "shutterclose" − "shutteropen" [s] (pbrt-v4's default 1).
    pub exposure_time: Option<f32>,
    /// Film "sensor": a camera's name (`None`: the cie1931 sensor).
    pub camera_sensor: Option<String>,
    /// Film "whitebalance" [K] (0: none; pbrt-v4's default for the cie1931 sensor; a camera
    /// sensor's default is 6500 K).
    pub white_balance: Option<f32>,
    /// Film "maxcomponentvalue": the largest sensor component of one sample (pbrt-v4's default
    /// +∞).
    pub max_component: Option<f32>,
    /// Film "savefp16": OpenEXR output in half floats (pbrt-v4's default) or 32-bit floats.
    pub save_fp16: Option<bool>,
    /// Film "gbuffer": the geometry buffers' coordinate system (`coordinatesystem`).
    pub aov: Option<crate::film::AovSpace>,
    /// Film "spectral": its buckets (`nbuckets`, `lambdamin`, `lambdamax`).
    pub spectral: Option<crate::film::SpectralSettings>,
}

/// pbrt-v4's `PixelFilter` `kind` with its parameters (`xradius`, `yradius`; Gaussian `sigma`;
/// Mitchell `B`, `C`; sinc `tau`), defaults as pbrt-v4's. Every name the parser accepts is one
/// of these.
fn pixel_filter(kind: &str, p: &ParamSet) -> crate::filter::Filter {
    use crate::filter::{Filter, FilterKind};
    let family = match Filter::kind_by_name(kind).unwrap_or(FilterKind::Gaussian { sigma: 0.5 }) {
        FilterKind::Gaussian { sigma } => FilterKind::Gaussian { sigma: p.float_or("sigma", sigma) },
        FilterKind::Mitchell { b, c } => FilterKind::Mitchell { b: p.float_or("B", b), c: p.float_or("C", c) },
        FilterKind::LanczosSinc { tau } => FilterKind::LanczosSinc { tau: p.float_or("tau", tau) },
        k => k,
    };
    let r = family.default_radius();
    Filter::with_radii(family, glam::Vec2::new(p.float_or("xradius", r), p.float_or("yradius", r)))
}

/// pbrt-v4's Integrator "maxdepth" when a scene gives none.
pub const PBRT_DEFAULT_MAX_DEPTH: u32 = 5;

/// Turns a desc into a builder, with analytic quadrics; warnings go to `warnings`.
pub fn build(desc: &SceneDesc, warnings: &mut Vec<Warning>) -> Result<(SceneBuilder, FileSettings), SceneError> {
    build_with(desc, warnings, QuadricMode::default())
}

/// [`build`] with quadrics built as `quadrics` says.
pub fn build_with(
    desc: &SceneDesc,
    warnings: &mut Vec<Warning>,
    quadrics: QuadricMode,
) -> Result<(SceneBuilder, FileSettings), SceneError> {
    translate(desc, Vec::new(), warnings, quadrics)
}

/// [`build_with`] that moves the meshes of the world's static shapes out of `desc` into the
/// scene (transformed in place) instead of copying them: for a description that is afterwards
/// only asked for its unused parameters and its input files. (A mesh still held elsewhere is
/// copied.)
pub fn build_moving_meshes(
    desc: &mut SceneDesc,
    warnings: &mut Vec<Warning>,
    quadrics: QuadricMode,
) -> Result<(SceneBuilder, FileSettings), SceneError> {
    let moved = desc
        .shapes
        .iter_mut()
        .map(|s| match &mut s.geometry {
            ShapeGeometry::Mesh(mesh) if s.motion.is_none() => Some(std::mem::take(mesh)),
            _ => None,
        })
        .collect();
    translate(desc, moved, warnings, quadrics)
}

/// The translation of `desc`; `moved[i]`, when given, is the mesh of `desc.shapes[i]`.
fn translate(
    desc: &SceneDesc,
    mut moved: Vec<Option<Arc<Mesh>>>,
    warnings: &mut Vec<Warning>,
    quadrics: QuadricMode,
) -> Result<(SceneBuilder, FileSettings), SceneError> {
    let mut ctx = Ctx {
        desc,
        defs: Definitions::new(desc),
        b: SceneBuilder::new(),
        warnings,
        materials: ByMaterial::default(),
        rgb_spectra: HashMap::default(),
        textures: Default::default(),
        media: Default::default(),
        quadrics,
    };
    ctx.camera()?;
    ctx.media = ctx.media()?;
    let settings = ctx.settings()?;
    let light_sampler = ctx.light_sampler()?;
    ctx.b.set_light_sampler(light_sampler);
    ctx.all_textures()?;
    for (i, shape) in desc.shapes.iter().enumerate() {
        ctx.shape(shape, moved.get_mut(i).and_then(Option::take))?;
    }
    ctx.instances()?;
    for l in &desc.lights {
        let first = ctx.b.light_count();
        ctx.light(l)?;
        let medium = ctx.media.get(&l.medium).copied();
        ctx.b.set_medium_of_lights_from(first, medium);
    }
    let Ctx { b, .. } = ctx;
    Ok((b, settings))
}

struct Ctx<'a> {
    desc: &'a SceneDesc,
    /// The description's named definitions by name.
    defs: Definitions<'a>,
    b: SceneBuilder,
    warnings: &'a mut Vec<Warning>,
    /// Material id per definition, so shared materials are built once.
    materials: ByMaterial<u32>,
    /// The spectrum of each RGB parameter value met so far, by its bits, kind and colour space:
    /// each fit (a Newton solve, ~0.1 ms) is done once per distinct colour.
    rgb_spectra: HashMap<([u32; 3], RgbKind, &'static str), Spectrum>,
    /// Textures and image pyramids built so far.
    textures: textures::Built,
    /// Medium ids by name.
    media: media::MediumIds,
    /// Whether quadrics are intersected exactly or tessellated.
    quadrics: QuadricMode,
}

/// An error at parameter `name` of `params` (at `directive` where the parameter is not written).
fn param_error(params: &ParamSet, name: &str, directive: &Location, message: String) -> SceneError {
    SceneError::syntax(params.get(name).map_or(directive, |p| &p.loc), name, message)
}

/// Why a spectrum parameter gives no spectrum.
#[derive(Debug, thiserror::Error)]
enum SpectrumError {
    /// An RGB parameter of more than one colour where one is expected.
    #[error("one RGB colour is expected here, not {0}")]
    RgbCount(usize),
    /// (λ, value) samples whose wavelengths do not increase.
    #[error("spectrum samples must have increasing wavelengths")]
    Unordered,
    /// A name listed among the built-in spectra without data (every listed name has data).
    #[error("built-in spectrum missing")]
    BuiltinMissing,
    /// A file name that names neither a named spectrum nor an existing file: most likely a
    /// misspelt name.
    #[error("\"{name}\" is neither a named spectrum nor a file ({path} does not exist); named spectra: {valid}")]
    Unknown {
        /// The name as given.
        name: String,
        /// Where it was looked for as a file.
        path: String,
        /// The named spectra prism has, comma-separated.
        valid: String,
    },
    /// An SPD file that cannot be read.
    #[error(transparent)]
    File(#[from] SpdError),
}

fn space_of(params: &ParamSet) -> &'static ColorSpace {
    ColorSpace::by_name(params.color_space).unwrap_or_else(ColorSpace::srgb)
}

/// Integer parameter `name`, which must be at least `min` (counts: the depth has its own rule);
/// clamping it silently would render something other than what the file says.
fn count(params: &ParamSet, name: &str, loc: &Location, min: i32) -> Result<Option<i32>, SceneError> {
    match params.int(name) {
        Some(n) if n < min => {
            let message = format!("\"{name}\" must be at least {min}, got {n}");
            Err(param_error(params, name, loc, message))
        }
        n => Ok(n),
    }
}

impl Ctx<'_> {
    fn warn(&mut self, loc: &Location, message: String) {
        self.warnings.push(Warning::note(loc, message));
    }

    /// A pbrt-v4 feature prism does not render, and what prism does instead.
    fn unsupported(&mut self, loc: &Location, feature: String, fallback: &str) {
        self.warnings.push(Warning::unsupported(loc, feature, fallback));
    }

    /// The Sampler directive as prism renders it, and the samples per pixel pbrt-v4 takes:
    /// "pixelsamples", for "stratified" "xsamples" × "ysamples", else its default (4 for
    /// "independent", 16 for the others). pbrt-v4's "sobol" (one Sobol' sequence over the whole
    /// image) is prism's "globalsobol" (its own "sobol" is the padded per-pixel one). A
    /// "randomization" a sampler does not take is an error, as in pbrt-v4.
    fn sampler(&mut self) -> Result<(SamplerKind, u64), SceneError> {
        let (kind, p, loc) = (self.desc.sampler.kind.as_str(), &self.desc.sampler.params, &self.desc.sampler.loc);
        let randomize = |default: Randomize, allowed: &[Randomize]| -> Result<Randomize, SceneError> {
            let Some(name) = p.string("randomization") else { return Ok(default) };
            match Randomize::parse(name) {
                Ok(r) if allowed.contains(&r) => Ok(r),
                _ => {
                    let valid = allowed.iter().map(|r| r.name()).collect::<Vec<_>>().join(", ");
                    let message = format!("sampler \"{kind}\": unknown \"randomization\" \"{name}\" (valid: {valid})");
                    Err(param_error(p, "randomization", loc, message))
                }
            }
        };
        let all = [Randomize::None, Randomize::PermuteDigits, Randomize::FastOwen, Randomize::Owen];
        let pixel_samples = |default: u64| count(p, "pixelsamples", loc, 1).map(|n| n.map_or(default, |n| n as u64));
        let (sampler, spp) = match kind {
            "independent" => (SamplerKind::Independent, pixel_samples(4)?),
            "zsobol" => (SamplerKind::ZSobol(randomize(Randomize::FastOwen, &all)?), pixel_samples(16)?),
            "paddedsobol" => (SamplerKind::PaddedSobol(randomize(Randomize::FastOwen, &all)?), pixel_samples(16)?),
            "halton" => {
                let allowed = [Randomize::None, Randomize::PermuteDigits, Randomize::Owen];
                (SamplerKind::Halton(randomize(Randomize::PermuteDigits, &allowed)?), pixel_samples(16)?)
            }
            "pmj02bn" => (SamplerKind::Pmj02bn, pixel_samples(16)?),
            "stratified" => {
                let (x, y) = (count(p, "xsamples", loc, 1)?.unwrap_or(4), count(p, "ysamples", loc, 1)?.unwrap_or(4));
                let jitter = p.bool("jitter").unwrap_or(true);
                (SamplerKind::Stratified { x: x as u32, y: y as u32, jitter }, x as u64 * y as u64)
            }
            // "sobol" (the parser admits only pbrt-v4's names).
            _ => (SamplerKind::GlobalSobol(randomize(Randomize::FastOwen, &all)?), pixel_samples(16)?),
        };
        if matches!(sampler, SamplerKind::ZSobol(_)) && !spp.is_power_of_two() {
            let message = format!(
                "sampler \"zsobol\" with {spp} samples per pixel: pbrt-v4 takes {} (a power of two), prism all {spp}",
                1u64 << spp.ilog2()
            );
            self.warn(loc, message);
        }
        Ok((sampler, spp))
    }

    /// Integrator "maxdepth": a depth ≥ 0, or −1 for no limit (Mitsuba's convention; pbrt-v4's
    /// loop never reaches a negative depth either).
    fn max_depth(&self) -> Result<Option<u32>, SceneError> {
        let (params, loc) = (&self.desc.integrator.params, &self.desc.integrator.loc);
        let Some(n) = params.int("maxdepth") else { return Ok(None) };
        crate::settings::max_depth(n.into(), "\"maxdepth\"")
            .map(Some)
            .map_err(|e| param_error(params, "maxdepth", loc, e.to_string()))
    }

    /// Integrator "sppm"'s "iterations" (≥ 1), "photonsperiteration" (≥ 1, or −1: one per
    /// pixel), "radius" (> 0) and "seed"; none for another integrator.
    #[allow(clippy::type_complexity)]
    fn sppm(&self) -> Result<(Option<u64>, Option<u64>, Option<f32>, Option<u64>), SceneError> {
        let (params, loc) = (&self.desc.integrator.params, &self.desc.integrator.loc);
        if self.desc.integrator.kind != "sppm" {
            return Ok((None, None, None, None));
        }
        let bad = |name: &str, what: &str| param_error(params, name, loc, format!("\"{name}\" must be {what}"));
        let iterations = match params.int("iterations") {
            Some(n) if n < 1 => return Err(bad("iterations", "at least 1")),
            n => n.map(|n| n as u64),
        };
        let photons = match params.int("photonsperiteration") {
            None | Some(-1) => None,
            Some(n) if n < 1 => return Err(bad("photonsperiteration", "at least 1, or -1 for one per pixel")),
            Some(n) => Some(n as u64),
        };
        let radius = match params.float("radius") {
            Some(r) if !(r > 0.0 && r.is_finite()) => return Err(bad("radius", "positive")),
            r => r,
        };
        let seed = params.int("seed").map(|s| s as u64);
        Ok((iterations, photons, radius, seed))
    }

    /// Integrator "function"'s "function" (one of [`crate::sampling::TestFunction`]); none for
    /// another integrator.
    fn test_function(&self) -> Result<Option<crate::sampling::TestFunction>, SceneError> {
        let (params, loc) = (&self.desc.integrator.params, &self.desc.integrator.loc);
        if self.desc.integrator.kind != "function" {
            return Ok(None);
        }
        let Some(name) = params.string("function") else { return Ok(None) };
        crate::sampling::TestFunction::parse(name).map(Some).map_err(|e| {
            let message = format!("unknown \"function\" \"{name}\" (valid: {})", e.valid);
            param_error(params, "function", loc, message)
        })
    }

    /// Integrator "lightsampler": "bvh" (pbrt-v4's default), "power" or "uniform".
    fn light_sampler(&self) -> Result<LightSamplerKind, SceneError> {
        let (params, loc) = (&self.desc.integrator.params, &self.desc.integrator.loc);
        let Some(name) = params.string("lightsampler") else { return Ok(LightSamplerKind::Bvh) };
        LightSamplerKind::parse(name).map_err(|e| {
            let message = format!("unknown \"lightsampler\" \"{name}\" (valid: {})", e.valid);
            param_error(params, "lightsampler", loc, message)
        })
    }

    fn camera(&mut self) -> Result<(), SceneError> {
        let c = &self.desc.camera;
        let p = &c.directive.params;
        let projection = match c.directive.kind.as_str() {
            "orthographic" => Projection::Orthographic,
            "realistic" => Projection::Realistic,
            "spherical" => match p.string("mapping").unwrap_or("equalarea") {
                "equalarea" => Projection::SphericalEqualArea,
                "equirectangular" => Projection::SphericalEquirect,
                other => {
                    let message =
                        format!("unknown spherical \"mapping\" \"{other}\" (valid: equalarea, equirectangular)");
                    return Err(param_error(p, "mapping", &c.directive.loc, message));
                }
            },
            _ => Projection::Perspective,
        };
        let spherical = matches!(projection, Projection::SphericalEqualArea | Projection::SphericalEquirect);
        let fov = if projection == Projection::Perspective { p.float_or("fov", 90.0) } else { 90.0 };
        if !(fov > 0.0 && fov < 180.0) {
            let message = format!("\"fov\" must be between 0 and 180 degrees, got {fov}");
            return Err(param_error(p, "fov", &c.directive.loc, message));
        }
        // pbrt-v4's defaults: the shutter is open from time 0 to 1.
        self.b.set_shutter(p.float_or("shutteropen", 0.0), p.float_or("shutterclose", 1.0));
        let screen_window = p.floats("screenwindow").filter(|s| s.len() == 4).map(|s| [s[0], s[1], s[2], s[3]]);
        let (lens_radius, focal_distance) =
            if spherical { (0.0, 1e6) } else { (p.float_or("lensradius", 0.0), p.float_or("focaldistance", 1e6)) };
        let lens = if projection == Projection::Realistic { Some(self.realistic_lens()?) } else { None };
        self.b.set_camera_desc(CameraDesc {
            camera_to_world: c.camera_from_world.inverse(),
            motion: c.motion,
            fov_deg: fov,
            lens_radius,
            focal_distance,
            screen_window,
            projection,
            lens,
        });
        Ok(())
    }

    fn settings(&mut self) -> Result<FileSettings, SceneError> {
        let d = self.desc;
        let film = &d.film.params;
        let res = (count(film, "xresolution", &d.film.loc, 1)?, count(film, "yresolution", &d.film.loc, 1)?);
        let resolution = match res {
            (None, None) => None,
            (x, y) => Some((x.unwrap_or(1280) as u32, y.unwrap_or(720) as u32)),
        };
        let crop = match (film.floats("cropwindow"), film.ints("pixelbounds")) {
            (Some(c), _) if c.len() == 4 => Some(Crop::Window([c[0], c[1], c[2], c[3]])),
            (_, Some(p)) if p.len() == 4 => Some(Crop::Pixels([p[0], p[1], p[2], p[3]].map(i64::from))),
            (None, None) => None,
            _ => {
                self.warn(&d.film.loc, "Film \"cropwindow\"/\"pixelbounds\" needs 4 values; ignored".into());
                None
            }
        };
        let sensor = film.string("sensor").unwrap_or("cie1931");
        let mut white_balance = film.float("whitebalance");
        let camera_sensor = if sensor == "cie1931" {
            None
        } else if crate::spectrum::camera_sensitivities(sensor).is_some() {
            // pbrt-v4 white balances a camera sensor to 6500 K unless told otherwise.
            white_balance = white_balance.filter(|&t| t > 0.0).or(Some(6500.0));
            Some(sensor.to_string())
        } else {
            let valid: Vec<&str> = std::iter::once("cie1931").chain(crate::spectrum::camera_names()).collect();
            let message = format!("unknown \"sensor\" \"{sensor}\" (valid: {})", valid.join(", "));
            return Err(param_error(film, "sensor", &d.film.loc, message));
        };
        let cam = &d.camera.directive.params;
        let shutter = (cam.float("shutteropen"), cam.float("shutterclose"));
        let exposure_time = match shutter {
            (None, None) => None,
            (open, close) => Some(close.unwrap_or(1.0) - open.unwrap_or(0.0)),
        };
        let aov = match d.film.kind.as_str() {
            "gbuffer" => {
                let name = film.string("coordinatesystem").unwrap_or("camera");
                let space = crate::film::AovSpace::parse(name)
                    .map_err(|e| param_error(film, "coordinatesystem", &d.film.loc, e.to_string()))?;
                Some(space)
            }
            _ => None,
        };
        let spectral = match d.film.kind.as_str() {
            "spectral" => {
                let default = crate::film::SpectralSettings::default();
                let buckets = film.int_or("nbuckets", default.buckets as i32);
                let s = crate::film::SpectralSettings {
                    buckets: buckets.max(0) as u32,
                    lambda_min: film.float_or("lambdamin", default.lambda_min),
                    lambda_max: film.float_or("lambdamax", default.lambda_max),
                };
                // The parameter the error points at (the directive when it is not given).
                let name = match buckets {
                    ..1 => "nbuckets",
                    _ if s.lambda_max > crate::spectrum::LAMBDA_MAX || !film.has("lambdamin") => "lambdamax",
                    _ => "lambdamin",
                };
                s.check().map_err(|e| param_error(film, name, &d.film.loc, e))?;
                Some(s)
            }
            _ => None,
        };
        let filter = pixel_filter(&d.filter.kind, &d.filter.params);
        let (sampler, spp) = self.sampler()?;
        let (sppm_iterations, sppm_photons_per_iteration, sppm_radius, sppm_seed) = self.sppm()?;
        let function = self.test_function()?;
        // Read only for "function", so another integrator's stray ones are reported unused.
        let (integrator, is_function) = (&d.integrator.params, d.integrator.kind == "function");
        let function_file = |name: &str| is_function.then(|| integrator.string(name)).flatten().map(Into::into);
        Ok(FileSettings {
            resolution,
            filename: film.string("filename").map(Into::into),
            spp: Some(spp),
            // pbrt-v4's default when the file gives none.
            max_depth: Some(self.max_depth()?.unwrap_or(PBRT_DEFAULT_MAX_DEPTH)),
            integrator: Some(d.integrator.kind.clone()),
            rr_threshold: d.integrator.params.float("rrthreshold"),
            regularize: d.integrator.params.bool("regularize"),
            ao_cos_sample: d.integrator.params.bool("cossample"),
            ao_max_distance: d.integrator.params.float("maxdistance"),
            sample_lights: d.integrator.params.bool("samplelights"),
            sample_bsdf: d.integrator.params.bool("samplebsdf"),
            mlt_bootstrap_samples: d.integrator.params.int("bootstrapsamples"),
            mlt_chains: d.integrator.params.int("chains"),
            mlt_mutations_per_pixel: d.integrator.params.int("mutationsperpixel"),
            mlt_large_step_probability: d.integrator.params.float("largestepprobability"),
            mlt_sigma: d.integrator.params.float("sigma"),
            visualize_strategies: d.integrator.params.bool("visualizestrategies"),
            visualize_weights: d.integrator.params.bool("visualizeweights"),
            sppm_iterations,
            sppm_photons_per_iteration,
            sppm_radius,
            sppm_seed,
            function,
            function_skip_bad: is_function.then(|| integrator.bool("skipbad")).flatten(),
            function_filename: function_file("filename"),
            function_image_filename: function_file("imagefilename"),
            filter: Some(filter),
            sampler: Some(sampler),
            seed: d.sampler.params.int("seed").or_else(|| d.options.int("seed")).map(|s| s as u64),
            color_space: Some(d.color_space.clone()),
            crop,
            iso: film.float("iso"),
            exposure_time,
            camera_sensor,
            white_balance,
            max_component: film.float("maxcomponentvalue"),
            save_fp16: film.bool("savefp16"),
            aov,
            spectral,
        })
    }

    /// A spectrum for a reflectance-like ("albedo"), unbounded or illuminant parameter.
    fn spectrum(&mut self, s: &SpectrumParam, kind: RgbKind, params: &ParamSet) -> Result<Spectrum, SpectrumError> {
        Ok(match s {
            SpectrumParam::Rgb(rgb) => {
                let space = space_of(params);
                let key = (rgb.map(f32::to_bits), kind, space.name);
                self.rgb_spectra.entry(key).or_insert_with(|| Spectrum::from_rgb(*rgb, kind, space)).clone()
            }
            SpectrumParam::Blackbody(t) => Spectrum::blackbody(*t),
            SpectrumParam::RgbArray(v) => return Err(SpectrumError::RgbCount(v.len())),
            SpectrumParam::Samples(v) => {
                let (l, x): (Vec<f32>, Vec<f32>) = v.iter().copied().unzip();
                Spectrum::piecewise_linear(&l, &x).ok_or(SpectrumError::Unordered)?
            }
            SpectrumParam::Named(n) => named_spectrum(n).ok_or(SpectrumError::BuiltinMissing)?,
            SpectrumParam::File(p) if !p.exists() => {
                // Neither a named spectrum nor a file: most likely a misspelt name.
                let name = p.file_name().map_or(String::new(), |f| f.to_string_lossy().into_owned());
                let valid: Vec<&str> =
                    crate::spectrum::NAMED_SPECTRA.iter().copied().filter(|n| named_spectrum(n).is_some()).collect();
                return Err(SpectrumError::Unknown { name, path: p.display().to_string(), valid: valid.join(", ") });
            }
            SpectrumParam::File(p) => Spectrum::from_spd_file(p)?,
        })
    }

    fn image(&mut self, p: &ParamSet, loc: &super::error::Location) -> Result<Arc<crate::image::Image>, SceneError> {
        let file = p.filename("filename").ok_or_else(|| SceneError::syntax(loc, "imagemap", "missing \"filename\""))?;
        crate::image::read(&file)
            .map(Arc::new)
            .map_err(|e| SceneError::syntax(loc, &file.display().to_string(), format!("cannot read the image: {e}")))
    }

    /// An area light's "filename" image, its RGB an illuminant of the scene's colour space
    /// (pbrt-v4 reads the file's colour space; prism does not read it from files). pbrt-v4
    /// rejects "L" beside it.
    fn emission_image(&mut self, p: &ParamSet, loc: &Location) -> Result<Option<Arc<EmissionImage>>, SceneError> {
        if !p.has("filename") {
            return Ok(None);
        }
        if p.has("L") {
            return Err(SceneError::syntax(loc, "L", "give one of \"L\" and \"filename\", not both"));
        }
        let image = self.image(p, loc)?;
        Ok(Some(Arc::new(EmissionImage::new(&image, space_of(p)))))
    }

    fn roughness(&mut self, p: &ParamSet) -> Result<Roughness, SceneError> {
        self.prefixed_roughness(p, "")
    }

    /// The id of the material `r` refers to (built on first use).
    fn material(&mut self, r: &MaterialRef) -> Result<u32, SceneError> {
        let (key, m) = self.defs.material(r);
        if let Some(id) = self.materials.get(key) {
            return Ok(id);
        }
        let mat = match m {
            None => Material::diffuse(Spectrum::constant(0.5)),
            Some(m) => self.make_material(m)?,
        };
        let id = self.b.add_material(mat);
        self.materials.set(key, id);
        Ok(id)
    }

    fn make_material(&mut self, m: &MaterialDesc) -> Result<Material, SceneError> {
        let base = self.base_material(m)?;
        if matches!(base, Material::Mix(_) | Material::Interface) {
            return Ok(base);
        }
        Ok(match self.normal_perturbation(&m.params, &m.loc)? {
            Some(perturbation) => Material::Bumped(Box::new(BumpedMaterial { base, perturbation })),
            None => base,
        })
    }

    fn base_material(&mut self, m: &MaterialDesc) -> Result<Material, SceneError> {
        let p = &m.params;
        let loc = &m.loc;
        Ok(match m.kind {
            "diffuse" => Material::Diffuse { reflectance: self.spectrum_texture(p, "reflectance", 0.5, loc)? },
            "diffusetransmission" => Material::DiffuseTransmission {
                reflectance: self.spectrum_texture(p, "reflectance", 0.25, loc)?,
                transmittance: self.spectrum_texture(p, "transmittance", 0.25, loc)?,
                scale: p.float_or("scale", 1.0),
            },
            "conductor" => self.conductor(p, loc)?,
            "dielectric" | "thindielectric" => {
                let eta = self.ior(p, "eta", 1.5, loc)?;
                if m.kind == "thindielectric" {
                    let e = match &eta {
                        Ior::Constant(e) => *e,
                        Ior::Spectral(s) => s.eval(550.0),
                    };
                    Material::ThinDielectric { eta: e }
                } else {
                    Material::Dielectric { eta, roughness: self.roughness(p)? }
                }
            }
            "coateddiffuse" => self.coated_diffuse(p, loc)?,
            "coatedconductor" => self.coated_conductor(p, loc)?,
            "mix" => self.mix(m)?,
            "subsurface" => self.subsurface(m)?,
            "interface" => Material::Interface,
            "hair" => self.hair(p, loc)?,
            "measured" => self.measured(p, loc)?,
            other => {
                self.unsupported(loc, format!("material \"{other}\""), "uses diffuse 0.5");
                Material::diffuse(Spectrum::constant(0.5))
            }
        })
    }

    fn unbounded(
        &mut self,
        p: &ParamSet,
        name: &str,
        default: &str,
        loc: &super::error::Location,
    ) -> Result<Spectrum, SceneError> {
        match p.spectrum(name) {
            Some(s) => {
                let s = s.clone();
                self.spectrum(&s, RgbKind::Unbounded, p).map_err(|e| param_error(p, name, loc, e.to_string()))
            }
            None => p
                .float(name)
                .map(Spectrum::constant)
                .or_else(|| named_spectrum(default))
                .ok_or_else(|| SceneError::syntax(loc, name, "missing spectrum")),
        }
    }

    /// Object instances, built as pbrt-v4 builds them (`BasicScene::CreateAggregate`): an
    /// instanced object's static shapes — meshes, curves, quadrics — become one prototype in
    /// instance space, built once and placed by every ObjectInstance; each of its moving shapes
    /// becomes a prototype of its own in its object space, placed by one instance per
    /// ObjectInstance that carries the ObjectInstance's placement times the shape's motion
    /// (pbrt-v4: an `AnimatedPrimitive` inside the object's BVH, [`Motion::compose`]). Objects
    /// nobody instances are not built; an instance with a singular transform is skipped with a
    /// warning.
    fn instances(&mut self) -> Result<(), SceneError> {
        let desc = self.desc;
        let mut built: HashMap<usize, ObjectParts> = HashMap::default();
        for inst in &desc.instances {
            if let std::collections::hash_map::Entry::Vacant(e) = built.entry(inst.object_index) {
                e.insert(self.object_parts(&desc.objects[inst.object_index])?);
            }
            let parts = &built[&inst.object_index];
            if let Some(proto) = parts.fixed {
                let placed = match inst.motion {
                    Some(m) => self.b.add_moving_instance(proto, m),
                    None => self.b.add_instance(proto, inst.world_from_instance),
                };
                self.note_unplaced(placed, &inst.loc);
            }
            for &(proto, shape_motion) in &parts.moving {
                let w = inst.world_from_instance;
                let fixed = AnimatedTransform::new(w, shape_motion.start_time, w, shape_motion.end_time);
                let motion = Motion::compose(inst.motion.unwrap_or(fixed), shape_motion);
                let placed = self.b.add_moving_instance(proto, motion);
                self.note_unplaced(placed, &inst.loc);
            }
        }
        Ok(())
    }

    /// [`SceneBuilder::add_mesh`], its warning (degenerate triangles skipped) at the shape's
    /// location `loc`.
    fn add_mesh(&mut self, mesh: Mesh, material: u32, emission: Option<Emission>, loc: &Location) -> u32 {
        let before = self.b.warnings.len();
        let id = self.b.add_mesh(mesh, material, emission);
        let notes: Vec<String> = self.b.warnings.drain(before..).collect();
        self.warnings.extend(notes.into_iter().map(|message| Warning::note(loc, message)));
        id
    }

    /// The builder's warning about an instance it did not place, at `loc`.
    fn note_unplaced(&mut self, placed: bool, loc: &Location) {
        if !placed {
            self.warnings.extend(self.b.warnings.pop().map(|message| Warning::note(loc, message)));
        }
    }

    /// The prototypes of object `obj`: one of its static shapes (`None` when it has none) and
    /// one per moving shape, with the shape's motion.
    fn object_parts(&mut self, obj: &ObjectDesc) -> Result<ObjectParts, SceneError> {
        let mut parts = ObjectParts { fixed: None, moving: Vec::new() };
        for s in &obj.shapes {
            match s.motion.as_deref() {
                Some(&motion) => parts.moving.push((self.shape_prototype(s)?, motion)),
                None => {
                    let id = self.geometry(s, &s.world_from_object)?;
                    let proto = match parts.fixed {
                        Some(p) => p,
                        None => *parts.fixed.insert(self.b.new_prototype()),
                    };
                    self.b.add_to_prototype(proto, id);
                }
            }
        }
        Ok(parts)
    }

    /// Shape `s` in its own object space as a prototype of its own.
    fn shape_prototype(&mut self, s: &ShapeDesc) -> Result<u32, SceneError> {
        let id = self.geometry(s, &Mat4::IDENTITY)?;
        let proto = self.b.new_prototype();
        self.b.add_to_prototype(proto, id);
        Ok(proto)
    }

    /// Shape `s` carried by `m` (to world space, to instance space inside an object definition,
    /// or the identity: its object space) as a primitive without emission, with its material,
    /// alpha and media: triangles, curves, or — unless tessellation is asked for or `m` is
    /// singular — an exact quadric. Returns its id.
    fn geometry(&mut self, s: &ShapeDesc, m: &Mat4) -> Result<u32, SceneError> {
        let material = self.material(&s.material)?;
        let id = match &s.geometry {
            ShapeGeometry::Curves(c) => {
                let oriented = Curves { flip_normal: c.flip_normal ^ s.reverse_orientation, ..Curves::clone(c) };
                self.b.add_curves(oriented.transformed(m), material)
            }
            ShapeGeometry::Quadric(q) => match self.analytic(q, m, s.reverse_orientation) {
                Some(placed) => self.b.add_quadric(placed, material, None),
                None => self.add_mesh(shape_mesh(s, m, None), material, None, &s.loc),
            },
            ShapeGeometry::Mesh(_) => self.add_mesh(shape_mesh(s, m, None), material, None, &s.loc),
        };
        self.finish(id, s)?;
        Ok(id)
    }

    /// Quadric `q` at `m`, intersected exactly; `None` when tessellation is asked for or the
    /// transform is singular.
    fn analytic(&self, q: &Quadric, m: &Mat4, reverse_orientation: bool) -> Option<PlacedQuadric> {
        (self.quadrics == QuadricMode::Analytic).then(|| PlacedQuadric::new(*q, *m, reverse_orientation)).flatten()
    }

    /// Gives primitive `id` shape `s`'s alpha mask and media.
    fn finish(&mut self, id: u32, s: &ShapeDesc) -> Result<(), SceneError> {
        let alpha = self.float_texture(&s.params, "alpha", 1.0)?;
        self.b.set_alpha(id, alpha);
        self.b.set_medium_interface(id, media::interface(&self.media, &s.media));
        Ok(())
    }

    /// A moving shape (pbrt-v4 wraps it in an `AnimatedPrimitive`): a quadric is intersected
    /// where it is at each ray's time; other shapes — meshes, curves — become a prototype of
    /// their own in object space, placed by one instance that moves. pbrt-v4 lets moving shapes
    /// emit; here they do not.
    fn moving_shape(&mut self, s: &ShapeDesc, motion: AnimatedTransform) -> Result<(), SceneError> {
        if s.area_light.is_some() && !matches!(s.geometry, ShapeGeometry::Curves(_)) {
            self.unsupported(&s.loc, "a moving area light".into(), "makes the shape non-emissive");
        }
        let moving = match &s.geometry {
            ShapeGeometry::Quadric(q) if self.quadrics == QuadricMode::Analytic => {
                PlacedQuadric::moving(*q, motion, s.reverse_orientation)
            }
            _ => None,
        };
        if let Some(q) = moving {
            let material = self.material(&s.material)?;
            let id = self.b.add_quadric(q, material, None);
            return self.finish(id, s);
        }
        let proto = self.shape_prototype(s)?;
        let placed = self.b.add_moving_instance(proto, motion);
        self.note_unplaced(placed, &s.loc);
        Ok(())
    }

    /// World shape `s`; `moved`: its mesh, taken from the description.
    fn shape(&mut self, s: &ShapeDesc, moved: Option<Arc<Mesh>>) -> Result<(), SceneError> {
        let curves = matches!(s.geometry, ShapeGeometry::Curves(_));
        if curves && s.area_light.is_some() {
            self.unsupported(&s.loc, "area light on a curve".into(), "makes the curve non-emissive");
        }
        if let Some(&motion) = s.motion.as_deref() {
            return self.moving_shape(s, motion);
        }
        if curves {
            return self.geometry(s, &s.world_from_object).map(drop);
        }
        // A quadric is intersected exactly (unless tessellation is asked for); under a
        // similarity it keeps its analytic area either way.
        let mut analytic = match &s.geometry {
            ShapeGeometry::Quadric(q) => self.analytic(q, &s.world_from_object, s.reverse_orientation),
            _ => None,
        };
        let mut mesh = if analytic.is_some() { Mesh::default() } else { shape_mesh(s, &s.world_from_object, moved) };
        // The shape's world-space area, asked for by an area light only.
        let area = || match (&s.geometry, &analytic) {
            (_, Some(q)) => q.area(),
            (ShapeGeometry::Quadric(q), None) => {
                similarity_scale(&s.world_from_object).map_or_else(|| mesh.area(), |k| q.area() * k * k)
            }
            _ => mesh.area(),
        };
        let material = self.material(&s.material)?;
        let mut per_face = false;
        let emission = match &s.area_light {
            None => None,
            Some(a) => {
                let p = &a.params;
                let image = self.emission_image(p, &a.loc)?;
                let (spectrum, norm) = self.light_spectrum(p, "L", &a.loc)?;
                let two_sided = p.bool_or("twosided", false);
                // pbrt-v4 DiffuseAreaLight: k_e = π A per emitting side (world-space area, so any
                // transform works), times an image's mean luminance. pbrt-v4 makes one light per
                // shape it creates, and a mesh creates one shape per face (triangle or bilinear
                // patch): its `power` is each face's, so k_e is taken per unit area here and each
                // triangle's scale divided by the area of its face.
                per_face = p.float("power").is_some_and(|v| v > 0.0) && FACETED_SHAPES.contains(&s.kind);
                let mean = image.as_ref().map_or(1.0, |i| i.mean_luminance());
                let k_area = if per_face { 1.0 } else { area() };
                let k_e = crate::math::PI * k_area * if two_sided { 2.0 } else { 1.0 } * mean;
                let scale =
                    p.float_or("scale", 1.0) * norm * brightness_factor(p, FLUX, k_e, Some((&spectrum, norm)), &a.loc)?;
                Some((Emission { spectrum, scale, two_sided }, image))
            }
        };
        let (emission, image) = emission.unzip();
        if analytic.is_some() && image.as_ref().is_some_and(Option::is_some) {
            // An emission image needs the triangles' (u, v) corners: tessellate.
            analytic = None;
            mesh = shape_mesh(s, &s.world_from_object, None);
        }
        let id = match analytic {
            Some(q) => self.b.add_quadric(q, material, emission),
            None => self.add_mesh(mesh, material, emission, &s.loc),
        };
        if let Some(image) = image.flatten() {
            self.b.set_emission_image(id, image);
        }
        if per_face {
            self.b.set_emission_per_face_area(id);
        }
        self.finish(id, s)
    }
}

/// The prototypes of an object definition.
struct ObjectParts {
    /// Its static shapes in instance space.
    fixed: Option<u32>,
    /// Each moving shape in its object space, with its motion (instance space from object).
    moving: Vec<(u32, AnimatedTransform)>,
}

/// The shapes pbrt-v4 creates as one shape per face: a `Triangle` per triangle (of a triangle
/// mesh, of a subdivided mesh's last level, of a PLY file) and a `BilinearPatch` per patch (of a
/// bilinear mesh, per quad of a PLY file).
const FACETED_SHAPES: &[&str] = &["trianglemesh", "loopsubdiv", "plymesh", "bilinearmesh"];

/// A shape's triangles under `m` (its own transform into world space, or instance space inside
/// an object definition; the identity keeps them in object space), oriented; `moved`: the
/// shape's mesh when it was taken from the description.
fn shape_mesh(s: &ShapeDesc, m: &Mat4, moved: Option<Arc<Mesh>>) -> Mesh {
    let mesh = match &s.geometry {
        ShapeGeometry::Mesh(mesh) => {
            let mut mesh = match moved.map(Arc::try_unwrap) {
                Some(Ok(owned)) => owned.into_transformed(m),
                Some(Err(shared)) => shared.transformed(m),
                None => mesh.transformed(m),
            };
            // pbrt-v4's `TriangleMesh` negates its per-vertex normals under ReverseOrientation,
            // and the geometric normal then follows them.
            if s.reverse_orientation {
                mesh.normals.iter_mut().flatten().for_each(|n| *n = -*n);
            }
            mesh
        }
        ShapeGeometry::Curves(_) => Mesh::default(),
        ShapeGeometry::Quadric(q) => {
            let mut mesh = q.tessellate();
            // pbrt-v4 takes a quadric's normal as ∂p/∂u × ∂p/∂v in object space, flipped when
            // ReverseOrientation is set or the transform swaps handedness, then carries it to
            // world space by the inverse transpose.
            if s.reverse_orientation ^ (glam::Mat3::from_mat4(*m).determinant() < 0.0) {
                mesh.normals.iter_mut().flatten().for_each(|n| *n = -*n);
            }
            mesh.transformed(m)
        }
    };
    orient(mesh, s.reverse_orientation)
}

/// Orients triangles as pbrt-v4 does: with per-vertex normals the geometric normal faces them
/// (they are already flipped under ReverseOrientation); otherwise ReverseOrientation flips it. (Mirroring transforms are already handled by
/// `Mesh::transformed`.)
fn orient(mut mesh: Mesh, reverse: bool) -> Mesh {
    use crate::geometry::MIN_ELEMENTS_PER_THREAD;
    use rayon::prelude::*;
    let Mesh { positions, indices, normals, .. } = &mut mesh;
    if let Some(normals) = normals {
        indices.par_iter_mut().with_min_len(MIN_ELEMENTS_PER_THREAD).for_each(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let n = (b - a).cross(c - a);
            let ns = normals[t[0] as usize] + normals[t[1] as usize] + normals[t[2] as usize];
            if n.dot(ns) < 0.0 {
                t.swap(1, 2);
            }
        });
    } else if reverse {
        indices.par_iter_mut().with_min_len(MIN_ELEMENTS_PER_THREAD).for_each(|t| t.swap(1, 2));
    }
    mesh
}

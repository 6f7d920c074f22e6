//! `prism render`: load a scene (or the built-in Cornell box), render it, write the image.

use super::render_function::{FunctionArgs, FunctionJob};
pub(crate) use super::render_job::write_film_image;
use super::render_job::{image_meta, summarize};
pub use super::render_job::{Job, RenderStats};
use super::Interrupted;
use crate::accel::AccelKind;
use crate::film::{AovSettings, AovSpace, Crop, FilmSettings};
use crate::image::{CropWindow, ExrSample, WriteOptions};
use crate::integrator::{Integrator, IntegratorKind, SubsurfaceMethod};
use crate::light::LightSamplerKind;
use crate::named::UnknownName;
use crate::pbrt::{input_stamps, FileSettings, LoadedScene, QuadricMode};
use crate::render::RenderSettings;
use crate::scene::{Scene, SceneBuilder};
use crate::sensor::Sensor;
use crate::settings;
use crate::spectrum::ColorSpace;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `prism render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// pbrt-v4 scene file; without one, the built-in Cornell box.
    pub scene: Option<PathBuf>,
    /// Samples per pixel (for integrator mlt: mutations per pixel, as pbrt-v4's --spp).
    #[arg(long, allow_negative_numbers = true)]
    pub spp: Option<i64>,
    /// Intersection backend: embree (fastest), embree-watertight (Embree's BVH with prism's
    /// watertight triangle test: no ray leaks through vertices, slower) or obvhs (pure Rust).
    #[arg(long)]
    pub accel: Option<String>,
    /// Output image; the format follows the extension (.exr linear float; .png/.jpg/.tif sRGB).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Seed of all random decisions [default: the file's, else 0].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Image size as WxH.
    #[arg(long, allow_hyphen_values = true)]
    pub resolution: Option<String>,
    /// Render only this part of the image: x0,x1,y0,y1 as fractions in [0, 1] (pbrt's
    /// --cropwindow; overrides the file's Film "cropwindow"/"pixelbounds").
    #[arg(long, allow_hyphen_values = true)]
    pub cropwindow: Option<String>,
    /// Render only pixels [x0, x1) × [y0, y1), given as x0,x1,y0,y1 (pbrt's --pixelbounds).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "cropwindow")]
    pub pixelbounds: Option<String>,
    /// Write timing figures as JSON to this file.
    #[arg(long)]
    pub stats_json: Option<PathBuf>,
    /// Sampler: sobol (prism's padded Owen-scrambled Sobol'), independent, or pbrt-v4's
    /// zsobol, globalsobol (pbrt-v4's "sobol": one Sobol' sequence over the image),
    /// paddedsobol, halton, pmj02bn, stratified, with pbrt-v4's default parameters
    /// [default: the file's, else sobol].
    #[arg(long)]
    pub sampler: Option<String>,
    /// Pixel filter with pbrt-v4's default parameters: box, gaussian, mitchell, sinc or
    /// triangle [default: the file's, else gaussian].
    #[arg(long)]
    pub filter: Option<String>,
    /// Maximum path depth, or -1 for no limit (Russian roulette ends every path) [default: the
    /// file's, else pbrt-v4's 5 for a scene file and 8 for the built-in Cornell box].
    #[arg(long, allow_negative_numbers = true)]
    pub max_depth: Option<i64>,
    /// Subsurface scattering: diffusion (PBD BSSRDF) or randomwalk (volumetric reference)
    /// [default: diffusion].
    #[arg(long)]
    pub sss: Option<String>,
    /// Light sampler for next-event estimation: bvh (importance at the shading point), power or
    /// uniform [default: the file's Integrator "lightsampler", else bvh].
    #[arg(long)]
    pub light_sampler: Option<String>,
    /// Integrator, by pbrt-v4's name: path or volpath (either renders a scene's media when it
    /// has any), ambientocclusion, randomwalk, simplepath, simplevolpath, lightpath, bdpt, mlt,
    /// sppm, or function (pbrt-v4's sampler test: writes the MSE per sample count as text to
    /// the output) [default: the file's Integrator, else path].
    #[arg(long)]
    pub integrator: Option<String>,
    /// Output colour space: srgb, rec2020, acescg, aces2065-1, display-p3 [default: srgb].
    #[arg(long)]
    pub color_space: Option<String>,
    /// Treat features prism does not render as errors instead of warnings.
    #[arg(long)]
    pub strict: bool,
    /// pbrt-v4's sphere, disk and cylinder: intersected exactly (`analytic`) or as inscribed
    /// triangle meshes (`tessellated`) [default: analytic].
    #[arg(long)]
    pub quadrics: Option<String>,
    /// Stop at the end of the pass during which this many seconds have passed (e.g. 30 or 30s).
    #[arg(long)]
    pub time_limit: Option<String>,
    /// Save the accumulated film to OUTPUT.ckpt at the end of a pass at most this often (e.g. 60s).
    #[arg(long)]
    pub checkpoint_every: Option<String>,
    /// Continue from OUTPUT.ckpt (written by --checkpoint-every) instead of starting over.
    #[arg(long)]
    pub resume: bool,
    /// Write pbrt-v4's geometry buffers beside R, G, B in one multi-channel OpenEXR output:
    /// Albedo, P, dzdx, dzdy, N, Ns, u, v, Variance, RelativeVariance (the file's Film "gbuffer"
    /// does the same; positions and normals in camera space unless it says "coordinatesystem"
    /// "world").
    #[arg(long)]
    pub aov: bool,
    /// Render only part i of N (e.g. 2/8): a disjoint share of the samples. Write it to a .film
    /// output and combine the parts with `prism merge`.
    #[arg(long)]
    pub part: Option<String>,
    /// Also write the image denoised by Intel Open Image Denoise beside the output, in its
    /// format (out.exr -> out.denoised.exr), guided by the albedo and normals it records for
    /// the purpose; the output stays the raw, unbiased estimate. Needs the library
    /// (scripts/install-oidn.sh, or PRISM_OIDN_LIB).
    #[arg(long)]
    pub denoise: bool,
    /// Render until the image's estimated error is at most this (RMSE of x/(1+x)-mapped RGB
    /// against the converged image, the error `prism compare` and `prism compat` report),
    /// giving more samples to noisier pixels; --spp is then the most a pixel takes, and
    /// --time-limit still stops it (docs/adaptive.md).
    #[arg(long)]
    pub target_error: Option<f64>,
    /// With --target-error: write each pixel's sample count as an image (OpenEXR: the counts;
    /// PNG: viridis from 0 to the largest count).
    #[arg(long, requires = "target_error")]
    pub spp_map: Option<PathBuf>,
    /// Render with the wavefront prototype (batches of paths advanced stage by stage; only the
    /// path integrator over surfaces lit by triangle area lights, without geometry buffers,
    /// spectral films or --target-error); prints the time of each stage.
    #[arg(long, hide = true)]
    pub wavefront: bool,
}

/// Parses four comma-separated numbers.
fn parse_four<T: std::str::FromStr>(flag: &str, s: &str) -> Result<[T; 4]> {
    let v: Vec<T> = s.split(',').map(|x| x.trim().parse()).collect::<Result<_, _>>().ok().unwrap_or_default();
    v.try_into().map_err(|_| anyhow::anyhow!("--{flag} '{s}' is not x0,x1,y0,y1"))
}

/// What `prism render` runs: a render, or pbrt-v4's sampler test (integrator `function`).
pub enum Prepared {
    /// A render of the scene.
    Render(Box<Job>),
    /// The sampler test, which renders nothing.
    Function(FunctionJob),
}

/// Checks every argument and loads the scene, before any rendering starts. Command-line values
/// override the scene file's, which override prism's defaults ([`RenderSettings::default`]).
pub fn prepare(args: &RenderArgs) -> Result<Prepared> {
    let started = Instant::now();
    let spp = args.spp.map(|n| settings::count(n, "--spp")).transpose()?;
    let accel = match &args.accel {
        Some(a) => AccelKind::parse(a)?,
        None => AccelKind::default_available(),
    };
    let resolution = args.resolution.as_deref().map(settings::parse_resolution).transpose()?;
    let crop_arg = match (&args.cropwindow, &args.pixelbounds) {
        (Some(c), _) => Some(Crop::Window(parse_four("cropwindow", c)?)),
        (_, Some(p)) => Some(Crop::Pixels(parse_four("pixelbounds", p)?)),
        _ => None,
    };
    let time_limit = args.time_limit.as_deref().map(settings::parse_duration).transpose()?;
    let integrator_kind = args.integrator.as_deref().map(IntegratorKind::parse).transpose()?;
    let max_depth = args.max_depth.map(|d| settings::max_depth(d, "--max-depth")).transpose()?;
    let sss = args.sss.as_deref().map(SubsurfaceMethod::parse).transpose()?;
    let light_sampler = match args.light_sampler.as_deref() {
        None => None,
        Some(name) => Some(LightSamplerKind::parse(name).map_err(|e| UnknownName { what: "--light-sampler", ..e })?),
    };

    let (mut builder, file, scene_name, inputs) = match &args.scene {
        None => (SceneBuilder::cornell_box(), FileSettings::default(), "builtin:cornell".to_string(), Vec::new()),
        Some(path) => {
            let quadrics = args.quadrics.as_deref().map(QuadricMode::parse).transpose()?;
            let loaded = load_scene_file(path, args.strict, quadrics.unwrap_or_default())?;
            let base = path.parent().unwrap_or(Path::new(""));
            let name = path.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
            (loaded.builder, loaded.settings, name, input_stamps(&loaded.inputs, base))
        }
    };
    if integrator_kind.unwrap_or(Integrator::from_file(&file).kind) == IntegratorKind::Function {
        let more = [(args.wavefront, "--wavefront"), (args.stats_json.is_some(), "--stats-json")];
        if let Some(flag) = film_state_refused(args, &more) {
            bail!("{flag} is not available with integrator \"function\": it writes the error of a sampler test, not an image");
        }
        let sampler = args.sampler.as_deref().map(settings::parse_sampler).transpose()?;
        let (output, seed) = (args.output.clone(), args.seed);
        let function = FunctionArgs { output, spp, resolution, crop: crop_arg, sampler, seed };
        return Ok(Prepared::Function(super::render_function::prepare(function, &file)?));
    }
    let d = RenderSettings::default();
    let sampler = args.sampler.as_deref().map(settings::parse_sampler).transpose()?.or(file.sampler);
    let filter = match args.filter.as_deref() {
        Some(name) => Some(settings::parse_filter(name)?),
        None => file.filter.clone(),
    };
    let space_name = args.color_space.as_deref().or(file.color_space.as_deref()).unwrap_or("srgb");
    let space = ColorSpace::by_name(space_name).with_context(|| {
        format!("unknown colour space '{space_name}' (valid: srgb, rec2020, acescg, aces2065-1, display-p3)")
    })?;
    let output = args
        .output
        .clone()
        .or_else(|| {
            file.filename.clone().map(|f| f.with_extension(f.extension().map_or("png".into(), |e| e.to_os_string())))
        })
        .unwrap_or_else(|| PathBuf::from("prism.png"));
    check_output(&output)?;
    let aov = aov_settings(args.aov, file.aov, &output, space)?;
    let spectral = file.spectral.filter(|_| {
        let kept = writes_named_channels(&output);
        if !kept {
            log::warn!("Film \"spectral\": its buckets need an OpenEXR output; {} gets R, G, B only", output.display());
        }
        kept
    });
    let write_aov = aov.is_some();
    let aov = aov.or(args.denoise.then_some(AovSettings { coordinates: AovSpace::Camera, space }));

    for w in &builder.warnings {
        log::warn!("{w}");
    }
    if let Some(kind) = light_sampler {
        builder.set_light_sampler(kind);
    }
    let resolution = resolution.or(file.resolution).unwrap_or(d.resolution);
    let crop = crop_arg.or(file.crop).map(|c| c.bounds(resolution)).transpose()?;
    // The rays the render will trace, about, so the accelerator's build can match them.
    let asked = integrator_asked(&file, integrator_kind, max_depth, sss);
    let (w, h) = crop.map_or(resolution, |b| (b.x1 - b.x0, b.y1 - b.y0));
    if let Some(per_sample) = asked.rays_per_sample() {
        let samples = spp.or(file.spp).unwrap_or(d.spp);
        builder.expect_rays((u64::from(w) * u64::from(h)).saturating_mul(samples).saturating_mul(per_sample));
    }
    let t0 = Instant::now();
    let scene = builder.build(accel).context("building the scene")?;
    let build_s = t0.elapsed().as_secs_f64();
    let mut integrator = integrator_for(&scene, &file, integrator_kind, max_depth, sss);
    integrator.ao.space = space;
    if spectral.is_some() && integrator.kind.splats() {
        log::warn!(
            "Film \"spectral\": integrator \"{}\" splats light the buckets do not record; rendering with \"path\"",
            integrator.kind.name()
        );
        integrator.kind = IntegratorKind::Path;
    }
    // A splatting estimator replaced (by the scene, or by the spectral film) is a substitution
    // like any other: under --strict an error.
    let named = integrator_kind.unwrap_or(Integrator::from_file(&file).kind);
    if args.strict && named.splats() && integrator.kind != named {
        let why = Integrator::fallback_reason(&scene).unwrap_or("its splats would miss the spectral film's buckets");
        bail!(
            "unsupported feature: integrator \"{}\" for this scene: {why} (strict mode; without --strict prism uses \"{}\" instead)",
            named.name(),
            integrator.kind.name()
        );
    }
    if let Some(why) = Integrator::bidirectional_ignores(&scene).filter(|_| args.strict && integrator.kind.splats()) {
        bail!("unsupported feature: integrator \"{}\" for this scene: {why} (strict mode)", integrator.kind.name());
    }
    let (mut aov, mut spectral, mut write_aov) = (aov, spectral, write_aov);
    if integrator.kind == IntegratorKind::Sppm {
        sppm_refusals(args)?;
        if let Some(why) = Integrator::sppm_ignores(&scene).filter(|_| args.strict) {
            bail!("unsupported feature: integrator \"sppm\" for this scene: {why} (strict mode)");
        }
        // Its pixels are density estimates, not sums of samples: the file's geometry buffers
        // and spectral buckets are left out.
        for (film, asked) in [("gbuffer", aov.is_some()), ("spectral", spectral.is_some())] {
            if asked {
                let message = format!("Film \"{film}\": integrator \"sppm\" records R, G, B only");
                if args.strict {
                    bail!("unsupported feature: {message} (strict mode)");
                }
                log::warn!("{message}");
            }
        }
        (aov, spectral, write_aov) = (None, None, false);
    }
    let (iso, exposure) = (file.iso.unwrap_or(100.0), file.exposure_time.unwrap_or(1.0));
    let white_balance = file.white_balance.unwrap_or(0.0);
    let sensor = match &file.camera_sensor {
        Some(name) => Sensor::camera(name, iso, exposure, white_balance, space)
            .with_context(|| format!("no curves for the sensor \"{name}\""))?,
        None => Sensor::new(iso, exposure, white_balance, space),
    }
    .with_max_component(file.max_component.filter(|m| *m > 0.0).unwrap_or(f32::INFINITY));
    let settings = RenderSettings {
        resolution,
        film: FilmSettings { crop, sensor, aov, spectral },
        // pbrt-v4's mlt takes its mutations per pixel and sppm its iterations from --spp, else
        // from their own parameters.
        spp: spp
            .or((integrator.kind == IntegratorKind::Mlt).then_some(integrator.mlt.mutations_per_pixel))
            .or(file.sppm_iterations.filter(|_| integrator.kind == IntegratorKind::Sppm))
            .or(file.spp)
            .unwrap_or(d.spp),
        seed: args.seed.or(file.seed).unwrap_or(d.seed),
        sampler: sampler.unwrap_or(d.sampler),
        filter: filter.unwrap_or(d.filter),
        integrator,
        time_limit,
        wavefront: args.wavefront,
    };
    if args.wavefront {
        crate::integrator::wavefront::check(&scene, &settings.integrator)?;
        if settings.film.aov.is_some() || settings.film.spectral.is_some() || args.target_error.is_some() {
            bail!("--wavefront renders without geometry buffers, spectral buckets or --target-error");
        }
    }
    let exr_sample = if file.save_fp16 == Some(false) { ExrSample::Float } else { ExrSample::Half };
    Ok(Prepared::Render(Box::new(Job {
        scene,
        settings,
        output,
        space,
        build_s,
        startup_s: started.elapsed().as_secs_f64(),
        scene_name,
        inputs,
        exr_sample,
        write_aov,
    })))
}

/// The geometry buffers to record: asked for by `--aov` (`flag`) or by the file's `gbuffer` film
/// (`file`, its coordinate system). They need an OpenEXR (or film-file) output: with `--aov`
/// another format is an error; the file's film then writes R, G, B only, with a warning.
fn aov_settings(
    flag: bool,
    file: Option<AovSpace>,
    output: &Path,
    space: &'static ColorSpace,
) -> Result<Option<AovSettings>> {
    let Some(coordinates) = file.or(flag.then_some(AovSpace::Camera)) else { return Ok(None) };
    if !writes_named_channels(output) {
        if flag {
            bail!("--aov writes its channels to OpenEXR only: give an .exr output, not {}", output.display());
        }
        log::warn!("Film \"gbuffer\": its channels need an OpenEXR output; {} gets R, G, B only", output.display());
        return Ok(None);
    }
    Ok(Some(AovSettings { coordinates, space }))
}

/// Whether `output` can hold channels beyond R, G, B: an OpenEXR, or a film file.
fn writes_named_channels(output: &Path) -> bool {
    let ext = output.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    ext == "exr" || ext == "film"
}

/// The integrator asked for, before a scene resolves it: command-line values (`named`,
/// `max_depth`, `sss`) over the file's, over prism's defaults.
fn integrator_asked(
    file: &FileSettings,
    named: Option<IntegratorKind>,
    max_depth: Option<u32>,
    sss: Option<SubsurfaceMethod>,
) -> Integrator {
    let from_file = Integrator::from_file(file);
    Integrator {
        kind: named.unwrap_or(from_file.kind),
        max_depth: max_depth.unwrap_or(from_file.max_depth),
        sss: sss.unwrap_or(from_file.sss),
        ..from_file
    }
}

/// The integrator for `scene`: command-line values (`named`, `max_depth`, `sss`) over the
/// file's, over prism's defaults, resolved against the scene ([`Integrator::for_scene`]). Every
/// subcommand that renders or measures a scene takes its integrator from here.
pub(crate) fn integrator_for(
    scene: &Scene,
    file: &FileSettings,
    named: Option<IntegratorKind>,
    max_depth: Option<u32>,
    sss: Option<SubsurfaceMethod>,
) -> Integrator {
    let asked = integrator_asked(file, named, max_depth, sss);
    let named = asked.kind;
    let integrator = asked.for_scene(scene);
    if named == IntegratorKind::Path && integrator.kind == IntegratorKind::VolPath {
        log::info!("the scene has media: integrator \"path\" renders them as \"volpath\"");
    }
    if named.splats() && integrator.kind != named {
        let why = Integrator::fallback_reason(scene).unwrap_or("");
        log::warn!("integrator \"{}\" renders this scene as \"{}\": {why}", named.name(), integrator.kind.name());
    }
    if let Some(why) = Integrator::sppm_ignores(scene).filter(|_| integrator.kind == IntegratorKind::Sppm) {
        log::warn!("integrator \"sppm\": {why}");
    }
    if let Some(why) = Integrator::bidirectional_ignores(scene).filter(|_| integrator.kind.splats()) {
        log::warn!("integrator \"{}\": {why}", integrator.kind.name());
    }
    integrator
}

/// Parses a pbrt-v4 file and maps it onto a builder, printing its warnings (in strict mode an
/// unsupported feature is the error instead).
pub(crate) fn load_scene_file(path: &Path, strict: bool, quadrics: QuadricMode) -> Result<LoadedScene> {
    if !path.exists() {
        bail!("scene file '{}' does not exist", path.display());
    }
    let opts = crate::pbrt::ParseOptions { strict, quadrics, ..Default::default() };
    let loaded = crate::pbrt::load_file(path, &opts)?;
    report_warnings(&loaded.warnings);
    Ok(loaded)
}

/// Prints each distinct warning once, as "prism: warning: file:line:col: message", at its first
/// place, with how many more places say the same.
fn report_warnings(warnings: &[crate::pbrt::Warning]) {
    let mut distinct: Vec<(&crate::pbrt::Warning, usize)> = Vec::new();
    let mut index: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    for w in warnings {
        match index.get(w.message.as_str()) {
            Some(&i) => distinct[i].1 += 1,
            None => {
                index.insert(&w.message, distinct.len());
                distinct.push((w, 0));
            }
        }
    }
    for (w, more) in distinct {
        match more {
            0 => log::warn!("{}: {}", w.loc, w.message),
            n => log::warn!("{}: {} ({n} more like it)", w.loc, w.message),
        }
    }
}

/// Extensions `prism render -o` accepts.
const OUTPUT_EXTENSIONS: [&str; 8] = ["exr", "png", "jpg", "jpeg", "tif", "tiff", "hdr", "film"];

/// Fails early, before rendering, on an output that could not be written.
pub fn check_output(path: &Path) -> Result<()> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    if !OUTPUT_EXTENSIONS.contains(&ext.as_str()) {
        bail!(
            "unsupported output format '{}' for {} (valid: {})",
            if ext.is_empty() { "(none)" } else { &ext },
            path.display(),
            OUTPUT_EXTENSIONS.join(", ")
        );
    }
    crate::io::check_dir_writable(path).with_context(|| format!("cannot write {}", path.display()))
}

/// The options an `sppm` render cannot honour: its pixels' state (radii, photon statistics)
/// lives outside the film, so it can be neither split, checkpointed nor resumed, nor given
/// per-pixel sample counts; and it records no geometry buffers.
fn sppm_refusals(args: &RenderArgs) -> Result<()> {
    match film_state_refused(args, &[]) {
        Some(flag) => bail!(
            "{flag} is not available with integrator \"sppm\": its pixels are progressive photon-map estimates whose state (radii, photon statistics) the film does not hold; use path or bdpt"
        ),
        None => Ok(()),
    }
}

/// The first of the options that split, checkpoint, resume or adapt a render through its film,
/// or add geometry buffers, given in `args` — or of `more` (given, flag) — if any.
fn film_state_refused(args: &RenderArgs, more: &[(bool, &'static str)]) -> Option<&'static str> {
    let refused = [
        (args.part.is_some(), "--part"),
        (args.checkpoint_every.is_some(), "--checkpoint-every"),
        (args.resume, "--resume"),
        (args.target_error.is_some(), "--target-error"),
        (args.aov, "--aov"),
        (args.denoise, "--denoise"),
    ];
    refused.iter().chain(more).find(|(given, _)| *given).map(|&(_, flag)| flag)
}

/// Parses "i/N" with 1 ≤ i ≤ N.
fn parse_part(s: &str) -> Result<(u64, u64)> {
    let (i, n) = s.split_once('/').with_context(|| format!("--part '{s}' is not i/N"))?;
    let (i, n): (u64, u64) = (
        i.trim().parse().with_context(|| format!("--part '{s}' is not i/N"))?,
        n.trim().parse().with_context(|| format!("--part '{s}' is not i/N"))?,
    );
    if n == 0 || i == 0 || i > n {
        bail!("--part {s}: need 1 <= i <= N");
    }
    Ok((i, n))
}

/// Refuses what Metropolis light transport cannot do: its image is normalised as a whole (no
/// share of the samples, checkpoint or per-pixel sample counts), its splats record no geometry
/// buffers, and its bootstrap needs a finite depth.
fn check_mlt(args: &RenderArgs, job: &Job) -> Result<()> {
    let refused = if args.part.is_some() || job.output.extension().is_some_and(|e| e == "film") {
        Some("--part and .film outputs")
    } else if args.checkpoint_every.is_some() || args.resume {
        Some("--checkpoint-every and --resume")
    } else if args.target_error.is_some() {
        Some("--target-error")
    } else if args.aov || args.denoise || job.settings.film.aov.is_some() {
        Some("geometry buffers (--aov, --denoise, Film \"gbuffer\")")
    } else if job.settings.integrator.max_depth == crate::integrator::UNBOUNDED_DEPTH {
        Some("an unbounded --max-depth")
    } else {
        None
    };
    match refused {
        Some(what) => {
            bail!("integrator \"mlt\" renders the image as a whole by Markov chains: it does not support {what}")
        }
        None => Ok(()),
    }
}

/// Runs `prism render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    let pool = super::worker_pool(args.threads)?;
    // Loading runs on the render's threads too: no second pool, and the many small parallel
    // passes of a scene of many small meshes run inline instead of being handed to a pool.
    let job = match pool.install(|| prepare(args))? {
        Prepared::Render(job) => job,
        Prepared::Function(job) => return super::render_function::run(&job, &pool),
    };
    let spp = job.settings.spp;
    let range = match &args.part {
        Some(p) => {
            let (i, n) = parse_part(p)?;
            let range = crate::checkpoint::part_range(i, n, spp);
            if range.is_empty() {
                bail!("--part {p}: {spp} samples per pixel in {n} parts leave this part none (use N <= {spp})");
            }
            range
        }
        None => 0..spp,
    };
    let film_output = job.output.extension().is_some_and(|e| e == "film");
    if let Some(p) = &args.stats_json {
        crate::io::check_dir_writable(p).with_context(|| format!("cannot write {}", p.display()))?;
    }
    if args.part.is_some() && !film_output {
        bail!("--part writes a share of the samples: give a .film output and combine with `prism merge`");
    }
    if args.denoise && film_output {
        bail!("--denoise writes an image beside an image output, not a .film: render the parts with --aov and denoise their merge (prism merge --denoise)");
    }
    if job.settings.integrator.kind == IntegratorKind::Mlt {
        check_mlt(args, &job)?;
    }
    // Before rendering: a missing library must not cost a render.
    let denoiser = args.denoise.then(crate::denoise::Denoiser::load).transpose()?;
    let denoiser = denoiser.map(|d| d.with_threads(args.threads));
    // Tessellated quadrics change the image: the backend's name carries the choice.
    let accel = match args.quadrics.as_deref().map(QuadricMode::parse) {
        Some(Ok(QuadricMode::Tessellated)) => format!("{} (tessellated quadrics)", job.scene.accel().name()),
        _ => job.scene.accel().name().to_string(),
    };
    // A crop keeps its place in the full image (OpenEXR data and display windows).
    let (full_width, full_height) = job.settings.resolution;
    let window = job.settings.film.crop.map(|b| CropWindow { x0: b.x0, y0: b.y0, full_width, full_height });
    if let Some(target) = args.target_error {
        let checkpoints = args.checkpoint_every.is_some() || args.resume;
        super::render_adaptive::check(target, args.part.is_some() || film_output, checkpoints)?;
        if job.settings.integrator.kind.splats() {
            bail!(
                "--target-error gives each pixel its own sample count; integrator \"{}\" splats light onto every pixel: use path",
                job.settings.integrator.kind.name()
            );
        }
        if let Some(p) = &args.spp_map {
            check_output(p)?;
        }
        let outputs = super::render_adaptive::Outputs {
            spp_map: args.spp_map.as_deref(),
            stats_json: args.stats_json.as_deref(),
            denoiser: denoiser.as_ref(),
        };
        return super::render_adaptive::run(&job, &pool, target, window, outputs);
    }
    let fp = crate::fingerprint::fingerprint(&job.scene_name, &job.inputs, &job.settings, job.space.name, &accel);
    let ckpt_path = PathBuf::from(format!("{}.ckpt", job.output.display()));
    let ckpt_every = args.checkpoint_every.as_deref().map(settings::parse_duration).transpose()?;
    let (w, h) = job.settings.film_size();
    let header = |samples: std::ops::Range<u64>| crate::checkpoint::FilmHeader {
        width: w,
        height: h,
        samples,
        spp_total: spp,
        fingerprint: fp.clone(),
        window,
        color_space: Some(job.space.name.to_string()),
        exr_float: job.exr_sample == ExrSample::Float,
        aov: job.settings.film.aov.is_some(),
        spectral: job.settings.film.spectral,
        splat_paths: None,
    };

    let mut film = crate::render::new_film(&job.settings)?;
    let mut start = range.start;
    if args.resume {
        let (f, hd) = crate::checkpoint::load(&ckpt_path)
            .with_context(|| format!("--resume: reading the checkpoint {}", ckpt_path.display()))?;
        if let Some(d) = crate::fingerprint::difference(&hd.fingerprint, &fp) {
            bail!("--resume: {} was written by a different scene or settings: {d}", ckpt_path.display());
        }
        if (hd.width, hd.height) != (w, h) || hd.samples.start != range.start {
            bail!("--resume: {} holds another part of the samples or image", ckpt_path.display());
        }
        film = f;
        start = hd.samples.end.min(range.end);
        eprintln!("prism: resuming at sample {start} of {}", range.end);
    }

    let mut progress = crate::progress::SppProgress::new(range.end - range.start, start - range.start);
    let interrupt = super::interrupt::Interrupt::install().context("installing the SIGINT and SIGTERM handlers")?;
    let t0 = Instant::now();
    let mut last_ckpt = Instant::now();
    let mut ckpt_error = None;
    let stats = pool.install(|| {
        let cancel = interrupt.flag();
        // Both reports write to the one progress display.
        let progress = std::cell::RefCell::new(&mut progress);
        let bootstrap = |done, total| progress.borrow_mut().bootstrap(done, total);
        crate::render::render_range_reporting(
            &job.scene,
            &job.settings,
            &mut film,
            start..range.end,
            cancel,
            bootstrap,
            |film, done| {
                progress.borrow_mut().set(done - range.start);
                if let Some(every) = ckpt_every {
                    if last_ckpt.elapsed() >= every && done < range.end {
                        if let Err(e) = crate::checkpoint::save(&ckpt_path, film, &header(range.start..done)) {
                            ckpt_error = Some(e);
                            return false;
                        }
                        last_ckpt = Instant::now();
                    }
                }
                true
            },
        )
    });
    if let Some(e) = ckpt_error {
        return Err(e).context("writing a checkpoint");
    }
    let elapsed = t0.elapsed().as_secs_f64();
    progress.finish();
    let done = range.start + film.pixels.first().map_or(0, |p| p.samples);
    // A signal that came after the last pass changes nothing: the render is whole.
    let interrupted = interrupt.status().filter(|_| done < range.end);
    let of = |done: u64| format!("{} of {} samples per pixel", done - range.start, range.end - range.start);
    if let Some(status) = interrupted.filter(|_| done == range.start) {
        return Err(Interrupted { status, message: format!("interrupted after {}; wrote nothing", of(done)) }.into());
    }

    let mut denoise_with = None;
    if film_output {
        // The header's sample range says which samples the part holds; `prism merge` names
        // the ones missing.
        crate::checkpoint::save(&job.output, &film, &header(range.start..done))?;
    } else {
        let meta = image_meta(&job, done - range.start, elapsed);
        let opts = WriteOptions { window, exr_sample: job.exr_sample, meta, ..Default::default() };
        write_film_image(&film, job.space, &job.output, &opts, job.write_aov)?;
        super::render_job::write_strategy_images(&film, job.space, &job.output, &opts)?;
        denoise_with = Some(opts);
    }
    if ckpt_every.is_some() {
        if done >= range.end {
            let _ = std::fs::remove_file(&ckpt_path);
        } else if interrupted.is_some() {
            crate::checkpoint::save(&ckpt_path, &film, &header(range.start..done)).context("writing a checkpoint")?;
        }
    }
    let rs = summarize(&job, &stats, elapsed);
    if interrupted.is_none() {
        eprintln!(
            "{}: {}x{} {} spp in {:.2} s  ({:.3} M samples/s, {:.2} M rays/s, {})",
            job.output.display(),
            rs.width,
            rs.height,
            done - range.start,
            rs.elapsed_s,
            rs.samples_per_s / 1e6,
            rs.rays_per_s / 1e6,
            rs.accel
        );
    }
    // A render stopped by a signal is wanted soon: it is not denoised.
    if let (Some(denoiser), Some(opts), true) = (&denoiser, &denoise_with, interrupted.is_none()) {
        super::denoised::write(denoiser, &film, job.space, &job.output, opts)?;
    }
    if job.settings.wavefront {
        let total: u64 = stats.stage_ns.iter().sum();
        for (stage, ns) in crate::integrator::wavefront::Stage::ALL.iter().zip(stats.stage_ns) {
            eprintln!(
                "  {:<18} {:7.3} s  {:5.1}%",
                stage.name(),
                ns as f64 * 1e-9,
                100.0 * ns as f64 / total.max(1) as f64
            );
        }
    }
    if stats.nonfinite > 0 {
        if let Some((x, y, s, d)) = stats.nonfinite_at.first() {
            log::warn!(
                "discarded {} non-finite samples; the first at pixel ({x}, {y}), sample {s}, depth {d}",
                stats.nonfinite
            );
        }
    }
    if let Some(p) = &args.stats_json {
        let text = serde_json::to_string_pretty(&rs)?;
        crate::io::write_atomic(p, text.as_bytes()).with_context(|| format!("writing {}", p.display()))?;
    }
    match interrupted {
        None => Ok(()),
        Some(status) => {
            let ckpt = match ckpt_every {
                Some(_) => format!(" and the checkpoint {}", ckpt_path.display()),
                None => String::new(),
            };
            let message = format!("interrupted after {}; wrote {}{ckpt}", of(done), job.output.display());
            Err(Interrupted { status, message }.into())
        }
    }
}

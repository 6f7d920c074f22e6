//! What a render job is and what it writes besides the image loop: the validated job, the
//! image written from a film, and the figures of `--stats-json`. Shared by the uniform and the
//! adaptive render.

use crate::film::{Film, StrategyImages};
use crate::image::{Chromaticities, ExrSample, FileFormat, ImageMeta, WriteOptions};
use crate::integrator::Stats;
use crate::pbrt::InputStamp;
use crate::render::RenderSettings;
use crate::scene::Scene;
use crate::spectrum::ColorSpace;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// Timing and throughput figures of a render (`--stats-json`).
#[derive(serde::Serialize, Debug)]
pub struct RenderStats {
    /// Wall time of the render loop [s].
    pub elapsed_s: f64,
    /// Samples per pixel actually taken.
    pub spp: u64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Rays traced.
    pub rays: u64,
    /// Rays per second.
    pub rays_per_s: f64,
    /// Camera samples per second.
    pub samples_per_s: f64,
    /// Backend.
    pub accel: String,
    /// Discarded non-finite samples.
    pub nonfinite_samples: u64,
    /// Scene build time (accelerator and lights) [s].
    pub build_s: f64,
    /// Time from the command's start to the first sample [s]: reading and translating the
    /// scene, and building it (the time to first pixel).
    pub startup_s: f64,
    /// Subsurface method (`--sss`).
    pub sss: String,
}

/// Validated settings and I/O choices for one render.
pub struct Job {
    /// The scene.
    pub scene: Scene,
    /// Settings.
    pub settings: RenderSettings,
    /// Output path.
    pub output: PathBuf,
    /// Output colour space.
    pub space: &'static ColorSpace,
    /// Scene build time [s].
    pub build_s: f64,
    /// Reading, translating and building the scene [s].
    pub startup_s: f64,
    /// The scene's name: the built-in Cornell box's, or the scene file's.
    pub scene_name: String,
    /// The files the scene reads, identified by their contents (none for the built-in scene).
    pub inputs: Vec<InputStamp>,
    /// OpenEXR sample type: half unless the file's Film "savefp16" is false (as pbrt-v4).
    pub exr_sample: ExrSample,
    /// Whether the output carries the geometry buffers (`--aov` or the file's `gbuffer` film);
    /// `--denoise` alone records them without writing them.
    pub write_aov: bool,
}

/// Writes `film` as an image to `path`: R, G, B, with the geometry buffers (when `aov` and the
/// film has them) and the spectral buckets after them (the buckets with the spectral layout's
/// header attributes); warns when the format cannot name the colour space.
pub(crate) fn write_film_image(
    film: &Film,
    space: &ColorSpace,
    path: &Path,
    opts: &WriteOptions,
    aov: bool,
) -> Result<()> {
    if let Some(w) = FileFormat::from_path(path).ok().and_then(|f| opts.meta.untagged_warning(f)) {
        eprintln!("prism: warning: {}: {w}", path.display());
    }
    let written = match film.to_layered_image(space, aov) {
        Some(image) => {
            let names = film.channel_names(aov);
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            let mut opts = opts.clone();
            opts.meta.spectral_layout = film.spectral.is_some();
            crate::image::write_channels(path, &image?, &names, &opts)
        }
        None => crate::image::write_with(path, &film.to_image(space)?, opts),
    };
    written.with_context(|| format!("writing {}", path.display()))
}

/// Writes the film's strategy images, if it records them, beside `output` under pbrt-v4's
/// names (`bdpt_d01_s02_t01.exr`, …), as OpenEXR.
pub(crate) fn write_strategy_images(film: &Film, space: &ColorSpace, output: &Path, opts: &WriteOptions) -> Result<()> {
    let Some(images) = &film.strategies else { return Ok(()) };
    let dir = output.parent().unwrap_or(Path::new(""));
    for (depth, s, t) in images.strategies() {
        let path = dir.join(StrategyImages::file_name(depth, s, t));
        let image = film.strategy_film(s, t).expect("a recorded strategy").to_image(space)?;
        crate::image::write_with(&path, &image, opts).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// What the image of a render of `job` says about itself: its colour space, the samples per
/// pixel it holds, the render time [s], seed and sampler, and where the camera was when the
/// shutter opened (pbrt-v4's `worldToCamera`, `worldToNDC`).
pub(crate) fn image_meta(job: &Job, samples_per_pixel: u64, elapsed: f64) -> ImageMeta {
    let open = job.scene.shutter.map_or(0.0, |(open, _)| open);
    let (camera_from_world, ndc_from_world) = job.scene.camera.header_matrices(open);
    ImageMeta {
        color_space: Some(Chromaticities::of(job.space)),
        samples_per_pixel: Some(samples_per_pixel),
        render_time_seconds: Some(elapsed),
        seed: Some(job.settings.seed),
        sampler: Some(job.settings.sampler.name().to_string()),
        world_to_camera: Some(camera_from_world.transpose().to_cols_array_2d()),
        world_to_ndc: ndc_from_world.map(|m| m.transpose().to_cols_array_2d()),
        ..Default::default()
    }
}

/// The figures of `--stats-json` for a render of `job` that took `elapsed` seconds.
pub(crate) fn summarize(job: &Job, stats: &Stats, elapsed: f64) -> RenderStats {
    let (w, h) = job.settings.film_size();
    let pixels = w as u64 * h as u64;
    RenderStats {
        elapsed_s: elapsed,
        spp: stats.samples.checked_div(pixels).unwrap_or(0),
        width: w,
        height: h,
        rays: stats.rays,
        rays_per_s: stats.rays as f64 / elapsed.max(1e-9),
        samples_per_s: stats.samples as f64 / elapsed.max(1e-9),
        accel: job.scene.accel().name().to_string(),
        nonfinite_samples: stats.nonfinite,
        build_s: job.build_s,
        startup_s: job.startup_s,
        sss: job.settings.integrator.sss.name().to_string(),
    }
}

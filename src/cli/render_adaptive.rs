//! `prism render --target-error E`: adaptive sampling to an estimated error ([`crate::adaptive`]).

use super::render_job::{image_meta, summarize, write_film_image, Job};
use super::Interrupted;
use crate::film::{AdaptivePixel, Film};
use crate::image::{CropWindow, Image, ImageMeta, WriteOptions};
use anyhow::{bail, Context, Result};
use std::path::Path;
use std::time::Instant;

/// Refuses, in one line each, what adaptive sampling cannot do: an error that is no positive
/// number, and the options that assume every pixel holds the same sample range: a part or a
/// .film output (`split`), checkpoints or resuming (`checkpoints`).
pub fn check(target: f64, split: bool, checkpoints: bool) -> Result<()> {
    if !(target.is_finite() && target > 0.0) {
        bail!("--target-error {target}: need a positive number (RMSE of x/(1+x)-mapped RGB, e.g. 0.01)");
    }
    if split {
        bail!("--target-error gives each pixel its own sample count: it cannot be split into --part or written to a .film");
    }
    if checkpoints {
        bail!(
            "--target-error renders cannot be checkpointed or resumed: film files hold one sample range for all pixels"
        );
    }
    Ok(())
}

/// Where an adaptive render writes besides its image.
pub struct Outputs<'a> {
    /// The per-pixel sample counts (`--spp-map`).
    pub spp_map: Option<&'a Path>,
    /// Timing figures (`--stats-json`).
    pub stats_json: Option<&'a Path>,
    /// The denoiser of `--denoise`, which writes the denoised image beside the output.
    pub denoiser: Option<&'a crate::denoise::Denoiser>,
}

/// Renders `job` until its estimated error is at most `target`, writes the image (and the
/// sample-count map with `--spp-map`), and prints the estimate.
pub fn run(job: &Job, pool: &rayon::ThreadPool, target: f64, window: Option<CropWindow>, out: Outputs) -> Result<()> {
    let (w, h) = job.settings.film_size();
    let mut film = Film::try_for(w, h, &job.settings.film)?;
    let max_spp = job.settings.spp;
    let mut progress = crate::progress::SppProgress::new(max_spp, 0);
    let interrupt = super::interrupt::Interrupt::install().context("installing the SIGINT and SIGTERM handlers")?;
    let t0 = Instant::now();
    let result = pool.install(|| {
        crate::adaptive::render_to_error(
            &job.scene,
            &job.settings,
            &mut film,
            job.space,
            target,
            interrupt.flag(),
            |_, pixels, _| {
                progress.set(pixels.iter().map(|p| p.taken).max().unwrap_or(0));
                true
            },
        )
    });
    let elapsed = t0.elapsed().as_secs_f64();
    progress.finish();
    let mean_spp = result.mean_spp();
    let met = result.estimated_error <= target;
    let interrupted = interrupt.status().filter(|_| !met);
    if let Some(status) = interrupted.filter(|_| mean_spp == 0.0) {
        return Err(Interrupted { status, message: "interrupted before the first pass; wrote nothing".into() }.into());
    }
    let meta = ImageMeta {
        estimated_error: Some(result.estimated_error),
        ..image_meta(job, mean_spp.round() as u64, elapsed)
    };
    let opts = WriteOptions { window, exr_sample: job.exr_sample, meta, ..Default::default() };
    write_film_image(&film, job.space, &job.output, &opts, job.write_aov)?;
    // A render stopped by a signal is wanted soon: it is not denoised.
    if let (Some(denoiser), None) = (out.denoiser, interrupted) {
        super::denoised::write(denoiser, &film, job.space, &job.output, &opts)?;
    }
    if let Some(p) = out.spp_map {
        write_spp_map(p, &film, &result.pixels, window)?;
    }
    let rs = summarize(job, &result.stats, elapsed);
    let why = if met {
        "target met"
    } else if interrupted.is_some() {
        "interrupted"
    } else if job.settings.time_limit.is_some_and(|t| t0.elapsed() >= t) {
        "time limit"
    } else {
        "every pixel that could lower it has its maximum (--spp)"
    };
    let max = result.pixels.iter().map(|p| p.taken).max().unwrap_or(0);
    eprintln!(
        "{}: {}x{} estimated error {:.5} (target {target}, {why}) with {mean_spp:.1} spp on average (max {max} of {max_spp}) in {:.2} s  ({:.3} M samples/s, {})",
        job.output.display(),
        rs.width,
        rs.height,
        result.estimated_error,
        rs.elapsed_s,
        rs.samples_per_s / 1e6,
        rs.accel
    );
    if let Some(p) = out.stats_json {
        let text = serde_json::to_string_pretty(&rs)?;
        crate::io::write_atomic(p, text.as_bytes()).with_context(|| format!("writing {}", p.display()))?;
    }
    match interrupted {
        None => Ok(()),
        Some(status) => Err(Interrupted {
            status,
            message: format!(
                "interrupted at estimated error {:.5} of target {target}; wrote {}",
                result.estimated_error,
                job.output.display()
            ),
        }
        .into()),
    }
}

/// Writes each pixel's sample count as an image: the counts themselves in OpenEXR (one value in
/// R, G and B), otherwise viridis from 0 (dark blue) to the largest count (yellow).
fn write_spp_map(path: &Path, film: &Film, pixels: &[AdaptivePixel], window: Option<CropWindow>) -> Result<()> {
    let counts: Vec<f32> = pixels.iter().map(|p| p.taken as f32).collect();
    let image = if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")) {
        let data = counts.iter().flat_map(|&n| [n; 3]).collect();
        Image { width: film.width, height: film.height, channels: 3, data }
    } else {
        let max = counts.iter().copied().fold(1.0, f32::max);
        crate::image::viridis_image(&counts, film.width, film.height, max)
    };
    let opts = WriteOptions { window, ..Default::default() };
    crate::image::write_with(path, &image, &opts).with_context(|| format!("writing {}", path.display()))
}

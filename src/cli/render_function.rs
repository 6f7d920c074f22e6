//! `prism render` with integrator `function` (pbrt-v4's test of the samplers): instead of an
//! image, the mean squared error of each film pixel's estimate of a known integral, per sample
//! count, written as text ([`crate::integrator::FunctionTest`]).

use crate::film::Crop;
use crate::integrator::{function_image, FunctionTest, Integrator};
use crate::pbrt::FileSettings;
use crate::render::RenderSettings;
use crate::sampling::SamplerKind;
use anyhow::{Context, Result};
use std::path::PathBuf;

/// A checked function test and where its results go.
pub struct FunctionJob {
    test: FunctionTest,
    /// The "n mse" text file.
    output: PathBuf,
    /// `imagefilename`: an image of the function.
    image: Option<PathBuf>,
}

/// What the command line gives the test (each overriding the file's).
pub(super) struct FunctionArgs {
    /// `-o`: the text file (pbrt-v4's `--outfile`).
    pub output: Option<PathBuf>,
    pub spp: Option<u64>,
    pub resolution: Option<(u32, u32)>,
    pub crop: Option<Crop>,
    pub sampler: Option<SamplerKind>,
    pub seed: Option<u64>,
}

/// The test the file and the command line ask for, as for a render.
pub(super) fn prepare(args: FunctionArgs, file: &FileSettings) -> Result<FunctionJob> {
    let d = RenderSettings::default();
    let options = Integrator::from_file(file).function;
    let resolution = args.resolution.or(file.resolution).unwrap_or(d.resolution);
    let bounds = args.crop.or(file.crop).map(|c| c.bounds(resolution)).transpose()?;
    let pixels = bounds.map_or(((0, resolution.0), (0, resolution.1)), |b| ((b.x0, b.x1), (b.y0, b.y1)));
    let test = FunctionTest {
        function: options.function,
        sampler: args.sampler.or(file.sampler).unwrap_or(d.sampler),
        spp: args.spp.or(file.spp).unwrap_or(d.spp),
        resolution,
        pixels,
        seed: args.seed.or(file.seed).unwrap_or(d.seed),
        skip_bad: options.skip_bad,
    };
    let output = args
        .output
        .or_else(|| file.function_filename.clone())
        .unwrap_or_else(|| PathBuf::from(format!("{}-mse.txt", test.function.name())));
    crate::io::check_dir_writable(&output).with_context(|| format!("cannot write {}", output.display()))?;
    let image = file.function_image_filename.clone();
    if let Some(p) = &image {
        crate::image::FileFormat::from_path(p)
            .with_context(|| format!("Integrator \"function\" \"imagefilename\" {}", p.display()))?;
        crate::io::check_dir_writable(p).with_context(|| format!("cannot write {}", p.display()))?;
    }
    Ok(FunctionJob { test, output, image })
}

/// Runs the test on the worker `pool` and writes its results (each file atomically).
pub(super) fn run(job: &FunctionJob, pool: &rayon::ThreadPool) -> Result<()> {
    let test = &job.test;
    if let Some(path) = &job.image {
        let ((x0, x1), (y0, y1)) = test.pixels;
        let image = pool.install(|| function_image(test.function, x1 - x0, y1 - y0));
        crate::image::write(path, &image)?;
    }
    let curve = pool.install(|| test.run())?;
    if curve.suspicious() {
        log::warn!("integrator \"function\": the average estimate is {}, suspiciously far from 1", curve.mean_estimate);
    }
    let output = &job.output;
    crate::io::write_atomic(output, curve.text().as_bytes())
        .with_context(|| format!("writing {}", output.display()))?;
    eprintln!(
        "{}: MSE of \"{}\" by sampler \"{}\" at {} sample counts up to {}",
        output.display(),
        test.function.name(),
        test.sampler.name(),
        curve.points.len(),
        test.spp
    );
    Ok(())
}

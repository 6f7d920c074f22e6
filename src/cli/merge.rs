//! `prism merge`: combine the .film parts of a split render into one image.

use crate::checkpoint;
use crate::image::{Chromaticities, ExrSample, ImageMeta, WriteOptions};
use crate::spectrum::ColorSpace;
use anyhow::{Context, Result};
use std::path::PathBuf;

/// Arguments of `prism merge`.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// The parts (.film files written by `prism render --part i/N`).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output image (or .film).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Output colour space [default: the render's].
    #[arg(long)]
    pub color_space: Option<String>,
    /// Also write the merged image denoised by Intel Open Image Denoise beside the output
    /// (out.exr -> out.denoised.exr); the parts must hold geometry buffers (`render --aov`).
    #[arg(long)]
    pub denoise: bool,
    /// Worker threads of the denoiser (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Runs `prism merge`.
pub fn run(args: &MergeArgs) -> Result<()> {
    if let Some(name) = &args.color_space {
        ColorSpace::by_name(name).with_context(|| format!("unknown colour space '{name}'"))?;
    }
    super::render::check_output(&args.output)?;
    let film_output = args.output.extension().is_some_and(|e| e == "film");
    if args.denoise && film_output {
        anyhow::bail!("--denoise writes an image beside an image output, not a .film");
    }
    let denoiser = args.denoise.then(crate::denoise::Denoiser::load).transpose()?.map(|d| d.with_threads(args.threads));
    let parts = args.parts.iter().map(|p| checkpoint::load(p)).collect::<Result<Vec<_>, _>>()?;
    let (film, header) = checkpoint::merge(parts)?;
    let name = args.color_space.as_deref().or(header.color_space.as_deref()).unwrap_or("srgb");
    let space = ColorSpace::by_name(name).with_context(|| format!("the parts' colour space '{name}' is unknown"))?;
    if header.samples.end - header.samples.start != header.spp_total {
        log::warn!(
            "the parts hold samples {:?} of {}: the image has fewer samples than the render asked for",
            header.samples,
            header.spp_total
        );
    }
    if denoiser.is_some() && !header.aov {
        anyhow::bail!("--denoise needs the parts' geometry buffers: render the parts with --aov");
    }
    if film_output {
        checkpoint::save(&args.output, &film, &header)?;
    } else {
        // A cropped render keeps its place in the full image, its OpenEXR sample type and its
        // geometry buffers, as `prism render` writes it.
        let exr_sample = if header.exr_float { ExrSample::Float } else { ExrSample::Half };
        // The file says which space and how many samples it holds; the parts' times and the
        // render's seed are not in their headers.
        let meta = ImageMeta {
            color_space: Some(Chromaticities::of(space)),
            samples_per_pixel: Some(header.samples.end - header.samples.start),
            ..Default::default()
        };
        let opts = WriteOptions { window: header.window, exr_sample, meta, ..Default::default() };
        super::render::write_film_image(&film, space, &args.output, &opts, true)?;
        if let Some(denoiser) = &denoiser {
            super::denoised::write(denoiser, &film, space, &args.output, &opts)?;
        }
    }
    eprintln!("{}: merged {} parts, samples {:?}", args.output.display(), args.parts.len(), header.samples);
    Ok(())
}

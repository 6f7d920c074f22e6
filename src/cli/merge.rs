//! `prism merge`: combine the .film parts of a split render into one image.

use crate::checkpoint;
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
    /// Output colour space.
    #[arg(long, default_value = "srgb")]
    pub color_space: String,
}

/// Runs `prism merge`.
pub fn run(args: &MergeArgs) -> Result<()> {
    let space = ColorSpace::by_name(&args.color_space)
        .with_context(|| format!("unknown colour space '{}'", args.color_space))?;
    super::render::check_output(&args.output)?;
    let parts = args.parts.iter().map(|p| checkpoint::load(p)).collect::<Result<Vec<_>, _>>()?;
    let (film, header) = checkpoint::merge(parts)?;
    if header.samples.end - header.samples.start != header.spp_total {
        log::warn!(
            "the parts hold samples {:?} of {}: the image has fewer samples than the render asked for",
            header.samples,
            header.spp_total
        );
    }
    if args.output.extension().is_some_and(|e| e == "film") {
        checkpoint::save(&args.output, &film, &header)?;
    } else {
        let image = super::render::film_to_image(&film, space)?;
        crate::image::write(&args.output, &image).with_context(|| format!("writing {}", args.output.display()))?;
    }
    eprintln!("{}: merged {} parts, samples {:?}", args.output.display(), args.parts.len(), header.samples);
    Ok(())
}

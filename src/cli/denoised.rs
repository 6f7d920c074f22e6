//! `--denoise` of `prism render` and `prism merge`: the denoised image beside the raw one.

use crate::denoise::{DenoiseInputs, Denoiser};
use crate::film::Film;
use crate::image::WriteOptions;
use crate::spectrum::ColorSpace;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where the denoised copy of `raw` goes: `out.exr` → `out.denoised.exr`, in the same format.
pub(crate) fn denoised_path(raw: &Path) -> PathBuf {
    let ext = raw.extension().map_or(String::new(), |e| e.to_string_lossy().into_owned());
    raw.with_extension(format!("denoised.{ext}"))
}

/// Denoises `film` (which records geometry buffers) in `space` and writes it beside `raw` with
/// the raw image's options; says where in one line.
pub(crate) fn write(
    denoiser: &Denoiser,
    film: &Film,
    space: &ColorSpace,
    raw: &Path,
    opts: &WriteOptions,
) -> Result<()> {
    let path = denoised_path(raw);
    let t0 = Instant::now();
    let inputs = DenoiseInputs::from_film(film, space)?;
    let image = denoiser.denoise(&inputs).with_context(|| format!("denoising {}", raw.display()))?;
    let seconds = t0.elapsed().as_secs_f64();
    crate::image::write_with(&path, &image, opts).with_context(|| format!("writing {}", path.display()))?;
    eprintln!("{}: denoised by Open Image Denoise in {seconds:.2} s", path.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_denoised_image_goes_beside_the_raw_one_in_its_format() {
        assert_eq!(denoised_path(Path::new("out.exr")), PathBuf::from("out.denoised.exr"));
        assert_eq!(denoised_path(Path::new("dir/a.b.png")), PathBuf::from("dir/a.b.denoised.png"));
    }
}

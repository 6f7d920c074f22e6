//! Denoising a rendered image with Intel Open Image Denoise 2 (OIDN), a convolutional network
//! trained on path-traced images (the "RT" filter), guided by the first visible surface's albedo
//! and shading normal from the geometry buffers ([`crate::film::gbuffer`]). As OIDN's
//! documentation recommends for noisy auxiliary images, the albedo and the normal are denoised
//! first by their own RT filters, and the beauty's filter is then told they are clean
//! (`cleanAux`). The beauty is HDR linear RGB in the output colour space (`hdr`).
//!
//! The library is loaded at run time (`PRISM_OIDN_LIB`, else the copy `scripts/install-oidn.sh`
//! puts in `target/oidn/lib`, else the system's `libOpenImageDenoise.so.2`), so prism builds and
//! runs without it; only denoising needs it. A denoised image is biased: it complements the
//! unbiased raw estimate, it does not replace it.

#[cfg(feature = "oidn")]
mod oidn_ffi;

use crate::film::Film;
use crate::image::Image;
use crate::spectrum::ColorSpace;
use std::path::PathBuf;

/// The library's file name (its soname).
pub const LIBRARY: &str = "libOpenImageDenoise.so.2";

/// How to get the library, said by every error that lacks it.
const HOW_TO_GET: &str =
    "run scripts/install-oidn.sh, or set PRISM_OIDN_LIB=/path/libOpenImageDenoise.so.2 (Intel Open Image Denoise 2)";

/// Why an image could not be denoised.
#[derive(Clone, Debug, thiserror::Error)]
pub enum DenoiseError {
    /// prism was built without the `oidn` feature.
    #[error("denoising needs a prism built with the `oidn` feature (cargo build --features oidn)")]
    NotBuilt,
    /// No candidate path holds the library.
    #[error("Intel Open Image Denoise 2 ({LIBRARY}) was not found: {HOW_TO_GET}")]
    NotFound,
    /// The library or one of its functions failed to load.
    #[error("cannot load Intel Open Image Denoise from {}: {cause}; {HOW_TO_GET}", path.display())]
    Load {
        /// The file tried.
        path: PathBuf,
        /// The loader's message.
        cause: String,
    },
    /// The film records no albedo and normals.
    #[error("denoising needs the film's geometry buffers (albedo and normals)")]
    NoGeometryBuffers,
    /// OIDN's own message.
    #[error("Open Image Denoise: {0}")]
    Library(String),
    /// The film's images do not fit in memory.
    #[error(transparent)]
    Alloc(#[from] crate::film::FilmAllocError),
}

/// What the RT filter reads: three `width` × `height` packed RGB images (row-major, f32).
#[derive(Clone, Debug, PartialEq)]
pub struct DenoiseInputs {
    /// Width [pixels].
    pub width: u32,
    /// Height [pixels].
    pub height: u32,
    /// The beauty: linear RGB radiance in the output colour space.
    pub color: Vec<f32>,
    /// The first visible surface's albedo (reflectance lit by the space's white), in [0, 1].
    pub albedo: Vec<f32>,
    /// The first visible surface's shading normal (unit, or 0 where no surface was seen).
    pub normal: Vec<f32>,
}

impl DenoiseInputs {
    /// The beauty, albedo and shading normal of a film that records geometry buffers, in `space`.
    pub fn from_film(film: &Film, space: &ColorSpace) -> Result<Self, DenoiseError> {
        if film.aov.is_none() {
            return Err(DenoiseError::NoGeometryBuffers);
        }
        let image = film.to_layered_image(space, true).ok_or(DenoiseError::NoGeometryBuffers)??;
        let names = film.channel_names(true);
        let channel = |name: &str| names.iter().position(|c| c == name).expect("a gbuffer channel");
        let c = image.channels as usize;
        let pick = |first: usize| -> Vec<f32> {
            image.data.chunks_exact(c).flat_map(|px| px[first..first + 3].iter().copied()).collect()
        };
        Ok(DenoiseInputs {
            width: film.width,
            height: film.height,
            color: pick(channel("R")),
            albedo: pick(channel("Albedo.R")),
            normal: pick(channel("Ns.X")),
        })
    }
}

/// Intel Open Image Denoise, loaded.
pub struct Denoiser {
    #[cfg(feature = "oidn")]
    oidn: &'static oidn_ffi::Oidn,
    /// The library file (or bare name, as the dynamic loader searched it).
    pub library: PathBuf,
    /// Worker threads the denoiser runs (`None`: OIDN's default, every core).
    pub threads: Option<usize>,
}

impl std::fmt::Debug for Denoiser {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Denoiser {{ library: {} }}", self.library.display())
    }
}

/// Where the library may be: only `PRISM_OIDN_LIB` when it is set; else the copy
/// `scripts/install-oidn.sh` makes beside the executable's directory (`target/oidn/lib` for
/// `target/release/prism`) or in the source tree's `target/`, then the system's by name.
#[cfg(feature = "oidn")]
fn candidates() -> Vec<PathBuf> {
    if let Some(path) = std::env::var_os("PRISM_OIDN_LIB") {
        return vec![PathBuf::from(path)];
    }
    let installed = |target: &std::path::Path| target.join("oidn/lib").join(LIBRARY);
    let mut paths: Vec<PathBuf> = Vec::new();
    if let Some(target) = std::env::current_exe().ok().as_deref().and_then(|e| e.parent()?.parent()) {
        paths.push(installed(target));
    }
    paths.push(installed(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target")));
    paths.retain(|p| p.is_file());
    paths.push(PathBuf::from(LIBRARY));
    paths
}

impl Denoiser {
    /// Loads the library (once per process: it is never unloaded, as OIDN's worker threads may
    /// outlive a filter).
    #[cfg(feature = "oidn")]
    pub fn load() -> Result<Self, DenoiseError> {
        use std::sync::OnceLock;
        static OIDN: OnceLock<Result<(oidn_ffi::Oidn, PathBuf), DenoiseError>> = OnceLock::new();
        let loaded = OIDN.get_or_init(|| {
            let explicit = std::env::var_os("PRISM_OIDN_LIB").is_some();
            let mut last = DenoiseError::NotFound;
            for path in candidates() {
                match oidn_ffi::Oidn::load(&path) {
                    Ok(oidn) => return Ok((oidn, path)),
                    // A bare name the loader did not find is "not found"; a file that does not
                    // load, or PRISM_OIDN_LIB's, says why.
                    Err(e) if explicit || path.components().count() > 1 => {
                        last = DenoiseError::Load { path, cause: e.to_string() }
                    }
                    Err(_) => {}
                }
            }
            Err(last)
        });
        match loaded {
            Ok((oidn, path)) => Ok(Denoiser { oidn, library: path.clone(), threads: None }),
            Err(e) => Err(e.clone()),
        }
    }

    /// Without the `oidn` feature: always [`DenoiseError::NotBuilt`].
    #[cfg(not(feature = "oidn"))]
    pub fn load() -> Result<Self, DenoiseError> {
        Err(DenoiseError::NotBuilt)
    }

    /// This denoiser running `threads` worker threads (`None`: OIDN's default, every core).
    pub fn with_threads(self, threads: Option<usize>) -> Self {
        Self { threads, ..self }
    }

    /// The denoised beauty of `inputs`: a 3-channel linear RGB image of the same size.
    #[cfg(feature = "oidn")]
    pub fn denoise(&self, inputs: &DenoiseInputs) -> Result<Image, DenoiseError> {
        use oidn_ffi::{Device, Image as Oidn};
        let (w, h) = (inputs.width as usize, inputs.height as usize);
        let n = inputs.color.len();
        let zeros = || -> Result<Vec<f32>, DenoiseError> {
            let mut v = Vec::new();
            v.try_reserve_exact(n).map_err(|_| crate::film::Film::alloc_error(inputs.width, inputs.height, n * 4))?;
            v.resize(n, 0.0);
            Ok(v)
        };
        let (mut albedo, mut normal, mut output) = (zeros()?, zeros()?, zeros()?);
        let mut run = || -> Result<(), String> {
            let device = Device::new(self.oidn, self.threads)?;
            // Prefiltering: each auxiliary image denoised by its own RT filter.
            device.filter("RT", &mut [Oidn::In("albedo", &inputs.albedo), Oidn::Out(&mut albedo)], &[], w, h)?;
            device.filter("RT", &mut [Oidn::In("normal", &inputs.normal), Oidn::Out(&mut normal)], &[], w, h)?;
            let mut images = [
                Oidn::In("color", &inputs.color),
                Oidn::In("albedo", &albedo),
                Oidn::In("normal", &normal),
                Oidn::Out(&mut output),
            ];
            device.filter("RT", &mut images, &[("hdr", true), ("cleanAux", true)], w, h)
        };
        run().map_err(DenoiseError::Library)?;
        Ok(Image { width: inputs.width, height: inputs.height, channels: 3, data: output })
    }

    /// Without the `oidn` feature: always [`DenoiseError::NotBuilt`].
    #[cfg(not(feature = "oidn"))]
    pub fn denoise(&self, _inputs: &DenoiseInputs) -> Result<Image, DenoiseError> {
        Err(DenoiseError::NotBuilt)
    }
}

#[cfg(all(test, feature = "oidn"))]
mod tests {
    use super::*;

    /// `--threads n` reaches the device: OIDN reports the worker count it was given, every core
    /// when none was (it runs at most one a core, so only one thread tells the two apart on a
    /// machine of several). Skips, saying so, without the library.
    #[test]
    fn the_device_runs_the_threads_it_is_given() {
        let denoiser = match Denoiser::load() {
            Ok(d) => d,
            Err(e) => return eprintln!("skipped: {e}"),
        };
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as i32;
        for (threads, reported) in [(None, cores), (Some(1), 1)] {
            let device = oidn_ffi::Device::new(denoiser.oidn, threads).unwrap();
            assert_eq!(device.threads(), reported, "{threads:?}");
        }
    }
}

//! The render loop: passes of samples over the image, parallel over bands of rows with rayon.
//! Every sample's random numbers depend only on (pixel, sample index, seed), and each pixel adds
//! its samples in index order, so the image is bit-identical for any thread count, and a render
//! can be split into disjoint sample ranges and merged.

use crate::camera::Camera;
use crate::film::{
    AdaptivePixel, AovPixel, AovSettings, AovSpace, Film, FilmAllocError, Pixel, SpectralSettings, Splat,
    StrategyImages,
};
use crate::filter::Filter;
use crate::integrator::{camera_sample, wavefront, Integrator, IntegratorKind, Stats, StrategyImageKind};
use crate::material::Material;
pub use crate::render_settings::RenderSettings;
use crate::sampling::Sampler;
pub use crate::sampling::SamplerKind;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::TextureFootprint;
use glam::{Mat3, Mat4};
use rayon::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Version of the sample stream: what a (pixel, sample index, seed) renders. Saved films that
/// are to be extended must come from the same version. 2: wavelengths stratified with the
/// sampler and drawn with the film position (`Sampler::get_pixel_3d`). 3: one 2D draw chooses
/// the light and the point on it (`Scene::sample_light`).
pub const SAMPLE_STREAM_VERSION: u32 = 3;

/// Rows per parallel work item.
const BAND_ROWS: usize = 4;

/// Where a camera sample's wavelengths come from and where its spectral radiance goes: nowhere
/// for an RGB film, a band of spectral buckets for a spectral one. The render loop is
/// instantiated once for each, so an RGB film pays nothing for the buckets.
trait SpectralSink {
    /// The wavelengths of a camera sample from `u`.
    fn sample_wavelengths(&self, u: f32) -> SampledWavelengths;
    /// Adds the radiance `l` of a sample of pixel `i` of the band, filter weight `w`.
    fn add(&mut self, i: usize, l: &SampledSpectrum, lambdas: &SampledWavelengths, w: f32);
}

/// No buckets: wavelengths sampled by the luminous efficiency.
struct NoSpectrum;

impl SpectralSink for NoSpectrum {
    #[inline]
    fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        SampledWavelengths::sample_visible(u)
    }

    #[inline]
    fn add(&mut self, _: usize, _: &SampledSpectrum, _: &SampledWavelengths, _: f32) {}
}

/// A band of pixels' spectral bucket sums.
struct SpectralBand<'a> {
    settings: SpectralSettings,
    sums: &'a mut [f64],
    /// The sensor's `maxcomponentvalue`.
    max_component: f32,
}

impl SpectralSink for SpectralBand<'_> {
    #[inline]
    fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        self.settings.sample_wavelengths(u)
    }

    #[inline]
    fn add(&mut self, i: usize, l: &SampledSpectrum, lambdas: &SampledWavelengths, w: f32) {
        let n = self.settings.stride();
        self.settings.add(&mut self.sums[i * n..(i + 1) * n], l, lambdas, w, self.max_component);
    }
}

/// Which samples a pass adds to each pixel.
pub enum PassSamples<'a> {
    /// The same sample indices for every pixel.
    Every(Range<u64>),
    /// Each pixel its own: samples `taken..taken + planned` of [`AdaptivePixel`] (one per film
    /// pixel), whose count and moments of output RGB (`to_rgb`: XYZ → RGB) the pass updates.
    PerPixel {
        /// One per film pixel, row-major.
        pixels: &'a mut [AdaptivePixel],
        /// The output colour space's XYZ → RGB matrix.
        to_rgb: Mat3,
    },
}

/// What every band of a pass shares.
struct Pass<'a> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    camera: Camera,
    integrator: Integrator,
    /// The camera-ray differentials, when something needs them.
    differentials: Option<&'a TextureFootprint>,
    /// The geometry buffers' settings, when they are recorded.
    aov: Option<AovSettings>,
    /// The film's width [pixels] and the full-image pixel of its (0, 0).
    width: usize,
    origin: (u32, u32),
    /// The sample indices of the pass (for every pixel when not adaptive).
    range: Range<u64>,
    /// XYZ → output RGB, for the adaptive pixels' moments.
    to_rgb: Mat3,
}

/// One pass's worth of work: samples `range` of every pixel.
pub fn render_pass(scene: &Scene, settings: &RenderSettings, film: &mut Film, range: Range<u64>) -> Stats {
    render_pass_of(scene, settings, film, PassSamples::Every(range))
}

/// One pass's worth of work: the samples `samples` names.
pub fn render_pass_of(scene: &Scene, settings: &RenderSettings, film: &mut Film, samples: PassSamples) -> Stats {
    let camera = scene.camera.camera(settings.resolution);
    let integrator =
        Integrator { footprint: Some(TextureFootprint::new(&camera, settings.spp)), ..settings.integrator }
            .for_scene(scene);
    let width = film.width as usize;
    if width == 0 {
        return Stats::default(); // an empty film: nothing to render (and no chunk size of 0)
    }
    let aov = settings.film.aov.filter(|_| film.aov.is_some());
    // A camera ray's own differentials are only needed where a texture is filtered with them,
    // or where the geometry buffers record the pixel footprint.
    let differentials =
        integrator.footprint.as_ref().filter(|_| aov.is_some() || scene.materials().iter().any(Material::is_textured));
    let band = width * BAND_ROWS;
    let (range, to_rgb, adaptive_bands): (Range<u64>, Mat3, Vec<Option<&mut [AdaptivePixel]>>) = match samples {
        PassSamples::Every(range) => (range, Mat3::IDENTITY, film.pixels.chunks(band).map(|_| None).collect()),
        PassSamples::PerPixel { pixels, to_rgb } => {
            assert_eq!(pixels.len(), film.pixels.len(), "one adaptive pixel per film pixel");
            (0..0, to_rgb, pixels.chunks_mut(band).map(Some).collect())
        }
    };
    let origin = settings.film_origin();
    let pass = Pass { scene, settings, camera, integrator, differentials, aov, width, origin, range, to_rgb };
    let aov_bands: Vec<Option<&mut [AovPixel]>> = match film.aov.as_mut().filter(|_| aov.is_some()) {
        Some(a) => a.chunks_mut(band).map(Some).collect(),
        None => film.pixels.chunks(band).map(|_| None).collect(),
    };
    // The spectral buckets: the film's, when the settings ask for the same ones.
    let spectral = settings.film.spectral.filter(|s| film.spectral.as_ref().is_some_and(|f| f.settings == *s));
    let spectral_bands: Vec<Option<&mut [f64]>> = match (film.spectral.as_mut(), spectral) {
        (Some(f), Some(s)) => f.sums.chunks_mut(band * s.stride()).map(Some).collect(),
        _ => film.pixels.chunks(band).map(|_| None).collect(),
    };
    let merge = |mut a: Stats, b: Stats| {
        a.merge(&b);
        a
    };
    let Some(splat_buffer) = film.splats.as_mut().filter(|_| pass.integrator.kind.splats()) else {
        return film
            .pixels
            .par_chunks_mut(band)
            .zip(aov_bands)
            .zip(spectral_bands)
            .zip(adaptive_bands)
            .enumerate()
            .map(|(band, (((pixels, aov_pixels), sums), adaptive))| match (spectral, sums) {
                (Some(settings), Some(sums)) => {
                    let sink = SpectralBand { settings, sums, max_component: pass.settings.film.sensor.max_component };
                    render_band(&pass, band, pixels, aov_pixels, adaptive, None, sink)
                }
                _ if pass.settings.wavefront && aov_pixels.is_none() && adaptive.is_none() => {
                    wavefront_band(&pass, band, pixels)
                }
                _ => render_band(&pass, band, pixels, aov_pixels, adaptive, None, NoSpectrum),
            })
            .reduce(Stats::default, merge);
    };
    // Splats land anywhere on the film: each band gathers its own, and they are added band by
    // band in order, a group of bands at a time (which bounds the memory they take). The sums
    // are therefore the same for any thread count. (Splatting estimators render neither
    // adaptively nor into spectral buckets.)
    let group_bands = 4 * rayon::current_num_threads();
    let height = film.height;
    let paths = film.pixels.len() as u64 * (pass.range.end - pass.range.start);
    splat_buffer.paths += paths;
    // Strategy images are box-filtered, as pbrt-v4's.
    let box_filter = Filter::by_name("box").expect("a built-in filter");
    for image in film.strategies.iter_mut().flat_map(|s| &mut s.images) {
        image.paths += paths;
    }
    let mut aov_bands = aov_bands.into_iter();
    let mut stats = Stats::default();
    for (g, group) in film.pixels.chunks_mut(band * group_bands).enumerate() {
        let aov_group: Vec<_> = aov_bands.by_ref().take(group.len().div_ceil(band)).collect();
        let done: Vec<(Stats, Vec<BandSplat>)> = group
            .par_chunks_mut(band)
            .zip(aov_group)
            .enumerate()
            .map(|(b, (pixels, aov_pixels))| {
                let mut splats = Vec::new();
                let band = g * group_bands + b;
                let stats = render_band(&pass, band, pixels, aov_pixels, None, Some(&mut splats), NoSpectrum);
                (stats, splats)
            })
            .collect();
        for (band_stats, splats) in done {
            stats.merge(&band_stats);
            for (sp, strategy) in &splats {
                match (strategy, film.strategies.as_mut()) {
                    (None, _) => splat_buffer.add(sp, &settings.filter, width as u32, height, origin),
                    (Some(i), Some(images)) if *i < images.images.len() => {
                        images.images[*i].add(sp, &box_filter, width as u32, height, origin)
                    }
                    _ => {}
                }
            }
        }
    }
    stats
}

/// An empty film for `settings`: with the geometry buffers and spectral buckets it asks for,
/// and a splat buffer when the integrator splats. Fails when it cannot be allocated.
pub fn new_film(settings: &RenderSettings) -> Result<Film, FilmAllocError> {
    let (w, h) = settings.film_size();
    let mut film = Film::try_for(w, h, &settings.film)?;
    if settings.integrator.kind.splats() {
        let (fw, fh) = settings.resolution;
        film = film.try_with_splats(fw as u64 * fh as u64)?;
        if settings.integrator.kind == IntegratorKind::Bdpt
            && settings.integrator.strategy_images != StrategyImageKind::Off
        {
            let pixels = film.pixels.len();
            film.strategies = Some(StrategyImages::new(settings.integrator.max_depth, pixels, fw as u64 * fh as u64));
        }
    }
    Ok(film)
}

/// [`render_band`] without geometry buffers, spectral buckets or adaptive sampling, by the
/// wavefront loop.
fn wavefront_band(pass: &Pass, band: usize, pixels: &mut [Pixel]) -> Stats {
    let Pass { scene, settings, ref camera, ref integrator, differentials, width, origin: (x0, y0), .. } = *pass;
    let job = wavefront::BandJob {
        scene,
        camera,
        integrator,
        filter: &settings.filter,
        sensor: &settings.film.sensor,
        sampler: settings.sampler,
        seed: settings.seed,
        spp: settings.spp,
        resolution: settings.resolution,
        differentials,
    };
    let pixel_at = |i: usize| (x0 + (i % width) as u32, y0 + (band * BAND_ROWS + i / width) as u32);
    wavefront::render_band(&job, pixel_at, pass.range.clone(), pixels)
}
/// A splat a band made, and the strategy image it alone belongs to
/// ([`StrategyImages::index`]; `None`: the main image).
type BandSplat = (Splat, Option<usize>);

/// Samples `pass.range` of every pixel of band `band` (its pixels, geometry buffers and
/// spectral sink), or each adaptive pixel's planned samples.
fn render_band<S: SpectralSink>(
    pass: &Pass,
    band: usize,
    pixels: &mut [Pixel],
    mut aov_pixels: Option<&mut [AovPixel]>,
    mut adaptive: Option<&mut [AdaptivePixel]>,
    mut splats: Option<&mut Vec<BandSplat>>,
    mut spectral: S,
) -> Stats {
    let Pass {
        scene, settings, ref camera, ref integrator, differentials, aov, width, origin: (x0, y0), to_rgb, ..
    } = *pass;
    let sensor = settings.film.sensor;
    let mut stats = Stats::default();
    // Pixels are named by their place in the full image, so a crop renders exactly the samples
    // of the same pixels of the full render.
    let pixel_at = |i: usize| (x0 + (i % width) as u32, y0 + (band * BAND_ROWS + i / width) as u32);
    // A camera sample of pixel `(x, y)`: its wavelengths, filter weight, ray and the ray's
    // differentials.
    let start = |sampler: &mut Sampler, spectral: &S, (x, y): (u32, u32), s: u64| {
        let wavelengths = |u| spectral.sample_wavelengths(u);
        let c = camera_sample(
            scene,
            camera,
            &settings.filter,
            differentials,
            sampler,
            wavelengths,
            (x, y),
            s,
            settings.seed,
        );
        (c.lambdas, c.filter_weight, c.ray, c.differentials, c.p_film)
    };
    // The sensor's response to an estimate, or `None` (counted) when it is not finite and is
    // dropped.
    let respond = |stats: &mut Stats, (x, y), s, l: &SampledSpectrum, lambdas: &SampledWavelengths| {
        let xyz = sensor.record(l, lambdas);
        if !xyz.is_finite() {
            stats.nonfinite += 1;
            if stats.nonfinite_at.len() < 16 {
                stats.nonfinite_at.push((x, y, s, stats.last_depth));
            }
            return None;
        }
        Some(xyz)
    };
    // Adds a sample's estimate to its pixel; the sensor's response, or `None` when the estimate
    // is not finite and is dropped.
    let add = |px: &mut Pixel,
               stats: &mut Stats,
               (x, y),
               s,
               l: &SampledSpectrum,
               lambdas: &SampledWavelengths,
               weight: f32| {
        stats.samples += 1;
        let xyz = respond(stats, (x, y), s, l, lambdas)?;
        px.xyz_sum += xyz.as_dvec3() * weight as f64;
        px.weight_sum += weight as f64;
        px.samples += 1;
        Some(xyz)
    };
    let mut sampler = settings.sampler.make(settings.spp, settings.resolution, settings.seed);
    let mut sample_splats = Vec::new();
    for (i, px) in pixels.iter_mut().enumerate() {
        let (x, y) = pixel_at(i);
        let samples = match adaptive.as_deref() {
            Some(a) => a[i].taken..a[i].taken + a[i].planned,
            None => pass.range.clone(),
        };
        for s in samples {
            let (mut lambdas, weight, ray, diff, p_film) = start(&mut sampler, &spectral, (x, y), s);
            let diff = diff.as_ref();
            let mut visible = None;
            let record = aov_pixels.is_some().then_some(&mut visible);
            let l = match (ray, splats.as_deref_mut()) {
                (None, _) => SampledSpectrum::splat(0.0),
                (Some(r), None) => {
                    integrator.li_camera(scene, r.ray, diff, record, &mut lambdas, &mut sampler, &mut stats) * r.weight
                }
                (Some(r), Some(list)) => {
                    let l = integrator.li_splatting(
                        scene,
                        camera,
                        r.ray,
                        diff,
                        record,
                        &mut lambdas,
                        &mut sampler,
                        &mut stats,
                        &mut sample_splats,
                    ) * r.weight;
                    for sp in sample_splats.drain(..) {
                        if let Some(xyz) = respond(&mut stats, (x, y), s, &(sp.l * r.weight), &sp.lambdas) {
                            let strategy = sp.strategy.map(|(s, t)| StrategyImages::index(s, t));
                            list.push((Splat { p_raster: sp.p_raster.unwrap_or(p_film), xyz }, strategy));
                        }
                    }
                    l
                }
            };
            let Some(response) = add(px, &mut stats, (x, y), s, &l, &lambdas, weight) else { continue };
            if let Some(a) = adaptive.as_deref_mut() {
                a[i].add(&to_rgb, response, weight);
            }
            spectral.add(i, &l, &lambdas, weight);
            if let (Some(a), Some(v), Some(aov)) = (aov_pixels.as_deref_mut(), visible, aov.as_ref()) {
                let out_from_world = match aov.coordinates {
                    AovSpace::Camera => camera.transform.camera_from_world(v.time),
                    AovSpace::World => Mat4::IDENTITY,
                };
                a[i].add(&v, &lambdas, aov, &out_from_world, response, weight);
            }
        }
        if let Some(a) = adaptive.as_deref_mut() {
            a[i].taken += a[i].planned;
            a[i].planned = 0;
        }
    }
    stats
}

/// Renders `settings.spp` samples per pixel (or fewer if the time limit ends it), in passes
/// of growing size, calling `progress(samples_done)` after each pass. Fails only when the film
/// cannot be allocated.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    mut progress: impl FnMut(u64),
) -> Result<(Film, Stats), FilmAllocError> {
    let mut film = new_film(settings)?;
    let never = AtomicBool::new(false);
    let stats = render_range(scene, settings, &mut film, 0..settings.spp, &never, |_, done| {
        progress(done);
        true
    });
    Ok((film, stats))
}

/// Adds samples `range` of every pixel to `film`, in passes of 1, 1, 2, 4, … 16 samples (for
/// `sppm`, iterations `range` of [`crate::sppm_render::render_sppm`], which must start at 0). After
/// each pass `after_pass(film, end_of_samples_so_far)` may save a checkpoint or report progress;
/// returning false stops. Stops early, at the end of a pass, once `settings.time_limit` is over,
/// and before the next pass once `cancel` is set (from another thread or a signal handler): the
/// film then holds whole passes, every pixel the same samples.
pub fn render_range(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut Film,
    range: Range<u64>,
    cancel: &AtomicBool,
    after_pass: impl FnMut(&Film, u64) -> bool,
) -> Stats {
    render_range_reporting(scene, settings, film, range, cancel, |_, _| {}, after_pass)
}

/// [`render_range`], telling `bootstrap(paths done, paths)` how far `mlt`'s bootstrap, which
/// comes before its first pass, has got.
pub fn render_range_reporting(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut Film,
    range: Range<u64>,
    cancel: &AtomicBool,
    bootstrap: impl FnMut(u64, u64),
    mut after_pass: impl FnMut(&Film, u64) -> bool,
) -> Stats {
    // Stochastic progressive photon mapping and Metropolis light transport have loops of
    // their own.
    let integrator = settings.integrator.for_scene(scene);
    if integrator.kind == IntegratorKind::Sppm {
        return crate::sppm_render::render_sppm(scene, settings, film, range, cancel, after_pass);
    }
    if integrator.kind == IntegratorKind::Mlt {
        return render_mlt(scene, settings, &integrator, film, range, cancel, bootstrap, after_pass);
    }
    let mut stats = Stats::default();
    let start = Instant::now();
    let mut done = range.start;
    let mut pass = 1u64;
    while done < range.end && !cancel.load(Ordering::Relaxed) {
        let n = pass.min(range.end - done);
        stats.merge(&render_pass(scene, settings, film, done..done + n));
        done += n;
        if !after_pass(film, done) {
            break;
        }
        if settings.time_limit.is_some_and(|t| start.elapsed() >= t) {
            break;
        }
        pass = (pass * 2).min(16);
    }
    warn_cut_off_walks();
    stats
}

/// Metropolis light transport renders the image as a whole rather than in passes of samples:
/// `range.end` mutations per pixel (pbrt-v4's `mutationsperpixel`), reported to `after_pass`
/// as they are done and recorded as every pixel's sample count; `bootstrap` is told the
/// bootstrap's progress. Textures are filtered over the pixel footprint of `range.end`
/// samples per pixel, as pbrt-v4's camera rays in `MLTIntegrator` are scaled for its
/// mutations per pixel. The film must be fresh.
#[allow(clippy::too_many_arguments)]
fn render_mlt(
    scene: &Scene,
    settings: &RenderSettings,
    integrator: &Integrator,
    film: &mut Film,
    range: Range<u64>,
    cancel: &AtomicBool,
    bootstrap: impl FnMut(u64, u64),
    mut after_pass: impl FnMut(&Film, u64) -> bool,
) -> Stats {
    let camera = scene.camera.camera(settings.resolution);
    let integrator = Integrator { footprint: Some(TextureFootprint::new(&camera, range.end)), ..*integrator };
    let mlt = crate::integrator::MltFilm {
        filter: &settings.filter,
        sensor: &settings.film.sensor,
        size: (film.width, film.height),
        origin: settings.film_origin(),
        mutations_per_pixel: range.end,
        seed: settings.seed,
        time_limit: settings.time_limit,
    };
    // (The film seen by `after_pass` holds no splats while the chains run.)
    let Some(mut splats) = film.splats.take() else { return Stats::default() };
    let view: &Film = film;
    let (stats, done) =
        integrator.render_mlt(scene, &camera, &mlt, &mut splats, cancel, bootstrap, |done| after_pass(view, done));
    film.splats = Some(splats);
    for p in &mut film.pixels {
        p.samples = done;
    }
    stats
}

/// Warns once about the free-flight walks through media that were cut off since the last call.
pub(crate) fn warn_cut_off_walks() {
    let cut_off = crate::media::take_cut_off_walks();
    if cut_off > 0 {
        log::warn!(
            "{cut_off} free-flight walks through media were cut off after {} collisions each and taken as \
             absorbed: the image is biased there",
            crate::media::MAX_COLLISIONS
        );
    }
}

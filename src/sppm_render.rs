//! The render loop of stochastic progressive photon mapping (Hachisuka & Jensen 2009; the
//! radius and flux statistics of Hachisuka, Ogaki & Jensen 2008; PBR 3rd ed. §16.2; pbrt-v4
//! `SPPMIntegrator::Render`). Each iteration
//! 1. draws one set of wavelengths for the whole iteration (photons and camera paths must share
//!    them), from a base-3 radical inverse of the iteration's index;
//! 2. traces one camera path per pixel to its visible point
//!    ([`Integrator::sppm_camera_path`]), adding the emission and direct light it gathers to
//!    the pixel's L_d;
//! 3. puts the visible points in a grid ([`VisiblePointGrid`]);
//! 4. traces N photon paths ([`Integrator::sppm_photon_path`]); each photon arriving within a
//!    pixel's radius r of its visible point adds Φ += β_vp f(wo, wi) β_photon and M += 1;
//! 5. updates every pixel that received photons: with α = 2/3,
//!    n' = n + α M, r' = r √(n' / (n + M)), τ' = (τ + Φ) r'² / r².
//!
//! After k iterations a pixel's estimate is L = L_d / k + τ / (k N π r²).
//!
//! Determinism: camera sample s = k of a pixel depends only on (pixel, k, seed) and photon j of
//! iteration k only on (k, j, seeds). Photons are traced in fixed chunks of
//! [`PHOTONS_PER_CHUNK`] in parallel; each chunk lists its deposits in photon order, and the
//! lists are added to the pixels chunk by chunk in index order, so every pixel's sums are the
//! same for any thread count.

use crate::film::{Film, Pixel};
use crate::integrator::camera_sample;
use crate::integrator::sppm_grid::VisiblePointGrid;
use crate::integrator::{Integrator, Stats, VisiblePoint};
use crate::material::Material;
use crate::render_settings::RenderSettings;
use crate::sampling::{radical_inverse, rng::hash64};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::TextureFootprint;
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Photon paths per parallel work item (the unit whose deposits are added in order).
pub const PHOTONS_PER_CHUNK: u64 = 4096;

/// The fraction of a pass's new photons the statistics keep (Hachisuka et al. 2008's α).
const ALPHA: f64 = 2.0 / 3.0;

/// The sampler "pixel" row photon paths draw from (camera samples use the film's pixels).
const PHOTON_ROW: u32 = u32::MAX;

/// What a pixel carries from one iteration to the next.
#[derive(Clone, Debug)]
struct SppmPixel {
    /// Σ of the camera paths' emission and direct light [XYZ].
    ld: DVec3,
    /// Search radius r [scene units].
    radius: f64,
    /// Photons kept by the statistics, n.
    n: f64,
    /// Flux kept by the statistics, τ [XYZ per photon path, before 1/(π r²)].
    tau: DVec3,
    /// This iteration's flux Φ and photon count M.
    phi: DVec3,
    m: u64,
}

/// One deposit: the pixel and the photon's measurement [XYZ].
type Deposit = (u32, Vec3);

/// Runs iterations `range` of SPPM (`settings.integrator.kind` is `Sppm`; its state lives here,
/// so a render must start at iteration 0 and cannot be extended or split). After each iteration
/// the film holds the estimate so far (each pixel's `samples` = iterations done) and
/// `after_pass(film, end_of_iterations_so_far)` may report it; false stops. Stops early, after
/// an iteration, once `settings.time_limit` is over or `cancel` is set.
pub fn render_sppm(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut Film,
    range: Range<u64>,
    cancel: &AtomicBool,
    mut after_pass: impl FnMut(&Film, u64) -> bool,
) -> Stats {
    let camera = scene.camera.camera(settings.resolution);
    let footprint = TextureFootprint::new(&camera, settings.spp);
    let integrator = Integrator { footprint: Some(footprint), ..settings.integrator }.for_scene(scene);
    let differentials = integrator.footprint.as_ref().filter(|_| scene.materials().iter().any(Material::is_textured));
    // pbrt-v4 converts every contribution without the film's per-sample clamp.
    let sensor = settings.film.sensor.with_max_component(f32::INFINITY);
    let width = film.width as usize;
    let origin = settings.film_origin();
    let pixel_at = |i: usize| (origin.0 + (i % width) as u32, origin.1 + (i / width) as u32);
    // The filter's weights f/pdf average ∫f: divided by it, a pixel's mean is its filtered
    // radiance (the band loop divides by the weights' sum instead).
    let filter_integral = settings.filter.integral();
    let photons = integrator.sppm.photons_per_iteration.unwrap_or(film.pixels.len() as u64);
    let photon_seed = hash64(&[settings.seed, integrator.sppm.seed]);
    let mut pixels = vec![
        SppmPixel {
            ld: DVec3::ZERO,
            radius: integrator.sppm.radius as f64,
            n: 0.0,
            tau: DVec3::ZERO,
            phi: DVec3::ZERO,
            m: 0,
        };
        film.pixels.len()
    ];
    let mut visible: Vec<Option<VisiblePoint>> = vec![None; film.pixels.len()];
    let mut stats = Stats::default();
    let start = Instant::now();
    let merge = |mut a: Stats, b: Stats| {
        a.merge(&b);
        a
    };
    for iteration in range.clone() {
        if cancel.load(Ordering::Relaxed) || width == 0 {
            break;
        }
        // 1. The iteration's wavelengths: a base-3 radical inverse (as pbrt-v4), rotated by the
        // seed.
        let u = (radical_inverse(3, iteration as u32) + (hash64(&[settings.seed]) >> 11) as f64 / (1u64 << 53) as f64)
            .fract();
        let lambdas = SampledWavelengths::sample_visible((u as f32).min(1.0 - f32::EPSILON));

        // 2. Camera paths.
        let camera_stats = pixels
            .par_chunks_mut(width)
            .zip(visible.par_chunks_mut(width))
            .enumerate()
            .map(|(row, (pixels, visible))| {
                let mut stats = Stats::default();
                let mut sampler = settings.sampler.make(settings.spp, settings.resolution, settings.seed);
                for (i, (px, vp)) in pixels.iter_mut().zip(visible.iter_mut()).enumerate() {
                    let (x, y) = pixel_at(row * width + i);
                    // One set of wavelengths for the whole iteration (the camera sample's own
                    // wavelength draw is not used).
                    let c = camera_sample(
                        scene,
                        &camera,
                        &settings.filter,
                        differentials,
                        &mut sampler,
                        |_| lambdas,
                        (x, y),
                        iteration,
                        settings.seed,
                    );
                    stats.samples += 1;
                    *vp = None;
                    let Some(r) = c.ray else { continue };
                    let mut w = lambdas;
                    let (l, v) = integrator.sppm_camera_path(
                        scene,
                        r.ray,
                        SampledSpectrum::splat(r.weight * c.filter_weight / filter_integral),
                        c.differentials.as_ref(),
                        &mut w,
                        &mut sampler,
                        &mut stats,
                    );
                    let xyz = sensor.record(&l, &w);
                    if xyz.is_finite() {
                        px.ld += xyz.as_dvec3();
                    } else {
                        stats.nonfinite += 1;
                    }
                    *vp = v.filter(|v| !v.beta.is_black());
                }
                stats
            })
            .reduce(Stats::default, merge);
        stats.merge(&camera_stats);

        // 3. The grid of visible points.
        let points: Vec<(u32, Vec3, f32)> = visible
            .iter()
            .zip(&pixels)
            .enumerate()
            .filter_map(|(i, (v, px))| v.as_ref().map(|v| (i as u32, v.p, px.radius as f32)))
            .collect();
        let grid = VisiblePointGrid::new(&points);

        // 4. Photon paths, in chunks whose deposits are added in chunk order.
        let chunks = photons.div_ceil(PHOTONS_PER_CHUNK);
        let group = 4 * rayon::current_num_threads() as u64;
        for first in (0..chunks).step_by(group as usize) {
            let done: Vec<(Stats, Vec<Deposit>)> = (first..(first + group).min(chunks))
                .into_par_iter()
                .map(|chunk| {
                    let (mut stats, mut deposits) = (Stats::default(), Vec::new());
                    let mut sampler = settings.sampler.make(settings.spp, settings.resolution, settings.seed);
                    let end = ((chunk + 1) * PHOTONS_PER_CHUNK).min(photons);
                    for j in chunk * PHOTONS_PER_CHUNK..end {
                        sampler.start_pixel_sample((iteration as u32, PHOTON_ROW), j, photon_seed);
                        let deposit = |p: Vec3, wi: Vec3, beta: &_, w: &SampledWavelengths| {
                            for &i in grid.candidates(p) {
                                let r = pixels[i as usize].radius as f32;
                                let Some(vp) = visible[i as usize].as_ref() else { continue };
                                if vp.p.distance_squared(p) > r * r {
                                    continue;
                                }
                                let (l, w) = vp.photon(wi, beta, w);
                                let xyz = sensor.record(&l, &w);
                                if xyz.is_finite() {
                                    deposits.push((i, xyz));
                                }
                            }
                        };
                        integrator.sppm_photon_path(scene, lambdas, &mut sampler, &mut stats, deposit);
                    }
                    (stats, deposits)
                })
                .collect();
            for (chunk_stats, deposits) in done {
                stats.merge(&chunk_stats);
                for (i, xyz) in deposits {
                    let px = &mut pixels[i as usize];
                    px.phi += xyz.as_dvec3();
                    px.m += 1;
                }
            }
        }

        // 5. The statistics, and the estimate so far.
        let k = (iteration + 1 - range.start) as f64;
        let emitted = k * photons as f64;
        pixels.par_iter_mut().zip(film.pixels.par_iter_mut()).for_each(|(px, out)| {
            if px.m > 0 {
                let m = px.m as f64;
                let n = px.n + ALPHA * m;
                let radius = px.radius * (n / (px.n + m)).sqrt();
                px.tau = (px.tau + px.phi) * (radius * radius) / (px.radius * px.radius);
                (px.n, px.radius, px.phi, px.m) = (n, radius, DVec3::ZERO, 0);
            }
            let l = px.ld / k + px.tau / (emitted * PI * px.radius * px.radius);
            *out = Pixel { xyz_sum: l, weight_sum: 1.0, samples: k as u64 };
        });
        if !after_pass(film, iteration + 1) || settings.time_limit.is_some_and(|t| start.elapsed() >= t) {
            break;
        }
    }
    stats
}

//! Metropolis light transport in primary sample space (Kelemen et al. 2002; Veach & Guibas
//! 1997; PBR 3rd ed. §16.4; pbrt-v4 `MLTIntegrator`): a path is the point u ∈ [0, 1)^∞ of the
//! random numbers that made it ([`crate::sampling::PssSampler`]), made as one bidirectional
//! strategy (s, t) of its depth chosen uniformly from u, its contribution L(u) taken times the
//! depth + 2 strategies (so that E[L] over u is the image). Markov chains over u, with the
//! luminance I(u) = Y(L(u)) as target, visit paths in proportion to their brightness; every
//! proposal u′ from state u splats a·L(u′)/I(u′) at its film position and (1 − a)·L(u)/I(u) at
//! the state's (expected values, Veach 1997 §11.5), a = min(1, I(u′)/I(u)). With b = ∫ I du
//! estimated from bootstrap paths and N mutations over a film of A pixels of positions, the
//! image is (b·A/N) times the splats, which is pbrt-v4's b / mutationsperpixel.
//!
//! Chains are seeded by their index and run in parallel; their splats are added chain by chain
//! in index order, so the image is the same for any thread count.

use super::interface::Integrator;
use super::Stats;
use crate::camera::Camera;
use crate::film::{Splat, SplatBuffer};
use crate::filter::Filter;
use crate::material::Material;
use crate::sampling::rng::hash64;
use crate::sampling::{AliasTable, PssStream, Rng, Sampler};
use crate::scene::Scene;
use crate::sensor::Sensor;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::TextureFootprint;
use glam::Vec2;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Chains run between two progress reports (and checks of the time limit and cancellation).
const CHAIN_BATCH: u64 = 16;
/// Bootstrap paths per parallel work item.
const BOOTSTRAP_CHUNK: u64 = 1024;
/// Work items of bootstrap paths between two progress reports, per worker thread.
const BOOTSTRAP_CHUNKS_PER_THREAD: u64 = 8;
/// PCG stream of the chains' own decisions (start state, acceptance).
const CHAIN_STREAM: u64 = 0x6d6c74;
/// Depth limit of the strategies: a bootstrap set per depth must stay finite.
const MAX_MLT_DEPTH: u32 = 100;

/// The film a Metropolis render splats onto and the render settings it needs.
pub struct MltFilm<'a> {
    /// The pixel filter that spreads each splat.
    pub filter: &'a Filter,
    /// The sensor's response to a path's radiance.
    pub sensor: &'a Sensor,
    /// The film's size [pixels] and the full-image pixel of its (0, 0).
    pub size: (u32, u32),
    pub origin: (u32, u32),
    /// pbrt-v4's `mutationsperpixel`.
    pub mutations_per_pixel: u64,
    /// Seed of all random decisions.
    pub seed: u64,
    /// Stop after the batch of chains during which this much time has passed.
    pub time_limit: Option<Duration>,
}

impl MltFilm<'_> {
    /// The film positions paths are drawn from [full-image pixels]: the film widened by the
    /// filter's radius, so every pixel receives light from its filter's whole support. Its
    /// corner and size.
    fn sample_bounds(&self) -> (Vec2, Vec2) {
        let r = self.filter.radius();
        let corner = Vec2::new(self.origin.0 as f32, self.origin.1 as f32) - r;
        (corner, Vec2::new(self.size.0 as f32, self.size.1 as f32) + 2.0 * r)
    }
}

/// One path of primary sample space.
#[derive(Clone, Copy, Debug)]
struct PathSample {
    /// Where it lands [full-image pixels].
    p_raster: Vec2,
    /// Its contribution, times the number of strategies of its depth.
    l: SampledSpectrum,
    lambdas: SampledWavelengths,
    /// The target I = Y(L) (0 when L is not finite).
    i: f32,
}

/// One Markov chain of `mutations` proposals from the sampler's current state `current`
/// (pbrt-v4's loop): `path` makes the path of the sampler's state and returns it with its
/// target I ≥ 0; `splat(path, w)` receives the expected-value weights w = a/I and (1 − a)/I
/// (never 0), and `rng` decides acceptance.
fn run_chain<P: Copy>(
    sampler: &mut Sampler,
    rng: &mut Rng,
    mutations: u64,
    mut current: (P, f32),
    mut path: impl FnMut(&mut Sampler) -> (P, f32),
    mut splat: impl FnMut(&P, f32),
) {
    for _ in 0..mutations {
        pss(sampler).start_iteration();
        let proposed = path(sampler);
        let accept = if current.1 > 0.0 { (proposed.1 / current.1).min(1.0) } else { 1.0 };
        if accept > 0.0 {
            splat(&proposed.0, accept / proposed.1);
        }
        if accept < 1.0 {
            splat(&current.0, (1.0 - accept) / current.1);
        }
        if rng.uniform() < accept {
            current = proposed;
            pss(sampler).accept();
        } else {
            pss(sampler).reject();
        }
    }
}

/// The chain's primary-sample-space sampler.
fn pss(sampler: &mut Sampler) -> &mut crate::sampling::PssSampler {
    sampler.as_pss_mut().expect("a Metropolis chain runs on a primary-sample-space sampler")
}

impl Integrator {
    /// The path of the sampler's state for paths of `depth` bounces (pbrt-v4
    /// `MLTIntegrator::L`): from the camera stream the strategy, wavelengths, film position in
    /// `bounds` (corner, size), time and lens; then bdpt's strategy (s, t), its camera ray
    /// carrying differentials when `differentials` is given (as pbrt-v4's, scaled by
    /// max(1/8, 1/√(mutations per pixel)), the footprint's own scale).
    #[allow(clippy::too_many_arguments)]
    fn mlt_path(
        &self,
        scene: &Scene,
        camera: &Camera,
        differentials: Option<&TextureFootprint>,
        bounds: (Vec2, Vec2),
        depth: u32,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> PathSample {
        sampler.start_stream(PssStream::Camera);
        let (s, t, strategies) = if depth == 0 {
            (0, 2, 1)
        } else {
            let n = depth as usize + 2;
            let s = ((sampler.get_1d() * n as f32) as usize).min(n - 1);
            (s, n - s, n)
        };
        let mut lambdas = SampledWavelengths::sample_visible(sampler.get_1d());
        let p_film = bounds.0 + sampler.get_2d() * bounds.1;
        let u_time = sampler.get_1d();
        let time = scene.shutter.map_or(0.0, |(open, close)| open + (close - open) * u_time);
        let u_lens = sampler.get_2d();
        let dark = PathSample { p_raster: p_film, l: SampledSpectrum::zero(), lambdas, i: 0.0 };
        let Some(ray) = camera.sample_ray(p_film, u_lens, time).filter(|r| r.weight > 0.0) else { return dark };
        let ray_differentials =
            differentials.and_then(|f| f.camera_ray_differentials(camera, &ray.ray, p_film, u_lens));
        let Some((l, p)) = self.bdpt_strategy(
            scene,
            camera,
            ray.ray,
            ray_differentials.as_ref(),
            (s, t),
            &mut lambdas,
            sampler,
            stats,
        ) else {
            return dark;
        };
        let l = l * (ray.weight * strategies as f32);
        let i = l.y(&lambdas);
        if !(i.is_finite() && i > 0.0) {
            return PathSample { lambdas, ..dark };
        }
        PathSample { p_raster: p.unwrap_or(p_film), l, lambdas, i }
    }

    /// Renders the image by Metropolis light transport into `splats` (a fresh buffer of the
    /// film `film` describes): bootstrap, calling `bootstrap_progress(paths done, paths)` as
    /// its paths are made, then the chains in batches of [`CHAIN_BATCH`], calling
    /// `progress(mutations per pixel done)` after each batch (false stops). Stops early, after
    /// whole chains, once the time limit is over or `cancel` is set; the buffer is normalised
    /// for the chains that ran. Returns the counters and the mutations per pixel done. Camera
    /// rays carry differentials when the integrator has a pixel footprint and a material is
    /// textured.
    #[allow(clippy::too_many_arguments)]
    pub fn render_mlt(
        &self,
        scene: &Scene,
        camera: &Camera,
        film: &MltFilm,
        splats: &mut SplatBuffer,
        cancel: &AtomicBool,
        mut bootstrap_progress: impl FnMut(u64, u64),
        mut progress: impl FnMut(u64) -> bool,
    ) -> (Stats, u64) {
        let start = Instant::now();
        let depths = self.max_depth.min(MAX_MLT_DEPTH) as u64 + 1;
        let bounds = film.sample_bounds();
        let (seed, sigma, large) = (film.seed, self.mlt.sigma, self.mlt.large_step_probability);
        let differentials = self.footprint.as_ref().filter(|_| scene.materials().iter().any(Material::is_textured));
        let path = |index: u64, sampler: &mut Sampler, stats: &mut Stats| {
            self.mlt_path(scene, camera, differentials, bounds, (index % depths) as u32, sampler, stats)
        };

        // Bootstrap: path k of depth k mod depths from sampler (seed, k); b = ∫ I du over all
        // depths is (depths) times the mean of I. Made in batches of work items, in order, with
        // a progress report after each.
        let n = self.mlt.bootstrap_samples as u64 * depths;
        let chunks = n.div_ceil(BOOTSTRAP_CHUNK);
        let batch = BOOTSTRAP_CHUNKS_PER_THREAD * rayon::current_num_threads() as u64;
        let mut stats = Stats::default();
        let mut weights = Vec::with_capacity(n as usize);
        bootstrap_progress(0, n);
        for first in (0..chunks).step_by(batch as usize) {
            if cancel.load(Ordering::Relaxed) {
                return (stats, 0);
            }
            let made: Vec<(Vec<f32>, Stats)> = (first..(first + batch).min(chunks))
                .into_par_iter()
                .map(|c| {
                    let mut stats = Stats::default();
                    let weights = (c * BOOTSTRAP_CHUNK..((c + 1) * BOOTSTRAP_CHUNK).min(n))
                        .map(|k| path(k, &mut Sampler::pss(seed, k, sigma, large), &mut stats).i)
                        .collect();
                    (weights, stats)
                })
                .collect();
            for (w, s) in made {
                weights.extend(w);
                stats.merge(&s);
            }
            bootstrap_progress(weights.len() as u64, n);
        }
        if cancel.load(Ordering::Relaxed) {
            return (stats, 0);
        }
        let sum: f64 = weights.iter().map(|&w| w as f64).sum();
        if sum == 0.0 {
            log::warn!("mlt: none of the {n} bootstrap paths carries light: the image is black");
            return (stats, film.mutations_per_pixel);
        }
        let b = depths as f64 * sum / n as f64;
        let table = AliasTable::new(&weights);
        drop(weights);

        // The chains.
        let area = bounds.1.x as f64 * bounds.1.y as f64;
        let total = (area * film.mutations_per_pixel as f64).round() as u64;
        let chains = self.mlt.chains.max(1) as u64;
        let share = |i: u64| ((i as u128 * total as u128) / chains as u128) as u64;
        let (width, height) = film.size;
        let mut done = 0u64;
        let mut batch = 0;
        while batch < chains && !cancel.load(Ordering::Relaxed) {
            let ran: Vec<(Vec<Splat>, Stats, u64)> = (batch..(batch + CHAIN_BATCH).min(chains))
                .into_par_iter()
                .map(|i| {
                    let mut stats = Stats::default();
                    let mutations = share(i + 1) - share(i);
                    let mut rng = Rng::new(hash64(&[seed, i]), CHAIN_STREAM);
                    let (index, _) = table.sample(rng.uniform());
                    let index = index as u64;
                    let mut sampler = Sampler::pss(seed, index, sigma, large);
                    let first = path(index, &mut sampler, &mut stats);
                    let mut list = Vec::with_capacity(2 * mutations as usize);
                    let mut splat_stats = Stats::default();
                    run_chain(
                        &mut sampler,
                        &mut rng,
                        mutations,
                        (first, first.i),
                        |sampler| {
                            let p = path(index, sampler, &mut stats);
                            (p, p.i)
                        },
                        |p, w| {
                            let xyz = film.sensor.record(&(p.l * w), &p.lambdas);
                            if xyz.is_finite() {
                                list.push(Splat { p_raster: p.p_raster, xyz });
                            } else {
                                splat_stats.nonfinite += 1;
                            }
                        },
                    );
                    stats.merge(&splat_stats);
                    stats.samples += mutations;
                    (list, stats, mutations)
                })
                .collect();
            for (list, s, mutations) in ran {
                for sp in &list {
                    splats.add(sp, film.filter, width, height, film.origin);
                }
                stats.merge(&s);
                done += mutations;
            }
            batch = (batch + CHAIN_BATCH).min(chains);
            let per_pixel = (done as f64 / area) as u64;
            if !progress(per_pixel) || film.time_limit.is_some_and(|t| start.elapsed() >= t) {
                break;
            }
        }
        // Each mutation splatted unit luminance: the image is b·A/N times the sums, and the
        // buffer scales them by M/N (M the full image's pixels).
        let scale = b * area / splats.full_pixels as f64;
        for v in &mut splats.xyz_sum {
            *v *= scale;
        }
        splats.paths = done;
        (stats, if done == total { film.mutations_per_pixel } else { (done as f64 / area) as u64 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1-D target f(u) = u² + 0.1 on the first primary sample: the chains' expected-value
    /// splats, scaled by b/N with the exact b = ∫f = 13/30, must give ∫f over each of 10 bins
    /// (computed in closed form). Per-chain histograms give the standard error (independent
    /// chains); every bin within 4σ.
    #[test]
    fn chains_splat_the_target_in_proportion_to_its_integral_over_each_bin() {
        let f = |u: f64| u * u + 0.1;
        let b = 1.0 / 3.0 + 0.1;
        let bins = 10usize;
        let (chains, mutations) = (200u64, 5000u64);
        let mut per_chain = vec![vec![0.0f64; bins]; chains as usize];
        for (c, hist) in per_chain.iter_mut().enumerate() {
            let mut sampler = Sampler::pss(5, c as u64, 0.05, 0.3);
            let mut rng = Rng::new(hash64(&[5, c as u64]), CHAIN_STREAM);
            let eval = |s: &mut Sampler| {
                s.start_stream(PssStream::Camera);
                let u = s.get_1d() as f64;
                (u, f(u) as f32)
            };
            let first = eval(&mut sampler);
            run_chain(&mut sampler, &mut rng, mutations, first, eval, |&u, w| {
                hist[(u * bins as f64) as usize] += w as f64 * f(u) * b / mutations as f64;
            });
        }
        for (j, lo) in (0..bins).map(|j| (j, j as f64 / bins as f64)) {
            let hi = lo + 1.0 / bins as f64;
            let exact = (hi.powi(3) - lo.powi(3)) / 3.0 + 0.1 * (hi - lo);
            let v: Vec<f64> = per_chain.iter().map(|h| h[j]).collect();
            let mean = v.iter().sum::<f64>() / chains as f64;
            let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (chains - 1) as f64;
            let se = (var / chains as f64).sqrt();
            assert!((mean - exact).abs() < 4.0 * se, "bin {j}: {mean} ± {se} vs {exact}");
        }
    }
}

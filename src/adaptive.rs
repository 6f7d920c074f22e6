//! Adaptive sampling to a target error (`prism render --target-error E`): render until the
//! image's estimated error is at most E, giving the next samples to the pixels whose variance
//! is highest.
//!
//! The error is the one prism's comparisons use ([`crate::image::metrics::compressed_rgb_rmse`]):
//! the RMSE over pixels and channels of x/(1+x)-mapped RGB. Its expected square, against the
//! converged image, is estimated as (1/3P) Σₚ vₚ/nₚ, where vₚ is the variance one sample adds
//! to pixel p's mapped RGB ([`AdaptivePixel::compressed_variance`]) and nₚ its sample count.
//! For a fixed budget the allocation minimising that sum is nₚ ∝ √vₚ (the Lagrange condition of
//! Σ vₚ/nₚ under Σ nₚ = N; e.g. Rousselle, Knaus & Zwicker 2011, §4); √vₚ is taken from the
//! mean of v over the pixel's 3 × 3 neighbourhood, so a pixel whose few samples happened to
//! agree is not starved, and a pixel's count depends less on its own samples.
//!
//! Every pixel first takes the uniform passes 1, 1, 2, 4, 8 (to [`BASE_SPP`] samples, or the
//! maximum when that is lower), stopping as soon as the estimate is met. Then each pass plans
//! the counts the rule asks for to reach E and adds them, at most doubling a pixel's count per
//! pass (its variance estimate is refined before it gets more) and never beyond the maximum
//! (`settings.spp`). A pixel always holds sample indices 0..n of its own stream, so it equals
//! the uniform render's first n samples there; the plan is computed serially from the film,
//! so the image is the same for any thread count.

use crate::film::{AdaptivePixel, Film};
use crate::integrator::Stats;
use crate::render::{render_pass_of, warn_cut_off_walks, PassSamples, RenderSettings};
use crate::scene::Scene;
use crate::spectrum::ColorSpace;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Samples every pixel takes before any is given more than the others.
pub const BASE_SPP: u64 = 16;

/// The result of an adaptive render besides its film.
#[derive(Clone, Debug)]
pub struct AdaptiveRender {
    /// Per film pixel (row-major): its sample count and statistics.
    pub pixels: Vec<AdaptivePixel>,
    /// The estimated error when it stopped: RMSE of x/(1+x)-mapped RGB against the converged
    /// image (+∞ before every pixel has two samples).
    pub estimated_error: f64,
    /// Counters of the integrator.
    pub stats: Stats,
}

impl AdaptiveRender {
    /// Mean samples per pixel taken.
    pub fn mean_spp(&self) -> f64 {
        self.pixels.iter().map(|p| p.taken as f64).sum::<f64>() / self.pixels.len().max(1) as f64
    }
}

/// The variance one sample adds to each pixel's mapped RGB ([`AdaptivePixel::compressed_variance`];
/// 0 for a pixel with fewer than two finite samples), and the estimated error of the image.
pub fn estimate(film: &Film, pixels: &[AdaptivePixel], space: &ColorSpace) -> (Vec<f64>, f64) {
    let mut sum = 0.0;
    let mut unknown = false;
    let v: Vec<f64> = film
        .pixels
        .iter()
        .zip(pixels)
        .enumerate()
        .map(|(i, (px, a))| {
            let (x, y) = (i as u32 % film.width, i as u32 / film.width);
            let v = a.compressed_variance(px, space.xyz_to_rgb(film.xyz(x, y)));
            // A pixel with two samples taken whose samples were not finite has no estimate; it
            // is black in the image, and counted as noiseless.
            unknown |= v.is_none() && a.taken < 2;
            let v = v.unwrap_or(0.0);
            sum += v / a.moments.n.max(1) as f64;
            v
        })
        .collect();
    let n = 3.0 * film.pixels.len().max(1) as f64;
    (v, if unknown { f64::INFINITY } else { (sum / n).sqrt() })
}

/// Plans the next pass: the samples each pixel adds (into `planned`) so that the estimated error
/// reaches `target` under the rule nₚ ∝ √v̄ₚ, at most doubling a pixel's count and never beyond
/// `max_spp`. Returns the samples planned in all.
fn plan(pixels: &mut [AdaptivePixel], v: &[f64], width: usize, target: f64, max_spp: u64) -> u64 {
    let height = pixels.len() / width.max(1);
    // v̄: the mean of v over the pixel's 3 × 3 neighbourhood (clipped at the film's edges).
    let smooth: Vec<f64> = (0..pixels.len())
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let (mut s, mut k) = (0.0, 0.0);
            for yy in y.saturating_sub(1)..(y + 2).min(height) {
                for xx in x.saturating_sub(1)..(x + 2).min(width) {
                    s += v[yy * width + xx];
                    k += 1.0;
                }
            }
            s / k
        })
        .collect();
    // With nₚ = λ√v̄ₚ the estimated squared error is Σ vₚ/(λ√v̄ₚ) / 3P; λ makes it target².
    let sum: f64 = v.iter().zip(&smooth).filter(|(_, s)| **s > 0.0).map(|(v, s)| v / s.sqrt()).sum();
    let lambda = sum / (3.0 * pixels.len() as f64 * target * target);
    let mut total = 0;
    for (a, s) in pixels.iter_mut().zip(&smooth) {
        let wanted = (lambda * s.sqrt()).ceil();
        let wanted = if wanted.is_finite() { wanted.min(max_spp as f64) as u64 } else { max_spp };
        a.planned = wanted.saturating_sub(a.taken).min(a.taken.max(1)).min(max_spp - a.taken);
        total += a.planned;
    }
    total
}

/// Adds samples to the empty `film` until the estimated error is at
/// most `target` (RMSE of x/(1+x)-mapped RGB in `space`), every pixel has `settings.spp` samples,
/// `settings.time_limit` is over at the end of a pass, `cancel` is set before a pass, or
/// `after_pass(film, pixels, estimated_error)` returns false.
pub fn render_to_error(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut Film,
    space: &ColorSpace,
    target: f64,
    cancel: &AtomicBool,
    mut after_pass: impl FnMut(&Film, &[AdaptivePixel], f64) -> bool,
) -> AdaptiveRender {
    let start = Instant::now();
    let to_rgb = space.xyz_to_rgb_matrix;
    let max_spp = settings.spp;
    let base = BASE_SPP.min(max_spp);
    let mut pixels = vec![AdaptivePixel::default(); film.pixels.len()];
    let mut stats = Stats::default();
    let (mut v, mut error) = (Vec::new(), f64::INFINITY);
    let mut pass = 1u64;
    while !cancel.load(Ordering::Relaxed) && error > target {
        let done = pixels.first().map_or(max_spp, |p| p.taken);
        let planned = if done < base || v.is_empty() {
            let n = pass.min(base.saturating_sub(done));
            pixels.iter_mut().for_each(|p| p.planned = n);
            pass *= 2;
            n
        } else {
            plan(&mut pixels, &v, film.width as usize, target, max_spp)
        };
        if planned == 0 {
            break; // every pixel that could lower the error has its maximum
        }
        stats.merge(&render_pass_of(scene, settings, film, PassSamples::PerPixel { pixels: &mut pixels, to_rgb }));
        (v, error) = estimate(film, &pixels, space);
        if !after_pass(film, &pixels, error) || settings.time_limit.is_some_and(|t| start.elapsed() >= t) {
            break;
        }
    }
    warn_cut_off_walks();
    AdaptiveRender { pixels, estimated_error: error, stats }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plan_gives_samples_in_proportion_to_the_standard_deviation() {
        // Two flat regions, v = 1 and v = 16 (σ 1 and 4), each pixel with 100 samples. Away
        // from the boundary the smoothed v is the pixel's own, so pixel counts go as λ·σ, with
        // λ = Σ v/√v̄ / (3P E²); E is chosen for λ = 150.5.
        let (w, h) = (8usize, 4usize);
        let v: Vec<f64> = (0..w * h).map(|i| if i % w < w / 2 { 1.0 } else { 16.0 }).collect();
        // Σ v/√v̄ by hand: v̄ is the row's 3-neighbourhood mean (rows are alike); only columns
        // 3 and 4 see both regions: v̄ = (1 + 1 + 16)/3 = 6 and (1 + 16 + 16)/3 = 11.
        let row = 3.0 * 1.0 + 1.0 / 6f64.sqrt() + 16.0 / 11f64.sqrt() + 3.0 * 4.0;
        let lambda = 150.5;
        let target = (row * h as f64 / (3.0 * (w * h) as f64 * lambda)).sqrt();
        let mut pixels = vec![AdaptivePixel { taken: 100, ..Default::default() }; w * h];
        plan(&mut pixels, &v, w, target, 1 << 20);
        assert_eq!(pixels[w + 1].planned, 51, "ceil(λ·1) − 100");
        assert_eq!(pixels[w + w - 1].planned, 100, "ceil(λ·4) − 100 = 502, at most doubling");
        // Never beyond the maximum.
        let mut capped = vec![AdaptivePixel { taken: 16, ..Default::default() }; w * h];
        plan(&mut capped, &v, w, 1e-6, 20);
        assert!(capped.iter().all(|p| p.planned == 4));
        // Noiseless pixels get nothing.
        let mut flat = vec![AdaptivePixel { taken: 16, ..Default::default() }; w * h];
        assert_eq!(plan(&mut flat, &vec![0.0; w * h], w, 0.01, 64), 0);
    }
}

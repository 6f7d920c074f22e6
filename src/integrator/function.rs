//! pbrt-v4's `function` integrator: not a renderer but a test of the samplers. Each film pixel
//! estimates the integral over [0, 1]² of a fixed function f — one of [`TestFunction`], each
//! with ∫f = 1 — from its pixel samples, I_n = (1/n) Σ_{i<n} f(u_i), and for each sample count n
//! the mean squared error over the pixels, MSE(n) = (1/P) Σ_p (I_n(p) − 1)², is recorded. For
//! independent samples MSE(n) = Var f / n; a stratified or low-discrepancy sampler should fall
//! faster at the counts its patterns are made for.

use crate::image::Image;
use crate::sampling::{Rng, Sampler, SamplerKind, TestFunction};
use rayon::prelude::*;

/// The sampler `function` cannot test.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FunctionTestError {
    /// pbrt-v4's global Sobol' sampler gives a pixel the points of one image-wide sequence that
    /// fall in it, so its pixel samples are no pattern of their own (pbrt-v4 refuses it too).
    #[error("integrator \"function\" tests a sampler's own per-pixel patterns: sampler \"sobol\" (pbrt-v4's global Sobol', prism's globalsobol) has none; use \"paddedsobol\"")]
    GlobalSobol,
}

/// What `function` measures: the function, the sampler and the pixels.
#[derive(Clone, Copy, Debug)]
pub struct FunctionTest {
    /// The integrand.
    pub function: TestFunction,
    /// The sampler, made as for a render of `spp` samples per pixel at `resolution`.
    pub sampler: SamplerKind,
    /// The largest sample count.
    pub spp: u64,
    /// The full image's size [pixels].
    pub resolution: (u32, u32),
    /// The pixels estimating: x0..x1 × y0..y1 of the full image.
    pub pixels: ((u32, u32), (u32, u32)),
    /// The render's seed.
    pub seed: u64,
    /// pbrt-v4's `skipbad` (default true): report only the counts the sampler's patterns are
    /// made for ([`Self::counts`]).
    pub skip_bad: bool,
}

/// The error curve `function` measures.
#[derive(Clone, Debug, PartialEq)]
pub struct MseCurve {
    /// (n, MSE(n)) for each reported sample count n, increasing.
    pub points: Vec<(u64, f64)>,
    /// The estimate at the largest reported count, averaged over the pixels (≈ 1).
    pub mean_estimate: f64,
}

impl MseCurve {
    /// pbrt-v4's file: a line "n mse" per reported count (the MSE to full f64 precision, where
    /// pbrt-v4 prints six decimals).
    pub fn text(&self) -> String {
        self.points.iter().map(|(n, mse)| format!("{n} {mse}\n")).collect()
    }

    /// Whether the mean estimate is far enough from 1 (outside 0.999–1.001, pbrt-v4's bounds)
    /// to suspect the sampler or the estimator.
    pub fn suspicious(&self) -> bool {
        !(0.999..=1.001).contains(&self.mean_estimate)
    }
}

impl FunctionTest {
    /// Whether `n` samples are a size the sampler's patterns are made for: a square for the
    /// stratified sampler, a power of two for the padded Sobol' samplers (pbrt-v4's
    /// `paddedsobol`, prism's `sobol`), 2^k·3^k for Halton (its first two dimensions stratify
    /// 2^k × 3^k grids); every count for the others (as pbrt-v4).
    pub fn natural_count(sampler: SamplerKind, n: u64) -> bool {
        match sampler {
            SamplerKind::Stratified { .. } => n.isqrt().pow(2) == n,
            SamplerKind::PaddedSobol(_) | SamplerKind::Sobol => n.is_power_of_two(),
            SamplerKind::Halton(_) => {
                let twos = n.trailing_zeros();
                let mut m = n >> twos;
                let mut threes = 0;
                while m > 1 && m.is_multiple_of(3) {
                    (m, threes) = (m / 3, threes + 1);
                }
                m == 1 && twos == threes
            }
            _ => true,
        }
    }

    /// The sample counts reported: 1 ..= spp, only the natural ones with `skip_bad`.
    pub fn counts(&self) -> Vec<u64> {
        (1..=self.spp).filter(|&n| !self.skip_bad || Self::natural_count(self.sampler, n)).collect()
    }

    /// Whether the pattern of n samples is the first n of the pattern of more. Not for the
    /// samplers that give each draw the strata (stratified) or Sobol' points (padded Sobol') of
    /// all the render's samples in a random order: their first n of more are a random subset,
    /// so the n-sample estimate takes the sampler made for n samples, as pbrt-v4 draws a fresh
    /// stratified grid per count.
    fn nested(&self) -> bool {
        !matches!(self.sampler, SamplerKind::Stratified { .. } | SamplerKind::PaddedSobol(_))
    }

    /// The sampler for renders of `spp` samples per pixel.
    fn sampler(&self, spp: u64) -> Sampler {
        self.sampler.make(spp, self.resolution, self.seed)
    }

    /// f at sample `index` of `pixel`: the sample's film position in the pixel, drawn first.
    fn sample(&self, sampler: &mut Sampler, pixel: (u32, u32), index: u64) -> f64 {
        sampler.start_pixel_sample(pixel, index, self.seed);
        let u = sampler.get_pixel_2d();
        self.function.eval(f64::from(u.x), f64::from(u.y))
    }

    /// Measures the curve: every pixel's estimate at every reported count (in parallel over
    /// rows, summed in row order: the same result for any thread count).
    pub fn run(&self) -> Result<MseCurve, FunctionTestError> {
        if matches!(self.sampler, SamplerKind::GlobalSobol(_)) {
            return Err(FunctionTestError::GlobalSobol);
        }
        let counts = self.counts();
        let ((x0, x1), (y0, y1)) = self.pixels;
        let (mut squared, mut last) = (vec![0.0; counts.len()], 0.0);
        // Rows a batch at a time, so that the rows' sums held at once stay few.
        let rows: Vec<u32> = (y0..y1).collect();
        for batch in rows.chunks(64) {
            let sums: Vec<(Vec<f64>, f64)> = batch.par_iter().map(|&y| self.row(y, &counts)).collect();
            for (row, row_last) in sums {
                for (s, r) in squared.iter_mut().zip(row) {
                    *s += r;
                }
                last += row_last;
            }
        }
        let pixels = f64::from(x1 - x0) * f64::from(y1 - y0);
        Ok(MseCurve {
            points: counts.iter().zip(squared).map(|(&n, s)| (n, s / pixels)).collect(),
            mean_estimate: last / pixels,
        })
    }

    /// Row `y`'s Σ_p (I_n − 1)² for each of the `counts`, and its Σ_p I_n at the last.
    fn row(&self, y: u32, counts: &[u64]) -> (Vec<f64>, f64) {
        let ((x0, x1), _) = self.pixels;
        let (mut squared, mut last) = (vec![0.0; counts.len()], 0.0);
        let largest = counts[counts.len() - 1];
        if self.nested() {
            let mut sampler = self.sampler(self.spp);
            for x in x0..x1 {
                let (mut sum, mut k) = (0.0, 0);
                for n in 1..=largest {
                    sum += self.sample(&mut sampler, (x, y), n - 1);
                    if n == counts[k] {
                        squared[k] += (sum / n as f64 - 1.0).powi(2);
                        k += 1;
                    }
                }
                last += sum / largest as f64;
            }
        } else {
            for (k, &n) in counts.iter().enumerate() {
                let mut sampler = self.sampler(n);
                for x in x0..x1 {
                    let estimate = (0..n).map(|i| self.sample(&mut sampler, (x, y), i)).sum::<f64>() / n as f64;
                    squared[k] += (estimate - 1.0).powi(2);
                    if n == largest {
                        last += estimate;
                    }
                }
            }
        }
        (squared, last)
    }
}

/// pbrt-v4's `imagefilename`: the function over a `width` × `height` image of the unit square
/// (row 0 at y = 0), each pixel the mean of 256 jittered samples, one channel.
pub fn function_image(function: TestFunction, width: u32, height: u32) -> Image {
    const SAMPLES: u32 = 256;
    let (w, h) = (f64::from(width), f64::from(height));
    let rows: Vec<Vec<f32>> = (0..height)
        .into_par_iter()
        .map(|y| {
            let mut rng = Rng::new(0, u64::from(y));
            (0..width)
                .map(|x| {
                    let sum: f64 = (0..SAMPLES)
                        .map(|_| {
                            let (u, v) = (f64::from(rng.uniform()), f64::from(rng.uniform()));
                            function.eval((f64::from(x) + u) / w, (f64::from(y) + v) / h)
                        })
                        .sum();
                    (sum / f64::from(SAMPLES)) as f32
                })
                .collect()
        })
        .collect();
    Image { width, height, channels: 1, data: rows.concat() }
}

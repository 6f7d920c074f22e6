//! Primary-sample-space Metropolis sampling (Kelemen et al. 2002, "A simple and robust mutation
//! strategy for the Metropolis light transport algorithm"; PBR 3rd ed. §16.4.2; pbrt-v4
//! `MLTSampler`): a path is a point u ∈ [0, 1)^∞ of the random numbers that made it, drawn
//! lazily. A Markov chain over u proposes either a large step (every coordinate fresh and
//! uniform: an independent sample) or a small step (every coordinate moved by a normal of
//! standard deviation σ and wrapped around [0, 1)); both are symmetric, so the acceptance
//! probability is the ratio of the target's values. Coordinates are brought up to the current
//! iteration only when read: one last changed k small steps ago takes one normal step of
//! σ√k (the sum of k independent ones), and one last changed before the last accepted large step
//! first takes a fresh uniform.
//!
//! The coordinates are split into interleaved streams (camera, light, connection), so that
//! each part of a path reads its own dimensions however many the others used.

use super::rng::{hash64, Rng};
use super::Sampler;

/// The streams a path's parts draw from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PssStream {
    /// The strategy, wavelengths, film position, time, lens and camera subpath.
    Camera = 0,
    /// The light subpath.
    Light = 1,
    /// The connection of the two.
    Connection = 2,
}

/// Number of [`PssStream`]s.
const STREAMS: usize = 3;

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// One coordinate of u, with its state before the current iteration (restored on rejection).
#[derive(Clone, Copy, Debug, Default)]
struct PrimarySample {
    value: f32,
    /// The iteration that last set `value`.
    modified: u64,
    backup_value: f32,
    backup_modified: u64,
}

/// A Markov chain's state in primary sample space and its mutations.
#[derive(Clone, Debug)]
pub struct PssSampler {
    rng: Rng,
    /// Standard deviation of a small step's perturbation of each coordinate.
    sigma: f32,
    large_step_probability: f32,
    x: Vec<PrimarySample>,
    /// The current iteration (the proposal being made).
    iteration: u64,
    large_step: bool,
    /// The iteration of the last accepted large step.
    last_large_step: u64,
    stream: usize,
    /// Next coordinate of the stream.
    index: usize,
}

impl PssSampler {
    /// A chain whose random numbers come from stream `index` of `seed`: two samplers of the
    /// same (seed, index) make the same paths, so a chain can restart from a bootstrap path.
    pub fn new(seed: u64, index: u64, sigma: f32, large_step_probability: f32) -> Self {
        Self {
            rng: Rng::new(hash64(&[seed, index]), index),
            sigma,
            large_step_probability,
            x: Vec::new(),
            iteration: 0,
            // The first path is a large step: every coordinate uniform.
            large_step: true,
            last_large_step: 0,
            stream: 0,
            index: 0,
        }
    }

    /// Starts a proposal: a large step with the large-step probability, else a small one.
    pub fn start_iteration(&mut self) {
        self.iteration += 1;
        self.large_step = self.rng.uniform() < self.large_step_probability;
    }

    /// True when the current proposal is a large step.
    pub fn is_large_step(&self) -> bool {
        self.large_step
    }

    /// Keeps the proposal as the chain's state.
    pub fn accept(&mut self) {
        if self.large_step {
            self.last_large_step = self.iteration;
        }
    }

    /// Returns to the state before the proposal.
    pub fn reject(&mut self) {
        for xi in &mut self.x {
            if xi.modified == self.iteration {
                xi.value = xi.backup_value;
                xi.modified = xi.backup_modified;
            }
        }
        self.iteration -= 1;
    }

    /// Reads the following draws from `stream`, from its first coordinate.
    pub fn start_stream(&mut self, stream: PssStream) {
        self.stream = stream as usize;
        self.index = 0;
    }

    /// The next coordinate of the current stream, in [0, 1).
    pub fn get_1d(&mut self) -> f32 {
        let i = self.stream + STREAMS * self.index;
        self.index += 1;
        self.ensure_ready(i);
        self.x[i].value
    }

    /// Brings coordinate `i` up to the current iteration.
    fn ensure_ready(&mut self, i: usize) {
        if i >= self.x.len() {
            self.x.resize(i + 1, PrimarySample::default());
        }
        let xi = &mut self.x[i];
        // Untouched since the last accepted large step, which replaced every coordinate.
        if xi.modified < self.last_large_step {
            xi.value = self.rng.uniform();
            xi.modified = self.last_large_step;
        }
        xi.backup_value = xi.value;
        xi.backup_modified = xi.modified;
        if self.large_step {
            xi.value = self.rng.uniform();
        } else {
            // The small steps since it was last set, all at once.
            let steps = (self.iteration - xi.modified) as f64;
            let step = standard_normal(self.rng.uniform()) * self.sigma as f64 * steps.sqrt();
            let v = xi.value as f64 + step;
            xi.value = ((v - v.floor()) as f32).min(ONE_MINUS_EPSILON);
        }
        xi.modified = self.iteration;
    }
}

/// The standard normal quantile of `u` ∈ (0, 1): √2 erf⁻¹(2u − 1).
pub fn standard_normal(u: f32) -> f64 {
    std::f64::consts::SQRT_2 * erf_inv(2.0 * u as f64 - 1.0)
}

/// erf⁻¹(x) for x ∈ (−1, 1), by Giles' single-precision polynomials (M. Giles 2010,
/// "Approximating the erfinv function", GPU Computing Gems Jade): relative error below 4e-7;
/// ±1 map to ±3.9 (x = ±1 − 2⁻²⁴, the last uniform, gives 3.8).
fn erf_inv(x: f64) -> f64 {
    let x = x.clamp(-1.0 + 1e-12, 1.0 - 1e-12);
    let mut w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        w -= 2.5;
        [
            3.43273939e-07,
            -3.5233877e-06,
            -4.39150654e-06,
            0.00021858087,
            -0.00125372503,
            -0.00417768164,
            0.246640727,
            1.50140941,
        ]
        .iter()
        .fold(2.81022636e-08, |p, c| c + p * w)
    } else {
        w = w.sqrt() - 3.0;
        [
            0.000100950558,
            0.00134934322,
            -0.00367342844,
            0.00573950773,
            -0.0076224613,
            0.00943887047,
            1.00167406,
            2.83297682,
        ]
        .iter()
        .fold(-0.000200214257, |p, c| c + p * w)
    };
    p * x
}

impl Sampler {
    /// A primary-sample-space sampler ([`PssSampler::new`]).
    pub fn pss(seed: u64, index: u64, sigma: f32, large_step_probability: f32) -> Self {
        Self::Pss(PssSampler::new(seed, index, sigma, large_step_probability))
    }

    /// The primary-sample-space sampler, when this is one.
    pub fn as_pss_mut(&mut self) -> Option<&mut PssSampler> {
        match self {
            Self::Pss(s) => Some(s),
            _ => None,
        }
    }

    /// Reads the following draws from `stream` (a primary-sample-space sampler; the others
    /// draw their dimensions in order and ignore it).
    pub fn start_stream(&mut self, stream: PssStream) {
        if let Some(s) = self.as_pss_mut() {
            s.start_stream(stream);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::chi2_survival;

    /// Pearson's χ² of `counts` against expected `expected` (cells below 5 pooled into one),
    /// and its degrees of freedom.
    fn pearson(counts: &[u64], expected: &[f64]) -> (f64, f64) {
        let (mut stat, mut cells, mut pool_n, mut pool_e) = (0.0, 0usize, 0.0, 0.0);
        for (&n, &e) in counts.iter().zip(expected) {
            if e < 5.0 {
                pool_n += n as f64;
                pool_e += e;
            } else {
                stat += (n as f64 - e).powi(2) / e;
                cells += 1;
            }
        }
        if pool_e > 0.0 {
            stat += (pool_n - pool_e).powi(2) / pool_e;
            cells += 1;
        }
        (stat, cells as f64 - 1.0)
    }

    /// Standard normal CDF by Simpson's rule on its density (independent of `erf_inv`).
    fn normal_cdf(x: f64) -> f64 {
        let (a, n) = (-9.0f64, 4000);
        if x <= a {
            return 0.0;
        }
        let h = (x - a) / n as f64;
        let pdf = |t: f64| (-0.5 * t * t).exp() / (2.0 * std::f64::consts::PI).sqrt();
        let mut s = pdf(a) + pdf(x);
        for i in 1..n {
            s += pdf(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    #[test]
    fn large_steps_are_uniform_and_independent_across_coordinates_and_streams() {
        // 64 × 64 cells of (coordinate 0 of the camera stream, coordinate 2 of the light
        // stream) over 200 000 accepted large steps: uniform on [0, 1)².
        let mut s = PssSampler::new(3, 7, 0.01, 1.0);
        let cells = 64usize;
        let mut counts = vec![0u64; cells * cells];
        let n = 200_000;
        for _ in 0..n {
            s.start_iteration();
            assert!(s.is_large_step());
            s.start_stream(PssStream::Camera);
            let a = s.get_1d();
            s.start_stream(PssStream::Light);
            let _ = (s.get_1d(), s.get_1d());
            let b = s.get_1d();
            counts[(a * cells as f32) as usize * cells + (b * cells as f32) as usize] += 1;
            s.accept();
        }
        let expected = vec![n as f64 / (cells * cells) as f64; cells * cells];
        let (stat, dof) = pearson(&counts, &expected);
        let p = chi2_survival(stat, dof);
        assert!(p > 1e-4, "χ² = {stat} for {dof} dof, p = {p}");
    }

    #[test]
    fn small_steps_move_each_coordinate_by_a_normal_of_sigma_root_k_wrapped() {
        // k accepted small steps move a coordinate read only after the last by one normal of
        // σ√k. The wrapped difference (x − x₀ + ½ mod 1) − ½ is tested against N(0, σ²k) in 40 cells
        // from −4σ√k to 4σ√k (and the two tails).
        for (sigma, k) in [(0.01f32, 1u64), (0.05, 1), (0.02, 9)] {
            let sd = sigma as f64 * (k as f64).sqrt();
            let edges: Vec<f64> = (0..=40).map(|i| -4.0 * sd + i as f64 * 0.2 * sd).collect();
            let mut counts = vec![0u64; 42];
            let n = 100_000;
            let mut s = PssSampler::new(11, k, sigma, 0.0);
            for _ in 0..n {
                // A fresh large step gives x₀; then k small steps, the coordinate read after
                // the last.
                s.large_step_probability = 1.0;
                s.start_iteration();
                s.start_stream(PssStream::Connection);
                let x0 = s.get_1d() as f64;
                s.accept();
                s.large_step_probability = 0.0;
                for step in 0..k {
                    s.start_iteration();
                    s.start_stream(PssStream::Connection);
                    if step + 1 == k {
                        let x = s.get_1d() as f64;
                        let d = (x - x0 + 0.5).rem_euclid(1.0) - 0.5;
                        let cell = edges.partition_point(|&e| e <= d);
                        counts[cell] += 1;
                    }
                    s.accept();
                }
            }
            let cdf: Vec<f64> = edges.iter().map(|&e| normal_cdf(e / sd)).collect();
            let mut expected = vec![cdf[0] * n as f64];
            expected.extend(cdf.windows(2).map(|w| (w[1] - w[0]) * n as f64));
            expected.push((1.0 - cdf[40]) * n as f64);
            let (stat, dof) = pearson(&counts, &expected);
            let p = chi2_survival(stat, dof);
            assert!(p > 1e-4, "σ = {sigma}, k = {k}: χ² = {stat} for {dof} dof, p = {p}");
        }
    }

    #[test]
    fn a_rejected_proposal_restores_every_coordinate_it_changed() {
        let mut s = PssSampler::new(1, 2, 0.1, 0.5);
        let read = |s: &mut PssSampler| {
            s.start_stream(PssStream::Camera);
            let mut v: Vec<f32> = (0..5).map(|_| s.get_1d()).collect();
            s.start_stream(PssStream::Light);
            v.extend((0..3).map(|_| s.get_1d()));
            v
        };
        let first = read(&mut s);
        for _ in 0..50 {
            s.start_iteration();
            let proposal = read(&mut s);
            assert_ne!(proposal, first);
            s.reject();
            // The stored state (reading it would mutate it): camera coordinates 0, 3, 6, …,
            // light ones 1, 4, 7, ….
            let stored: Vec<f32> = [0, 3, 6, 9, 12, 1, 4, 7].iter().map(|&i| s.x[i].value).collect();
            assert_eq!(stored, first);
        }
        // The same (seed, index) makes the same first path.
        assert_eq!(read(&mut PssSampler::new(1, 2, 0.1, 0.5)), first);
    }

    #[test]
    fn erf_inv_inverts_the_normal_cdf() {
        for u in [1e-6f32, 0.001, 0.1, 0.3, 0.5, 0.7, 0.95, 0.999, 1.0 - 6e-8] {
            let x = standard_normal(u);
            let u = u as f64;
            assert!((normal_cdf(x) - u).abs() < 1e-6 * u.min(1.0 - u) + 1e-9, "{u}: {x}");
        }
    }
}

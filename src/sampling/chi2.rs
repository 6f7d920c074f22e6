//! Generic Pearson χ² goodness-of-fit test of a sampling routine against its density.
//!
//! Design after Mitsuba 3's `ChiSquareTest(domain, sample_func, pdf_func)` with pbrt-v4's
//! constants (`src/pbrt/bsdfs_test.cpp`): 80 × 160 (θ, φ) cells, 10⁶ samples, cells with an
//! expected count below 5 are pooled, significance α = 0.01 with a Šidák correction
//! 1 − (1 − α)^(1/m) over the m tests of a suite. The expected count of each cell is
//! N ∫_cell pdf, integrated by adaptive Simpson quadrature (Lyness 1969), so no analytic
//! cell integral is needed. Failed samples (`None`) are legal: the density then integrates to
//! less than one and the expected counts say so.

use crate::math::{Frame, Vec2, Vec3, PI};
use crate::sampling::Rng;
use std::fmt;

/// Where samples live and how cells are laid out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Domain {
    /// Directions in the cap of half-angle `theta_max` [rad] around `axis` (π: the whole
    /// sphere). Cells are `theta_res` × `phi_res` in (θ, φ) about the axis; directions outside
    /// the cap and failed samples share one extra cell of probability 1 − ∫_cap pdf dω.
    /// A narrow cap zooms onto a peaked lobe (a near-specular BSDF).
    Cap {
        /// Centre of the cap (unit vector).
        axis: Vec3,
        /// Half-angle [rad], in (0, π].
        theta_max: f32,
    },
    /// Points (x, y) of a rectangle (the z of the sample is ignored); pdf per unit area.
    /// Cells are `phi_res` along x by `theta_res` along y.
    Plane {
        /// Lower corner.
        min: Vec2,
        /// Upper corner.
        max: Vec2,
    },
}

impl Domain {
    /// The whole sphere of directions.
    pub const SPHERE: Domain = Domain::Cap { axis: Vec3::Z, theta_max: PI };
}

/// A χ² test configuration; run it with [`Chi2Test::run`].
#[derive(Clone, Copy, Debug)]
pub struct Chi2Test {
    /// Sample domain.
    pub domain: Domain,
    /// Cells along θ (or y).
    pub theta_res: usize,
    /// Cells along φ (or x).
    pub phi_res: usize,
    /// Number of calls to the sampler.
    pub sample_count: usize,
    /// Seed of the PCG32 stream feeding the sampler.
    pub seed: u64,
    /// Significance level of the whole suite before the Šidák correction.
    pub alpha: f64,
    /// Number of tests in the suite (for the Šidák correction).
    pub test_count: usize,
    /// Smallest expected count of a cell before it is pooled.
    pub min_expected: f64,
}

impl Default for Chi2Test {
    fn default() -> Self {
        Self {
            domain: Domain::SPHERE,
            theta_res: 80,
            phi_res: 160,
            sample_count: 1_000_000,
            seed: 0x5eed,
            alpha: 0.01,
            test_count: 1,
            min_expected: 5.0,
        }
    }
}

/// Outcome of a χ² test.
#[derive(Clone, Debug)]
pub struct Chi2Result {
    /// Pearson's statistic Σ (O − E)² / E over the (pooled) cells.
    pub statistic: f64,
    /// Degrees of freedom (cells − 1).
    pub dof: usize,
    /// P(χ²_dof ≥ statistic).
    pub p_value: f64,
    /// Šidák-corrected significance level the p-value is compared with.
    pub significance: f64,
    /// ∫ pdf over the domain (≤ 1; < 1 where the sampler may fail).
    pub pdf_integral: f64,
    /// Fraction of calls that returned a sample.
    pub sampled_fraction: f64,
    /// Why the test failed, if it did.
    pub failure: Option<String>,
    /// True when the sampler is consistent with the density at this significance.
    pub passed: bool,
}

impl fmt::Display for Chi2Result {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "chi2 = {:.1}, dof = {}, p = {:.3e} (need ≥ {:.2e}), ∫pdf = {:.5}, sampled = {:.5}",
            self.statistic, self.dof, self.p_value, self.significance, self.pdf_integral, self.sampled_fraction
        )?;
        if let Some(why) = &self.failure {
            write!(f, ", FAILED: {why}")?;
        }
        Ok(())
    }
}

impl Chi2Test {
    /// Runs the test. `sample(uc, u)` draws one sample from a 1D and a 2D uniform random number
    /// (BSDF convention) and may fail; `pdf` is the density it claims, per steradian on a
    /// [`Domain::Cap`], per unit area on a [`Domain::Plane`].
    pub fn run(&self, mut sample: impl FnMut(f32, Vec2) -> Option<Vec3>, pdf: impl Fn(Vec3) -> f32) -> Chi2Result {
        let cells = self.theta_res * self.phi_res;
        let mut observed = vec![0f64; cells + 1];
        let mut rng = Rng::new(self.seed, 0xc412);
        let mut sampled = 0usize;
        let mut non_finite = 0usize;
        for _ in 0..self.sample_count {
            let uc = rng.uniform();
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let Some(w) = sample(uc, u) else {
                observed[cells] += 1.0;
                continue;
            };
            if !w.is_finite() {
                non_finite += 1;
                continue;
            }
            sampled += 1;
            observed[self.cell_of(w).unwrap_or(cells)] += 1.0;
        }
        let n = self.sample_count as f64;
        let mut expected = self.integrate_cells(&pdf);
        let pdf_integral: f64 = expected.iter().sum();
        expected.iter_mut().for_each(|e| *e *= n);
        let outside = match self.domain {
            Domain::Cap { theta_max, .. } if theta_max < PI => (1.0 - pdf_integral).max(0.0),
            // Whole domain: only failures land in the extra cell, with the missing mass.
            _ => (1.0 - pdf_integral).max(0.0),
        };
        expected.push(outside * n);
        let significance = 1.0 - (1.0 - self.alpha).powf(1.0 / self.test_count.max(1) as f64);
        let mut result = Chi2Result {
            statistic: 0.0,
            dof: 0,
            p_value: 0.0,
            significance,
            pdf_integral,
            sampled_fraction: sampled as f64 / n,
            failure: None,
            passed: false,
        };
        if non_finite > 0 {
            result.failure = Some(format!("{non_finite} non-finite samples"));
            return result;
        }
        if pdf_integral > 1.0 + 1e-3 {
            result.failure = Some(format!("pdf integrates to {pdf_integral} > 1"));
            return result;
        }
        let (statistic, dof, bad) = pooled_statistic(&expected, &observed, self.min_expected, n, cells);
        result.statistic = statistic;
        result.dof = dof;
        if let Some(bad) = bad {
            result.failure = Some(bad);
            return result;
        }
        if dof == 0 {
            result.failure = Some("fewer than two cells with a usable expected count".into());
            return result;
        }
        result.p_value = chi2_survival(statistic, dof as f64);
        result.passed = result.p_value >= significance;
        if !result.passed {
            result.failure = Some("p-value below the significance level".into());
        }
        result
    }

    /// Cell index of a sample, `None` outside the binned region.
    fn cell_of(&self, w: Vec3) -> Option<usize> {
        let (x, y) = match self.domain {
            Domain::Cap { axis, theta_max } => {
                let l = Frame::from_normal(axis).to_local(w.normalize());
                // atan2, not acos: acos(z) loses all precision near the axis, where a zoomed cap lives.
                let theta = (l.x * l.x + l.y * l.y).sqrt().atan2(l.z);
                if theta > theta_max {
                    return None;
                }
                let mut phi = l.y.atan2(l.x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                (phi / (2.0 * PI), theta / theta_max)
            }
            Domain::Plane { min, max } => {
                let p = (w.truncate() - min) / (max - min);
                if !(0.0..=1.0).contains(&p.x) || !(0.0..=1.0).contains(&p.y) {
                    return None;
                }
                (p.x, p.y)
            }
        };
        let ix = ((x * self.phi_res as f32) as usize).min(self.phi_res - 1);
        let iy = ((y * self.theta_res as f32) as usize).min(self.theta_res - 1);
        Some(iy * self.phi_res + ix)
    }

    /// ∫ pdf over every cell (probabilities, not yet scaled by N).
    fn integrate_cells(&self, pdf: &impl Fn(Vec3) -> f32) -> Vec<f64> {
        // Cells expected to hold less than 0.01 samples need no accuracy at all.
        let floor = 0.01 / self.sample_count.max(1) as f64;
        let mut out = Vec::with_capacity(self.theta_res * self.phi_res);
        match self.domain {
            Domain::Cap { axis, theta_max } => {
                let frame = Frame::from_normal(axis);
                let dtheta = theta_max as f64 / self.theta_res as f64;
                let dphi = 2.0 * std::f64::consts::PI / self.phi_res as f64;
                let f = |theta: f64, phi: f64| {
                    let (st, ct) = theta.sin_cos();
                    let l = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, ct as f32);
                    pdf(frame.to_world(l)) as f64 * st
                };
                for iy in 0..self.theta_res {
                    for ix in 0..self.phi_res {
                        let (t0, p0) = (iy as f64 * dtheta, ix as f64 * dphi);
                        out.push(simpson_2d(&f, t0, t0 + dtheta, p0, p0 + dphi, floor));
                    }
                }
            }
            Domain::Plane { min, max } => {
                let dx = (max.x - min.x) as f64 / self.phi_res as f64;
                let dy = (max.y - min.y) as f64 / self.theta_res as f64;
                let f = |y: f64, x: f64| pdf(Vec3::new(x as f32, y as f32, 0.0)) as f64;
                for iy in 0..self.theta_res {
                    for ix in 0..self.phi_res {
                        let y0 = min.y as f64 + iy as f64 * dy;
                        let x0 = min.x as f64 + ix as f64 * dx;
                        out.push(simpson_2d(&f, y0, y0 + dy, x0, x0 + dx, floor));
                    }
                }
            }
        }
        out
    }
}

/// Pearson's statistic with cells of expected count < `min_expected` pooled into one
/// (Mitsuba 3 `chi2.py`). Returns (statistic, dof, failure). A cell with expected count 0 but
/// more than 10⁻⁵ N observations is a failure: the sampler produces what the pdf forbids
/// (except `failure_cell`, whose expectation is a difference of integrals).
fn pooled_statistic(
    expected: &[f64],
    observed: &[f64],
    min_expected: f64,
    n: f64,
    failure_cell: usize,
) -> (f64, usize, Option<String>) {
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut stat, mut cells) = (0.0f64, 0usize);
    let (mut pool_e, mut pool_o) = (0.0f64, 0.0f64);
    for &i in &order {
        let (e, o) = (expected[i], observed[i]);
        // The failure/outside cell's expectation 1 − ∫pdf may round to 0 by quadrature error:
        // it is pooled like any small cell instead.
        if e <= 0.0 && i != failure_cell {
            if o > 1e-5 * n {
                return (stat, 0, Some(format!("{o} samples in a cell of expected count 0 (cell {i})")));
            }
            pool_o += o;
            continue;
        }
        if e < min_expected {
            pool_e += e;
            pool_o += o;
            if pool_e >= min_expected {
                stat += (pool_o - pool_e).powi(2) / pool_e;
                cells += 1;
                pool_e = 0.0;
                pool_o = 0.0;
            }
            continue;
        }
        stat += (o - e).powi(2) / e;
        cells += 1;
    }
    if pool_e > 0.0 {
        stat += (pool_o - pool_e).powi(2) / pool_e;
        cells += 1;
    }
    (stat, cells.saturating_sub(1), None)
}

/// ∫∫ f(y, x) dx dy over a cell by nested adaptive Simpson quadrature.
/// `floor` is an absolute tolerance on the cell integral below which refinement stops.
fn simpson_2d(f: &impl Fn(f64, f64) -> f64, y0: f64, y1: f64, x0: f64, x1: f64, floor: f64) -> f64 {
    // Relative tolerance 1e-3 of a cell's mass: far below the Poisson noise of any cell with
    // fewer than 10⁶ expected samples, yet cheap for smooth densities. Depth 9 (512 panels per
    // axis) resolves the near-singular grazing-transmission densities; only they go that deep.
    let inner_floor = floor / (y1 - y0);
    let inner = |y: f64| simpson_adaptive(&|x| f(y, x), x0, x1, 1e-3, inner_floor, 9);
    simpson_adaptive(&inner, y0, y1, 1e-3, floor, 9)
}

/// Adaptive Simpson integration of `f` over [a, b] to a tolerance `eps` relative to the
/// whole-interval estimate, at most `depth` halvings. The first two halvings are always made:
/// a peak that falls between the five points of the coarse rule would otherwise fool its
/// error estimate (it did for a GGX transmission lobe at the pole).
fn simpson_adaptive(f: &dyn Fn(f64) -> f64, a: f64, b: f64, eps: f64, floor: f64, depth: u32) -> f64 {
    const MIN_LEVEL: u32 = 2;
    #[allow(clippy::too_many_arguments)]
    fn rec(
        f: &dyn Fn(f64) -> f64,
        (a, b): (f64, f64),
        (fa, fm, fb): (f64, f64, f64),
        whole: f64,
        eps: f64,
        level: u32,
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
        let (flm, frm) = (f(lm), f(rm));
        let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
        let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
        let delta = left + right - whole;
        if level >= depth || (level >= MIN_LEVEL && delta.abs() <= 15.0 * eps) {
            return left + right + delta / 15.0;
        }
        rec(f, (a, m), (fa, flm, fm), left, 0.5 * eps, level + 1, depth)
            + rec(f, (m, b), (fm, frm, fb), right, 0.5 * eps, level + 1, depth)
    }
    // Cell edges are evaluated a hair inside: a density discontinuous exactly on an edge (the
    // horizon between reflection and transmission) must take the value of this cell's side.
    let inset = (b - a) * 1e-7;
    let (fa, fm, fb) = (f(a + inset), f(0.5 * (a + b)), f(b - inset));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    let tol = (eps * whole.abs()).max(floor).max(1e-300);
    rec(f, (a, b), (fa, fm, fb), whole, tol, 0, depth)
}

/// P(X ≥ x) for X ~ χ²(k): the regularized upper incomplete gamma function Q(k/2, x/2).
pub fn chi2_survival(x: f64, k: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    gamma_q(0.5 * k, 0.5 * x)
}

/// Regularized upper incomplete gamma Q(a, x) = Γ(a, x)/Γ(a): power series for x < a + 1,
/// Lentz's continued fraction otherwise (Press et al., Numerical Recipes §6.2).
fn gamma_q(a: f64, x: f64) -> f64 {
    let log_prefactor = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum) = (1.0 / a, 1.0 / a);
        for n in 1..100_000 {
            term *= x / (a + n as f64);
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * log_prefactor.exp()).clamp(0.0, 1.0)
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (h * log_prefactor.exp()).clamp(0.0, 1.0)
    }
}

/// ln Γ(z) for z > 0: the recurrence Γ(z) = Γ(z+1)/z up to z ≥ 10, then Stirling's series.
fn ln_gamma(mut z: f64) -> f64 {
    let mut shift = 0.0;
    while z < 10.0 {
        shift -= z.ln();
        z += 1.0;
    }
    let z2 = z * z;
    let series =
        1.0 / (12.0 * z) - 1.0 / (360.0 * z * z2) + 1.0 / (1260.0 * z * z2 * z2) - 1.0 / (1680.0 * z * z2 * z2 * z2);
    shift + (z - 0.5) * z.ln() - z + 0.5 * (2.0 * std::f64::consts::PI).ln() + series
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_gamma_matches_factorials() {
        let mut fact = 1.0f64;
        for n in 1..30 {
            fact *= n as f64;
            assert!((ln_gamma(n as f64 + 1.0) - fact.ln()).abs() < 1e-10, "{n}");
        }
        assert!((ln_gamma(0.5) - PI.sqrt().ln() as f64).abs() < 1e-6);
    }

    #[test]
    fn chi2_survival_matches_closed_forms() {
        // k = 2: Q = exp(−x/2). k = 1: Q = erfc(√(x/2)); at x = 3.841459, Q = 0.05 (tables).
        for &x in &[0.1, 1.0, 5.0, 30.0] {
            assert!((chi2_survival(x, 2.0) - (-0.5 * x).exp()).abs() < 1e-12);
        }
        assert!((chi2_survival(3.841459, 1.0) - 0.05).abs() < 1e-6);
        // Large dof: the median of χ²_k is ≈ k(1 − 2/(9k))³.
        let k: f64 = 10_000.0;
        let median = k * (1.0 - 2.0 / (9.0 * k)).powi(3);
        assert!((chi2_survival(median, k) - 0.5).abs() < 1e-3);
    }

    #[test]
    fn adaptive_simpson_handles_a_step() {
        let v = simpson_adaptive(&|x| if x < 0.3 { 1.0 } else { 0.0 }, 0.0, 1.0, 1e-7, 0.0, 12);
        assert!((v - 0.3).abs() < 1e-3, "{v}");
        let v = simpson_adaptive(&|x: f64| x.sin(), 0.0, std::f64::consts::PI, 1e-9, 0.0, 10);
        assert!((v - 2.0).abs() < 1e-8);
    }
}

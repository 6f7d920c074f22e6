//! The PBD profile tabulated over single-scattering albedo ρ × optical radius r σ_t, for one
//! (g, η), as pbrt-v4's `BSSRDFTable` (100 albedos spaced densely near 1, radii growing
//! geometrically). Where pbrt interpolates with Catmull–Rom splines we interpolate linearly in ρ
//! and r: evaluation, sampling and pdf then describe exactly the same piecewise-linear profile,
//! so the probe estimator stays consistent, and the radii are denser (ratio 1.1 instead of 1.2)
//! to keep the interpolation error small. Sampling picks one of the two bracketing albedo rows
//! with probability ∝ its weight × effective albedo, then inverts that row's piecewise-linear
//! density; the mixture's density is the interpolated profile over the interpolated effective
//! albedo.

use super::pbd::{beam_diffusion_ms, beam_diffusion_ss};
use std::sync::atomic::{AtomicUsize, Ordering};

const N_RHO: usize = 100;
const N_RADIUS: usize = 128;

/// Tables built so far in this process (for "no subsurface, no tables" checks).
static TABLES_BUILT: AtomicUsize = AtomicUsize::new(0);

/// P(ρ, r) = 2π r (R_ss + R_ms)(r) for σ_t = 1, and its integral ρ_eff(ρ) (the total diffuse
/// reflectance of the semi-infinite medium).
pub struct BssrdfTable {
    rho: Vec<f32>,
    radius: Vec<f32>,
    /// Row-major [ρ][r] radial density [1/optical length].
    profile: Vec<f32>,
    /// Row-major running integral of `profile` over r (trapezoids).
    cdf: Vec<f32>,
    /// ρ_eff per albedo row (last entry of each `cdf` row).
    rho_eff: Vec<f32>,
}

impl std::fmt::Debug for BssrdfTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BssrdfTable({}×{})", self.rho.len(), self.radius.len())
    }
}

impl BssrdfTable {
    /// Builds the table for phase asymmetry `g` and relative index `eta` (~2 ms per row).
    pub fn new(g: f32, eta: f32) -> Self {
        TABLES_BUILT.fetch_add(1, Ordering::Relaxed);
        let mut radius = vec![0.0f32; N_RADIUS];
        radius[1] = 2.5e-3;
        for i in 2..N_RADIUS {
            radius[i] = radius[i - 1] * 1.1;
        }
        let rho: Vec<f32> = (0..N_RHO)
            .map(|i| ((1.0 - (-8.0 * i as f64 / (N_RHO - 1) as f64).exp()) / (1.0 - (-8.0f64).exp())) as f32)
            .collect();
        let rows: Vec<(Vec<f32>, Vec<f32>)> = {
            use rayon::prelude::*;
            rho.par_iter()
                .map(|&p| {
                    let (p, g) = (p as f64, g as f64);
                    let mut prof: Vec<f32> = radius
                        .iter()
                        .map(|&r| {
                            let r = r as f64;
                            let v = 2.0
                                * std::f64::consts::PI
                                * r
                                * (beam_diffusion_ss(p, 1.0 - p, g, eta, r) + beam_diffusion_ms(p, 1.0 - p, g, eta, r));
                            if v.is_finite() {
                                v.max(0.0) as f32
                            } else {
                                0.0
                            }
                        })
                        .collect();
                    let mut cdf = vec![0.0f32; N_RADIUS];
                    for j in 1..N_RADIUS {
                        cdf[j] = cdf[j - 1] + 0.5 * (prof[j] + prof[j - 1]) * (radius[j] - radius[j - 1]);
                    }
                    // PBD overshoots near ρ = 1 (ρ_eff(1) ≈ 1.03 for η = 1.33, 1.09 for η = 1): scale
                    // such rows to ρ_eff = 1 so the model never reflects more than it receives.
                    let total = cdf[N_RADIUS - 1];
                    if total > 1.0 {
                        prof.iter_mut().chain(cdf.iter_mut()).for_each(|v| *v /= total);
                    }
                    (prof, cdf)
                })
                .collect()
        };
        let rho_eff = rows.iter().map(|(_, c)| c[N_RADIUS - 1]).collect();
        let (profile, cdf) = rows.into_iter().fold((Vec::new(), Vec::new()), |(mut p, mut c), (pr, cr)| {
            p.extend(pr);
            c.extend(cr);
            (p, c)
        });
        Self { rho, radius, profile, cdf, rho_eff }
    }

    /// Number of tables built in this process so far.
    pub fn built_count() -> usize {
        TABLES_BUILT.load(Ordering::Relaxed)
    }

    /// Bracketing albedo rows and the weight of the upper one.
    fn rho_bracket(&self, rho: f32) -> (usize, f32) {
        bracket(&self.rho, rho.clamp(0.0, 1.0))
    }

    /// Effective albedo ρ_eff(ρ): the total diffuse reflectance of a semi-infinite medium of
    /// single-scattering albedo ρ under normal incidence (before the exit Fresnel factor).
    pub fn rho_eff(&self, rho: f32) -> f32 {
        let (i, w) = self.rho_bracket(rho);
        lerp(self.rho_eff[i], self.rho_eff[i + 1], w)
    }

    /// The albedo ρ with ρ_eff(ρ) = `target` (monotone: bisection on the interpolated curve,
    /// pbrt-v4 `InvertCatmullRom`); targets beyond the table clamp to ρ = 0 or 1.
    pub fn invert_rho_eff(&self, target: f32) -> f32 {
        if target.is_nan() || target <= self.rho_eff[0] {
            return 0.0;
        }
        if target >= self.rho_eff[N_RHO - 1] {
            return 1.0;
        }
        let j = self.rho_eff.partition_point(|&v| v <= target).clamp(1, N_RHO - 1);
        let (a, b) = (self.rho_eff[j - 1], self.rho_eff[j]);
        let w = if b > a { (target - a) / (b - a) } else { 0.0 };
        lerp(self.rho[j - 1], self.rho[j], w)
    }

    /// Radial density P(ρ, r) [1/optical length] at optical radius `r` ≥ 0 (0 beyond the table).
    pub fn profile(&self, rho: f32, r: f32) -> f32 {
        let (i, w) = self.rho_bracket(rho);
        if r.is_nan() || r < 0.0 || r > self.radius[N_RADIUS - 1] {
            return 0.0;
        }
        let (j, t) = bracket(&self.radius, r);
        let row = |k: usize| lerp(self.profile[k * N_RADIUS + j], self.profile[k * N_RADIUS + j + 1], t);
        lerp(row(i), row(i + 1), w)
    }

    /// Samples an optical radius with density `profile(ρ, r) / rho_eff(ρ)`; `None` when ρ_eff = 0.
    pub fn sample_radius(&self, rho: f32, u: f32) -> Option<f32> {
        let (i, w) = self.rho_bracket(rho);
        let (m0, m1) = ((1.0 - w) * self.rho_eff[i], w * self.rho_eff[i + 1]);
        if (m0 + m1).is_nan() || m0 + m1 <= 0.0 {
            return None;
        }
        let p0 = m0 / (m0 + m1);
        let (row, u) = if u < p0 { (i, u / p0) } else { (i + 1, ((u - p0) / (1.0 - p0)).min(1.0 - f32::EPSILON)) };
        let cdf = &self.cdf[row * N_RADIUS..(row + 1) * N_RADIUS];
        let prof = &self.profile[row * N_RADIUS..(row + 1) * N_RADIUS];
        let target = u * cdf[N_RADIUS - 1];
        let j = cdf.partition_point(|&c| c <= target).clamp(1, N_RADIUS - 1) - 1;
        let h = self.radius[j + 1] - self.radius[j];
        // Solve h (f0 t + (f1 − f0) t²/2) = target − cdf[j] for t ∈ [0, 1] (stable root form).
        let (f0, f1) = (prof[j], prof[j + 1]);
        let c = ((target - cdf[j]) / h).max(0.0);
        let a = 0.5 * (f1 - f0);
        let disc = (f0 * f0 + 4.0 * a * c).max(0.0);
        let denom = f0 + disc.sqrt();
        let t = if denom > 0.0 { (2.0 * c / denom).clamp(0.0, 1.0) } else { 0.5 };
        Some(self.radius[j] + t * h)
    }

    /// Density of [`Self::sample_radius`] [1/optical length].
    pub fn radius_pdf(&self, rho: f32, r: f32) -> f32 {
        let e = self.rho_eff(rho);
        if e > 0.0 {
            self.profile(rho, r) / e
        } else {
            0.0
        }
    }
}

/// Index i and weight w with xs[i] ≤ x ≤ xs[i+1] (clamped to the ends; xs increasing).
fn bracket(xs: &[f32], x: f32) -> (usize, f32) {
    let n = xs.len();
    let i = xs.partition_point(|&v| v <= x).clamp(1, n - 1) - 1;
    let d = xs[i + 1] - xs[i];
    let w = if d > 0.0 { ((x - xs[i]) / d).clamp(0.0, 1.0) } else { 0.0 };
    (i, w)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

#[cfg(test)]
#[path = "table_tests.rs"]
mod tests;

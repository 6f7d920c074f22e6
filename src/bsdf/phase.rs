//! The Henyey–Greenstein phase function (Henyey & Greenstein 1941, "Diffuse radiation in the
//! galaxy"), p(cos θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}), with θ the angle between the
//! propagation directions before and after scattering (g > 0: forward scattering).
//! Sampling inverts its CDF in closed form (pbrt-v4 `SampleHenyeyGreenstein`).

use crate::math::{Frame, Vec2, Vec3, PI};
use crate::sampling::warp::sin_cos_turn;

/// HG phase function with asymmetry g = E[cos θ] ∈ (−1, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    /// Mean cosine of the scattering angle.
    pub g: f32,
}

impl HenyeyGreenstein {
    /// HG with `g` clamped to [−0.99, 0.99] (|g| → 1 is a delta and has no density); NaN → 0.
    pub fn new(g: f32) -> Self {
        let g = if g.is_finite() { g.clamp(-0.99, 0.99) } else { 0.0 };
        Self { g }
    }

    /// Density [1/sr] of scattering from propagation direction `d_in` to `d_out` (both unit).
    #[inline]
    pub fn p(&self, d_in: Vec3, d_out: Vec3) -> f32 {
        hg_density(d_in.dot(d_out), self.g)
    }

    /// Samples a new unit propagation direction after scattering from `d_in` (unit); its
    /// density is exactly [`Self::p`], so the phase/pdf ratio is 1.
    pub fn sample(&self, d_in: Vec3, u: Vec2) -> Vec3 {
        let g = self.g;
        let cos_theta = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
            (1.0 + g * g - s * s) / (2.0 * g)
        }
        .clamp(-1.0, 1.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let (sin_phi, cos_phi) = sin_cos_turn(u.y);
        let f = Frame::from_normal(d_in);
        f.to_world(Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta))
    }
}

/// p(cos θ) for asymmetry g [1/sr].
#[inline]
pub fn hg_density(cos_theta: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * PI * denom * denom.max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::Chi2Test;

    #[test]
    fn hg_sampling_matches_its_density_chi2() {
        let gs = [-0.7, 0.0, 0.3, 0.9];
        let d_in = Vec3::new(0.3, -0.4, 0.866).normalize();
        for g in gs {
            let phase = HenyeyGreenstein::new(g);
            let test = Chi2Test { test_count: gs.len(), sample_count: 300_000, ..Default::default() };
            let r = test.run(|_, u| Some(phase.sample(d_in, u)), |w| phase.p(d_in, w));
            assert!(r.passed, "g = {g}: {r}");
            assert!((r.pdf_integral - 1.0).abs() < 1e-3, "g = {g}: ∫p = {}", r.pdf_integral);
        }
    }

    #[test]
    fn hg_mean_cosine_is_g() {
        // E[cos θ] = g by definition of the asymmetry parameter; midpoint rule in cos θ.
        for g in [-0.5f32, 0.0, 0.8] {
            let n = 200_000;
            let mean: f64 = (0..n)
                .map(|i| {
                    let mu = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
                    (mu * hg_density(mu, g) * 2.0 * PI * 2.0 / n as f32) as f64
                })
                .sum();
            assert!((mean - g as f64).abs() < 2e-3, "g = {g}: mean cos = {mean}");
        }
    }
}

//! Piecewise-constant 1D and 2D distributions (pbrt-v4 `PiecewiseConstant1D/2D`, PBR 4th ed.
//! §A.4.2, §A.4.3): continuous samples with their pdf, discrete samples, and inversion, e.g. for
//! importance sampling an environment map by luminance.

use glam::Vec2;

/// A piecewise-constant density on [0, 1] with `n` equal segments, proportional to |f|.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// |f| per segment (NaN/inf → 0).
    func: Vec<f32>,
    /// cdf[i] = P(segment < i); cdf[n] = 1. In f64 so long tables sum accurately.
    cdf: Vec<f64>,
    /// ∫₀¹ |f| dx (0 when all zero, and the density is then uniform).
    integral: f32,
}

/// A continuous sample of a [`Distribution1D`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample1D {
    /// Position in [0, 1).
    pub x: f32,
    /// Density at `x` (w.r.t. dx on [0, 1]).
    pub pdf: f32,
    /// Segment containing `x`.
    pub offset: usize,
}

impl Distribution1D {
    /// The density ∝ |f| over [0, 1]. Empty `f` is treated as one zero segment (uniform).
    pub fn new(f: &[f32]) -> Self {
        let mut func: Vec<f32> = f.iter().map(|&v| if v.is_finite() { v.abs() } else { 0.0 }).collect();
        if func.is_empty() {
            func.push(0.0);
        }
        let n = func.len();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f64);
        for &v in &func {
            cdf.push(cdf.last().unwrap() + v as f64 / n as f64);
        }
        let integral = cdf[n];
        if integral == 0.0 {
            // No information: sample uniformly (pbrt-v4 does the same).
            cdf.iter_mut().enumerate().for_each(|(i, c)| *c = i as f64 / n as f64);
        } else {
            cdf.iter_mut().for_each(|c| *c /= integral);
        }
        cdf[n] = 1.0;
        Self { func, cdf, integral: integral as f32 }
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// Never true (an empty input becomes one segment); for clippy's `len` convention.
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// ∫₀¹ |f| dx.
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Segment i with cdf[i] ≤ u < cdf[i+1].
    fn find_segment(&self, u: f64) -> usize {
        // partition_point: first index with cdf > u; the segment is one before it.
        let i = self.cdf.partition_point(|&c| c <= u);
        i.saturating_sub(1).min(self.len() - 1)
    }

    /// Density at x ∈ [0, 1] (w.r.t. dx).
    pub fn pdf(&self, x: f32) -> f32 {
        if !(0.0..=1.0).contains(&x) {
            return 0.0;
        }
        let i = ((x * self.len() as f32) as usize).min(self.len() - 1);
        self.segment_pdf(i)
    }

    fn segment_pdf(&self, i: usize) -> f32 {
        if self.integral > 0.0 {
            self.func[i] / self.integral
        } else {
            1.0
        }
    }

    /// A continuous sample by inverting the cdf for uniform `u` in [0, 1).
    pub fn sample(&self, u: f32) -> Sample1D {
        let u = u.clamp(0.0, 1.0) as f64;
        let i = self.find_segment(u);
        let width = self.cdf[i + 1] - self.cdf[i];
        // Linear inversion within the segment (the cdf is linear there).
        let du = if width > 0.0 { ((u - self.cdf[i]) / width).clamp(0.0, 1.0) } else { 0.0 };
        let x = ((i as f64 + du) / self.len() as f64) as f32;
        // Keep x inside the segment despite rounding, and below 1.
        let x = x.min(((i + 1) as f32 / self.len() as f32).next_down()).max(i as f32 / self.len() as f32);
        Sample1D { x, pdf: self.segment_pdf(i), offset: i }
    }

    /// A segment index with probability ∝ |f| (uniform if all zero), its probability, and `u`
    /// remapped to a fresh uniform in [0, 1) for reuse.
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let u64_ = u.clamp(0.0, 1.0) as f64;
        let i = self.find_segment(u64_);
        let p = self.cdf[i + 1] - self.cdf[i];
        let remapped = if p > 0.0 { ((u64_ - self.cdf[i]) / p) as f32 } else { 0.0 };
        (i, p as f32, remapped.clamp(0.0, 1.0f32.next_down()))
    }

    /// Probability of segment `i` in [`Distribution1D::sample_discrete`] (0 out of range).
    pub fn discrete_pmf(&self, i: usize) -> f32 {
        if i < self.len() {
            (self.cdf[i + 1] - self.cdf[i]) as f32
        } else {
            0.0
        }
    }

    /// The `u` that [`Distribution1D::sample`] maps to `x`, or `None` if x ∉ [0, 1] or lies in a
    /// zero-density segment (not reachable).
    pub fn invert(&self, x: f32) -> Option<f32> {
        if !(0.0..=1.0).contains(&x) {
            return None;
        }
        let n = self.len();
        let i = ((x as f64 * n as f64) as usize).min(n - 1);
        let width = self.cdf[i + 1] - self.cdf[i];
        if width == 0.0 {
            return None;
        }
        let t = x as f64 * n as f64 - i as f64;
        Some((self.cdf[i] + t * width) as f32)
    }
}

/// A piecewise-constant density on [0, 1]² from an `nu × nv` grid (row-major, v rows), sampled as
/// p(u, v) = p(v) · p(u | v): a marginal over rows, then the row's conditional.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    conditional: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// The density ∝ |f| with `f[v * nu + u]`. Missing entries (f shorter than nu·nv) count as 0.
    pub fn new(f: &[f32], nu: usize, nv: usize) -> Self {
        let (nu, nv) = (nu.max(1), nv.max(1));
        let conditional: Vec<Distribution1D> = (0..nv)
            .map(|v| {
                let row: Vec<f32> = (0..nu).map(|u| f.get(v * nu + u).copied().unwrap_or(0.0)).collect();
                Distribution1D::new(&row)
            })
            .collect();
        let marginal = Distribution1D::new(&conditional.iter().map(|c| c.integral()).collect::<Vec<_>>());
        Self { conditional, marginal }
    }

    /// ∫∫ |f| du dv.
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// A point in [0, 1)² and its density, from two uniforms.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let sv = self.marginal.sample(u.y);
        let su = self.conditional[sv.offset].sample(u.x);
        (Vec2::new(su.x, sv.x), su.pdf * sv.pdf)
    }

    /// Density at p ∈ [0, 1]² (0 outside).
    pub fn pdf(&self, p: Vec2) -> f32 {
        if !(0.0..=1.0).contains(&p.x) || !(0.0..=1.0).contains(&p.y) {
            return 0.0;
        }
        let nv = self.conditional.len();
        let v = ((p.y * nv as f32) as usize).min(nv - 1);
        self.marginal.pdf(p.y) * self.conditional[v].pdf(p.x)
    }

    /// The uniforms that [`Distribution2D::sample`] maps to `p`, if `p` is reachable.
    pub fn invert(&self, p: Vec2) -> Option<Vec2> {
        let uv = self.marginal.invert(p.y)?;
        let nv = self.conditional.len();
        let v = ((p.y * nv as f32) as usize).min(nv - 1);
        let uu = self.conditional[v].invert(p.x)?;
        Some(Vec2::new(uu, uv))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::alias::tests::chi2_critical;
    use crate::sampling::Rng;

    #[test]
    fn sample_1d_pdf_matches_function_and_inverts() {
        let f = [1.0, 3.0, 0.0, 4.0];
        let d = Distribution1D::new(&f);
        assert!((d.integral() - 2.0).abs() < 1e-6);
        let mut rng = Rng::new(1, 0);
        for _ in 0..10_000 {
            let u = rng.uniform();
            let s = d.sample(u);
            assert!((0.0..1.0).contains(&s.x));
            assert_ne!(s.offset, 2, "zero-density segment sampled");
            assert_eq!(s.pdf, d.pdf(s.x));
            assert!((s.pdf - f[s.offset] / 2.0).abs() < 1e-6);
            assert!((d.invert(s.x).unwrap() - u).abs() < 1e-5, "u {u} x {}", s.x);
        }
        assert_eq!(d.invert(0.6), None);
        assert_eq!(d.invert(1.5), None);
    }

    #[test]
    fn discrete_1d_chi2_and_remap() {
        let f: Vec<f32> = (0..50).map(|i| (i as f32 * 0.3).cos().abs() + 0.01).collect();
        let d = Distribution1D::new(&f);
        let n = 500_000;
        let mut counts = vec![0u64; 50];
        let mut rng = Rng::new(2, 0);
        let mut remapped_sum = 0.0f64;
        for _ in 0..n {
            let (i, p, u2) = d.sample_discrete(rng.uniform());
            assert!((p - d.discrete_pmf(i)).abs() < 1e-7);
            counts[i] += 1;
            remapped_sum += u2 as f64;
        }
        let stat: f64 = counts
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                let e = d.discrete_pmf(i) as f64 * n as f64;
                (c as f64 - e).powi(2) / e
            })
            .sum();
        assert!(stat < chi2_critical(49.0, 3.09), "χ² {stat}");
        // The remapped u is uniform: mean 1/2 within 4 standard errors.
        let mean = remapped_sum / n as f64;
        assert!((mean - 0.5).abs() < 4.0 * (1.0 / 12.0 / n as f64).sqrt(), "{mean}");
    }

    #[test]
    fn all_zero_and_empty_are_uniform() {
        for d in [Distribution1D::new(&[0.0; 8]), Distribution1D::new(&[]), Distribution1D::new(&[f32::NAN, 0.0])] {
            assert_eq!(d.integral(), 0.0);
            let s = d.sample(0.3);
            assert!((s.x - 0.3).abs() < 1e-6 && s.pdf == 1.0);
        }
    }

    #[test]
    fn sample_2d_chi2_against_pdf() {
        // A smooth 2D "environment map" with a bright spot and a zero band.
        let (nu, nv) = (32, 16);
        let f: Vec<f32> = (0..nu * nv)
            .map(|k| {
                let (u, v) = ((k % nu) as f32 / nu as f32, (k / nu) as f32 / nv as f32);
                if (0.4..0.5).contains(&v) {
                    0.0
                } else {
                    0.1 + 5.0 * (-40.0 * ((u - 0.7f32).powi(2) + (v - 0.2f32).powi(2))).exp()
                }
            })
            .collect();
        let d = Distribution2D::new(&f, nu, nv);
        // Histogram on a grid coarser than and misaligned with the function's cells.
        let (bu, bv) = (20, 10);
        let n = 1_000_000;
        let mut counts = vec![0u64; bu * bv];
        let mut rng = Rng::new(3, 0);
        for _ in 0..n {
            let (p, pdf) = d.sample(Vec2::new(rng.uniform(), rng.uniform()));
            assert!(pdf > 0.0 && (pdf - d.pdf(p)).abs() <= 1e-5 * pdf, "{p} {pdf}");
            let inv = d.invert(p).unwrap();
            assert!(d.sample(inv).0.distance(p) < 1e-4);
            counts[(p.y * bv as f32) as usize * bu + (p.x * bu as f32) as usize] += 1;
        }
        // Expected counts: integrate the pdf over each bin with a fine midpoint rule (exact for a
        // piecewise-constant pdf when the rule's grid refines both grids: 160 = lcm(32, 20)·1).
        let fine = 160;
        let mut expected = vec![0.0f64; bu * bv];
        for j in 0..fine {
            for i in 0..fine {
                let p = Vec2::new((i as f32 + 0.5) / fine as f32, (j as f32 + 0.5) / fine as f32);
                expected[(j * bv / fine) * bu + i * bu / fine] += d.pdf(p) as f64 / (fine * fine) as f64 * n as f64;
            }
        }
        let (mut stat, mut df) = (0.0, -1.0);
        for (c, e) in counts.iter().zip(&expected) {
            if *e >= 5.0 {
                stat += (*c as f64 - e).powi(2) / e;
                df += 1.0;
            } else {
                assert!((*c as f64) < 5.0 + 5.0 * e.max(1.0), "unexpected mass {c} vs {e}");
            }
        }
        assert!(stat < chi2_critical(df, 3.09), "χ² {stat} dof {df}");
        assert!((d.integral() - f.iter().sum::<f32>() / (nu * nv) as f32).abs() < 1e-5);
    }
}

//! Pixel reconstruction filters, used by importance sampling (pbrt-v4's approach): each camera
//! sample is offset from the pixel centre by a draw from |f|, weighted f/pdf, and only touches its
//! own pixel. Splatting nothing across pixels keeps tiles independent and renders deterministic.

use glam::Vec2;

/// Table resolution per unit of filter radius.
const TABLE_PER_UNIT: usize = 64;

/// A separable reconstruction filter f(x, y) = f₁(x) f₁(y).
#[derive(Clone, Debug)]
pub struct Filter {
    kind: FilterKind,
    radius: f32,
    /// |f₁| tabulated over [-radius, radius] and its normalised CDF (piecewise constant).
    table: Vec<f32>,
    cdf: Vec<f32>,
    integral: f32,
}

/// The filter families prism offers (`--filter`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterKind {
    /// Box of half-width `radius` (default 0.5): plain pixel averaging.
    Box,
    /// Gaussian with standard deviation `sigma`, truncated at `radius` and shifted to 0 there.
    Gaussian {
        /// Standard deviation [pixels].
        sigma: f32,
    },
    /// Mitchell–Netravali cubic with parameters B, C (1/3, 1/3 recommended), negative lobes.
    Mitchell {
        /// B parameter.
        b: f32,
        /// C parameter.
        c: f32,
    },
}

impl Filter {
    /// Builds the filter and its sampling table.
    pub fn new(kind: FilterKind, radius: f32) -> Self {
        let radius = radius.max(1e-3);
        let n = ((2.0 * radius) * TABLE_PER_UNIT as f32).ceil().max(2.0) as usize;
        let mut f = Filter { kind, radius, table: Vec::new(), cdf: Vec::new(), integral: 0.0 };
        let dx = 2.0 * radius / n as f32;
        f.table = (0..n).map(|i| f.eval_1d(-radius + (i as f32 + 0.5) * dx)).collect();
        let mut cdf = Vec::with_capacity(n + 1);
        let mut acc = 0.0f32;
        cdf.push(0.0);
        for v in &f.table {
            acc += v.abs() * dx;
            cdf.push(acc);
        }
        f.integral = f.table.iter().map(|v| v * dx).sum();
        for c in cdf.iter_mut() {
            *c /= acc;
        }
        f.cdf = cdf;
        f
    }

    /// pbrt-v4 defaults: box radius 0.5, Gaussian σ = 0.5 radius 1.5, Mitchell radius 2, B = C = 1/3.
    pub fn by_name(name: &str) -> Option<Self> {
        Some(match name {
            "box" => Self::new(FilterKind::Box, 0.5),
            "gaussian" => Self::new(FilterKind::Gaussian { sigma: 0.5 }, 1.5),
            "mitchell" => Self::new(FilterKind::Mitchell { b: 1.0 / 3.0, c: 1.0 / 3.0 }, 2.0),
            _ => return None,
        })
    }

    /// The 1D profile f₁(x).
    pub fn eval_1d(&self, x: f32) -> f32 {
        let r = self.radius;
        if x.abs() > r {
            return 0.0;
        }
        match self.kind {
            FilterKind::Box => 1.0,
            FilterKind::Gaussian { sigma } => {
                let g = |x: f32| (-x * x / (2.0 * sigma * sigma)).exp();
                (g(x) - g(r)).max(0.0)
            }
            FilterKind::Mitchell { b, c } => {
                // Mitchell & Netravali 1988, on x scaled so the support is [-2, 2].
                let x = (2.0 * x / r).abs();
                if x > 1.0 {
                    ((-b - 6.0 * c) * x * x * x
                        + (6.0 * b + 30.0 * c) * x * x
                        + (-12.0 * b - 48.0 * c) * x
                        + (8.0 * b + 24.0 * c))
                        / 6.0
                } else {
                    ((12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b))
                        / 6.0
                }
            }
        }
    }

    /// Samples a 1D offset from |f₁|, returning (x, f₁(x)/pdf(x)) using the tabulated f₁ so
    /// that the weight is piecewise exact.
    fn sample_1d(&self, u: f32) -> (f32, f32) {
        let n = self.table.len();
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let t = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let dx = 2.0 * self.radius / n as f32;
        let x = -self.radius + (i as f32 + t) * dx;
        let pdf = (c1 - c0) / dx;
        let v = self.table[i];
        (x, if pdf > 0.0 { v / pdf } else { 0.0 })
    }

    /// Offset from the pixel centre [pixels] and sample weight f/pdf for `u` in [0,1)².
    /// The weight is constant (= ∫f) for non-negative filters and changes sign on Mitchell's
    /// negative lobes.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        if self.kind == FilterKind::Box {
            return ((u - Vec2::splat(0.5)) * 2.0 * self.radius, 1.0);
        }
        let (x, wx) = self.sample_1d(u.x);
        let (y, wy) = self.sample_1d(u.y);
        (Vec2::new(x, y), wx * wy)
    }

    /// The filter family.
    pub fn kind(&self) -> FilterKind {
        self.kind
    }

    /// ∫f₁ over the support (the weights of a non-negative filter all equal its square).
    pub fn integral_1d(&self) -> f32 {
        self.integral
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn weights_average_to_the_filter_integral() {
        // E[f/pdf] = ∫f over the 2D support: check it for each filter with a fixed seed.
        for name in ["box", "gaussian", "mitchell"] {
            let f = Filter::by_name(name).unwrap();
            let mut rng = Rng::new(5, 0);
            let n = 200_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let (p, w) = f.sample(Vec2::new(rng.uniform(), rng.uniform()));
                assert!(p.x.abs() <= f.radius + 1e-5 && p.y.abs() <= f.radius + 1e-5);
                s += w as f64;
                s2 += (w * w) as f64;
            }
            let mean = s / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            let expected = if name == "box" { 1.0 } else { (f.integral_1d() as f64).powi(2) };
            assert!((mean - expected).abs() <= 4.0 * se + 1e-6, "{name}: {mean} vs {expected} ± {se}");
        }
    }

    #[test]
    fn mitchell_has_negative_lobes_and_unit_dc() {
        let f = Filter::by_name("mitchell").unwrap();
        assert!(f.eval_1d(1.5) < 0.0);
        // Mitchell with 2B+... is normalised: ∫ over [-2,2] in its own units = 1 → here r/2.
        assert!((f.integral_1d() - 1.0).abs() < 1e-3, "{}", f.integral_1d());
    }
}

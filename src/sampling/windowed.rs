//! A piecewise-constant density on [0, 1]² sampled inside any axis-aligned window of it (the
//! sampling routine of pbrt-v4's `WindowedPiecewiseConstant2D`, PBR 4th ed. §A.5.6), from a
//! summed-area table (Crow 1984, "Summed-Area Tables for Texture Mapping").
//!
//! With f constant on each of the `nu × nv` cells, F(u, v) = ∫₀ᵘ∫₀ᵛ f is exactly the bilinear
//! interpolation of the table's corner values, so the integral over a window with fractional
//! cells is four lookups. A sample takes u from the window's marginal M(u) = ∫_{v₀}^{v₁} F_u dv,
//! which is linear on each column (inverted exactly: a binary search over the columns, then one
//! division), and v from the chosen column's cells restricted to [v₀, v₁] likewise.

use glam::Vec2;

/// An axis-aligned window [min, max] of the unit square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    /// Lower corner.
    pub min: Vec2,
    /// Upper corner.
    pub max: Vec2,
}

impl Window {
    /// The window spanned by two opposite corners, in either order, clamped to [0, 1]².
    pub fn spanning(a: Vec2, b: Vec2) -> Self {
        let clamp = |p: Vec2| p.clamp(Vec2::ZERO, Vec2::ONE);
        Self { min: clamp(a.min(b)), max: clamp(a.max(b)) }
    }

    /// True when `p` lies in the closed window.
    pub fn contains(&self, p: Vec2) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// f ≥ 0 on an `nu × nv` grid of cells over [0, 1]², with its summed-area table.
#[derive(Clone, Debug)]
pub struct WindowedDistribution2D {
    nu: usize,
    nv: usize,
    /// f per cell, row-major (v rows).
    f: Vec<f32>,
    /// sat[j (nu + 1) + i] = Σ f over cells (x < i, y < j), in cell units.
    sat: Vec<f64>,
}

impl WindowedDistribution2D {
    /// The density ∝ `f[v * nu + u]` (negative and non-finite values count as 0).
    pub fn new(f: &[f32], nu: usize, nv: usize) -> Self {
        let (nu, nv) = (nu.max(1), nv.max(1));
        let f: Vec<f32> =
            (0..nu * nv).map(|i| f.get(i).copied().filter(|x| x.is_finite()).unwrap_or(0.0).max(0.0)).collect();
        let mut sat = vec![0f64; (nu + 1) * (nv + 1)];
        for y in 0..nv {
            let mut row = 0f64;
            for x in 0..nu {
                row += f[y * nu + x] as f64;
                sat[(y + 1) * (nu + 1) + x + 1] = sat[y * (nu + 1) + x + 1] + row;
            }
        }
        Self { nu, nv, f, sat }
    }

    /// Σ f over the cells left of column boundary `i` and below row boundary `j`.
    #[inline]
    fn sat(&self, i: usize, j: usize) -> f64 {
        self.sat[j * (self.nu + 1) + i]
    }

    /// The window in cell units.
    fn cells(&self, w: &Window) -> (f64, f64, f64, f64) {
        let (nu, nv) = (self.nu as f64, self.nv as f64);
        (w.min.x as f64 * nu, w.max.x as f64 * nu, w.min.y as f64 * nv, w.max.y as f64 * nv)
    }

    /// The window's marginal in x at the column boundaries: M(i) = F(i, y₁) − F(i, y₀), the
    /// table's rows interpolated once for the window's y₀ and y₁.
    fn marginal(&self, y0: f64, y1: f64) -> impl Fn(usize) -> f64 + '_ {
        let row = |y: f64| {
            let j = (y.floor().max(0.0) as usize).min(self.nv - 1);
            (j, (y - j as f64).clamp(0.0, 1.0))
        };
        let ((j0, t0), (j1, t1)) = (row(y0), row(y1));
        move |i| {
            let f = |j: usize, t: f64| self.sat(i, j) * (1.0 - t) + self.sat(i, j + 1) * t;
            f(j1, t1) - f(j0, t0)
        }
    }

    /// ∫∫ f du dv over the window.
    pub fn integral(&self, w: &Window) -> f64 {
        let (x0, x1, y0, y1) = self.cells(w);
        let m = self.marginal(y0, y1);
        let cells = at(&m, x1, self.nu) - at(&m, x0, self.nu);
        cells.max(0.0) / (self.nu * self.nv) as f64
    }

    /// A point of the window with density f/∫_window f, and that density (per unit area of
    /// [0, 1]²); `None` where f is zero over the whole window.
    pub fn sample(&self, u: Vec2, w: &Window) -> Option<(Vec2, f32)> {
        let (x0, x1, y0, y1) = self.cells(w);
        // x: invert the marginal, linear on each column.
        let (x, total) = invert_piecewise_linear(self.marginal(y0, y1), x0, x1, self.nu, u.x as f64)?;
        let column = (x.floor() as usize).min(self.nu - 1);
        // y: the column's cells restricted to [y₀, y₁].
        let conditional = |j: usize| self.sat(column + 1, j) - self.sat(column, j);
        let (y, _) = invert_piecewise_linear(conditional, y0, y1, self.nv, u.y as f64)?;
        let p = Vec2::new((x / self.nu as f64) as f32, (y / self.nv as f64) as f32).clamp(w.min, w.max);
        let row = ((p.y * self.nv as f32) as usize).min(self.nv - 1);
        let cell = self.f[row * self.nu + ((p.x * self.nu as f32) as usize).min(self.nu - 1)];
        let pdf = (cell as f64 * (self.nu * self.nv) as f64 / total) as f32;
        (pdf > 0.0).then_some((p, pdf))
    }

    /// The density of [`Self::sample`] at `p` (0 outside the window).
    pub fn pdf(&self, p: Vec2, w: &Window) -> f32 {
        if !w.contains(p) {
            return 0.0;
        }
        let total = self.integral(w);
        if total.is_nan() || total <= 0.0 {
            return 0.0;
        }
        let x = ((p.x * self.nu as f32) as usize).min(self.nu - 1);
        let y = ((p.y * self.nv as f32) as usize).min(self.nv - 1);
        (self.f[y * self.nu + x] as f64 / total) as f32
    }
}

/// g at x ∈ [0, n], from its values at the integers (g is linear between them).
fn at(g: impl Fn(usize) -> f64, x: f64, n: usize) -> f64 {
    let i = (x.floor().max(0.0) as usize).min(n - 1);
    let (g0, g1) = (g(i), g(i + 1));
    g0 + (x - i as f64).clamp(0.0, 1.0) * (g1 - g0)
}

/// The x ∈ [a, b] where the non-decreasing `g`, given at the integers 0..=n and linear between
/// them, reaches g(a) + ξ (g(b) − g(a)), and g(b) − g(a): a binary search for the first
/// integer at or above the target, then the linear piece solved. Pieces of zero slope are
/// skipped, so x never lands where f is zero.
fn invert_piecewise_linear(g: impl Fn(usize) -> f64, a: f64, b: f64, n: usize, xi: f64) -> Option<(f64, f64)> {
    let (ga, gb) = (at(&g, a, n), at(&g, b, n));
    if gb.is_nan() || gb <= ga {
        return None;
    }
    let target = ga + xi.clamp(0.0, 1.0) * (gb - ga);
    // Breakpoints a < ⌊a⌋+1 < … < ⌈b⌉−1 < b; find the first piece whose end reaches the target.
    let value = |k: i64| {
        if k as f64 <= a {
            ga
        } else if k as f64 >= b {
            gb
        } else {
            g(k as usize)
        }
    };
    let (mut lo, mut hi) = (a.floor() as i64, b.ceil() as i64);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if value(mid) >= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let (x0, x1) = ((lo as f64).clamp(a, b), (hi as f64).clamp(a, b));
    let (g0, g1) = (value(lo), value(hi));
    let x = if g1 > g0 { x0 + (target - g0) / (g1 - g0) * (x1 - x0) } else { x1 };
    Some((x.clamp(x0, x1), gb - ga))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::alias::tests::chi2_critical;
    use crate::sampling::Rng;

    /// A 7 × 5 grid with zeros, a bright cell and distinct values elsewhere.
    fn grid() -> (Vec<f32>, usize, usize) {
        let (nu, nv) = (7, 5);
        let f = (0..nu * nv)
            .map(|i| if i % 6 == 0 { 0.0 } else { 1.0 + (i % 5) as f32 + 20.0 * (i == 17) as u8 as f32 })
            .collect();
        (f, nu, nv)
    }

    /// ∫ f over the window by brute force: each cell's value times its overlap with the window.
    fn overlap_integral(f: &[f32], nu: usize, nv: usize, w: &Window) -> f64 {
        let mut sum = 0.0;
        for y in 0..nv {
            for x in 0..nu {
                let (cx0, cx1) = (x as f64 / nu as f64, (x + 1) as f64 / nu as f64);
                let (cy0, cy1) = (y as f64 / nv as f64, (y + 1) as f64 / nv as f64);
                let ox = (cx1.min(w.max.x as f64) - cx0.max(w.min.x as f64)).max(0.0);
                let oy = (cy1.min(w.max.y as f64) - cy0.max(w.min.y as f64)).max(0.0);
                sum += f[y * nu + x] as f64 * ox * oy;
            }
        }
        sum
    }

    fn windows() -> [Window; 4] {
        [
            Window::spanning(Vec2::ZERO, Vec2::ONE),
            Window::spanning(Vec2::new(0.13, 0.61), Vec2::new(0.77, 0.22)),
            Window::spanning(Vec2::new(0.30, 0.41), Vec2::new(0.33, 0.47)),
            Window::spanning(Vec2::new(0.0, 0.9), Vec2::new(0.5, 1.0)),
        ]
    }

    #[test]
    fn window_integrals_equal_the_cell_overlaps() {
        let (f, nu, nv) = grid();
        let d = WindowedDistribution2D::new(&f, nu, nv);
        for w in windows() {
            let want = overlap_integral(&f, nu, nv, &w);
            assert!((d.integral(&w) - want).abs() < 1e-9 * want.max(1.0), "{w:?}: {} vs {want}", d.integral(&w));
        }
    }

    /// χ² of samples against the expected counts on a 4 × 4 subdivision of the window, each
    /// cell's probability its brute-force overlap integral over the window's.
    #[test]
    fn samples_follow_f_inside_each_window_chi2() {
        let (f, nu, nv) = grid();
        let d = WindowedDistribution2D::new(&f, nu, nv);
        let mut rng = Rng::new(11, 3);
        let n = 200_000;
        for w in windows() {
            let k = 4;
            let mut counts = vec![0f64; k * k];
            for _ in 0..n {
                let (p, pdf) = d.sample(Vec2::new(rng.uniform(), rng.uniform()), &w).expect("window has mass");
                assert!(w.contains(p), "{p} outside {w:?}");
                assert!((pdf - d.pdf(p, &w)).abs() <= 1e-5 * pdf, "pdf {pdf} vs {}", d.pdf(p, &w));
                let size = w.max - w.min;
                let q = ((p - w.min) / size * k as f32).as_uvec2().min(glam::UVec2::splat(k as u32 - 1));
                counts[q.y as usize * k + q.x as usize] += 1.0;
            }
            let total = overlap_integral(&f, nu, nv, &w);
            let (mut chi2, mut dof) = (0.0, 0usize);
            for j in 0..k {
                for i in 0..k {
                    let a = w.min + (w.max - w.min) * Vec2::new(i as f32, j as f32) / k as f32;
                    let b = w.min + (w.max - w.min) * Vec2::new((i + 1) as f32, (j + 1) as f32) / k as f32;
                    let expected = n as f64 * overlap_integral(&f, nu, nv, &Window { min: a, max: b }) / total;
                    let observed = counts[j * k + i];
                    if expected == 0.0 {
                        assert_eq!(observed, 0.0, "samples where f is zero");
                        continue;
                    }
                    chi2 += (observed - expected).powi(2) / expected;
                    dof += 1;
                }
            }
            let critical = chi2_critical((dof - 1) as f64, 3.09);
            assert!(chi2 < critical, "{w:?}: χ² = {chi2:.1} ≥ {critical:.1} (dof {})", dof - 1);
        }
    }

    #[test]
    fn the_density_integrates_to_one_over_the_window_and_is_zero_outside() {
        let (f, nu, nv) = grid();
        let d = WindowedDistribution2D::new(&f, nu, nv);
        let w = windows()[1];
        let m = 400;
        let mut sum = 0.0;
        for j in 0..m {
            for i in 0..m {
                let p = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                sum += d.pdf(p, &w) as f64 / (m * m) as f64;
            }
        }
        assert!((sum - 1.0).abs() < 0.02, "∫ pdf = {sum}");
        assert_eq!(d.pdf(Vec2::new(0.9, 0.9), &w), 0.0);
        let black = WindowedDistribution2D::new(&[0.0; 4], 2, 2);
        assert!(black.sample(Vec2::splat(0.5), &windows()[0]).is_none());
    }
}

//! Pixel reconstruction filters, used by importance sampling (pbrt-v4's approach): each camera
//! sample is offset from the pixel centre by a draw from |f|, weighted f/pdf, and only touches its
//! own pixel. Splatting nothing across pixels keeps tiles independent and renders deterministic.

use glam::Vec2;

/// Table resolution per unit of filter radius.
const TABLE_PER_UNIT: usize = 64;

/// A separable reconstruction filter f(x, y) = f₁(x; r_x) f₁(y; r_y), radii per axis as
/// pbrt-v4's `xradius`/`yradius`.
#[derive(Clone, Debug)]
pub struct Filter {
    kind: FilterKind,
    radius: Vec2,
    x: Profile,
    y: Profile,
}

/// One axis of a filter: |f₁| tabulated over [−r, r], its normalised CDF (piecewise constant)
/// and the integral of the signed f₁. `guide[k]` is the table segment where the CDF reaches
/// k/len, so that inverting the CDF starts a short walk there instead of a binary search (a
/// guide table, Chen & Wang 1974): each camera sample inverts two profiles.
#[derive(Clone, Debug)]
struct Profile {
    radius: f32,
    table: Vec<f32>,
    cdf: Vec<f32>,
    guide: Vec<u32>,
    integral: f32,
}

/// The filter families of pbrt-v4 (`PixelFilter`, `--filter`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterKind {
    /// Box: plain pixel averaging (default radius 0.5).
    Box,
    /// Gaussian with standard deviation `sigma`, truncated at the radius and shifted to 0 there.
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
    /// Lanczos windowed sinc, sinc(x)·sinc(x/τ) (pbrt-v4's `sinc`), negative lobes.
    LanczosSinc {
        /// Number of cycles of the window, τ.
        tau: f32,
    },
    /// Triangle (tent), r − |x|.
    Triangle,
}

/// sin(πx)/(πx).
fn sinc(x: f32) -> f32 {
    if x.abs() < 1e-5 {
        1.0
    } else {
        let px = std::f32::consts::PI * x;
        px.sin() / px
    }
}

impl FilterKind {
    /// The 1D profile f₁(x) of support [−r, r].
    fn eval(self, x: f32, r: f32) -> f32 {
        if x.abs() > r {
            return 0.0;
        }
        match self {
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
            FilterKind::LanczosSinc { tau } => sinc(x) * sinc(x / tau),
            FilterKind::Triangle => r - x.abs(),
        }
    }

    /// pbrt-v4's default radius of this family [pixels].
    pub fn default_radius(self) -> f32 {
        match self {
            FilterKind::Box => 0.5,
            FilterKind::Gaussian { .. } => 1.5,
            FilterKind::Mitchell { .. } | FilterKind::Triangle => 2.0,
            FilterKind::LanczosSinc { .. } => 4.0,
        }
    }
}

impl Profile {
    fn new(kind: FilterKind, radius: f32) -> Self {
        let n = ((2.0 * radius) * TABLE_PER_UNIT as f32).ceil().max(2.0) as usize;
        let dx = 2.0 * radius / n as f32;
        let table: Vec<f32> = (0..n).map(|i| kind.eval(-radius + (i as f32 + 0.5) * dx, radius)).collect();
        let mut cdf = Vec::with_capacity(n + 1);
        let mut acc = 0.0f32;
        cdf.push(0.0);
        for v in &table {
            acc += v.abs() * dx;
            cdf.push(acc);
        }
        for c in cdf.iter_mut() {
            *c /= acc;
        }
        let integral = table.iter().map(|v| v * dx).sum();
        let guide =
            (0..n).map(|k| (cdf.partition_point(|&c| c <= k as f32 / n as f32).clamp(1, n) - 1) as u32).collect();
        Self { radius, table, cdf, guide, integral }
    }

    /// The last segment i < n with cdf[i] ≤ u, walked to from the guide's start.
    #[inline]
    fn segment(&self, u: f32) -> usize {
        let n = self.table.len();
        let mut i = self.guide[((u * n as f32) as usize).min(n - 1)] as usize;
        while i > 0 && self.cdf[i] > u {
            i -= 1;
        }
        while i + 1 < n && self.cdf[i + 1] <= u {
            i += 1;
        }
        i
    }

    /// Samples an offset from |f₁|, returning (x, f₁(x)/pdf(x)) using the tabulated f₁ so
    /// that the weight is piecewise exact.
    fn sample(&self, u: f32) -> (f32, f32) {
        let n = self.table.len();
        let i = self.segment(u);
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let t = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let dx = 2.0 * self.radius / n as f32;
        let x = -self.radius + (i as f32 + t) * dx;
        let pdf = (c1 - c0) / dx;
        let v = self.table[i];
        (x, if pdf > 0.0 { v / pdf } else { 0.0 })
    }
}

impl Filter {
    /// Builds the filter of radius `radius` [pixels] on both axes, and its sampling tables.
    pub fn new(kind: FilterKind, radius: f32) -> Self {
        Self::with_radii(kind, Vec2::splat(radius))
    }

    /// Builds the filter with radii `radius.x`, `radius.y` [pixels] (each at least 10⁻³).
    pub fn with_radii(kind: FilterKind, radius: Vec2) -> Self {
        let radius = radius.max(Vec2::splat(1e-3));
        Self { kind, radius, x: Profile::new(kind, radius.x), y: Profile::new(kind, radius.y) }
    }

    /// The family `name` with pbrt-v4's default parameters: box radius 0.5; Gaussian σ = 0.5
    /// radius 1.5; Mitchell radius 2, B = C = 1/3; sinc (Lanczos) radius 4, τ = 3; triangle
    /// radius 2.
    pub fn kind_by_name(name: &str) -> Option<FilterKind> {
        Some(match name {
            "box" => FilterKind::Box,
            "gaussian" => FilterKind::Gaussian { sigma: 0.5 },
            "mitchell" => FilterKind::Mitchell { b: 1.0 / 3.0, c: 1.0 / 3.0 },
            "sinc" | "lanczos" => FilterKind::LanczosSinc { tau: 3.0 },
            "triangle" => FilterKind::Triangle,
            _ => return None,
        })
    }

    /// The filter `name` with pbrt-v4's defaults ([`Filter::kind_by_name`]).
    pub fn by_name(name: &str) -> Option<Self> {
        let kind = Self::kind_by_name(name)?;
        Some(Self::new(kind, kind.default_radius()))
    }

    /// The 1D profile f₁(x) along x.
    pub fn eval_1d(&self, x: f32) -> f32 {
        self.kind.eval(x, self.radius.x)
    }

    /// f(x, y).
    pub fn eval(&self, p: Vec2) -> f32 {
        self.kind.eval(p.x, self.radius.x) * self.kind.eval(p.y, self.radius.y)
    }

    /// Offset from the pixel centre [pixels] and sample weight f/pdf for `u` in [0,1)².
    /// The weight is constant (= ∫f) for non-negative filters and changes sign on negative
    /// lobes.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        if self.kind == FilterKind::Box {
            return ((u - Vec2::splat(0.5)) * 2.0 * self.radius, 1.0);
        }
        let (x, wx) = self.x.sample(u.x);
        let (y, wy) = self.y.sample(u.y);
        (Vec2::new(x, y), wx * wy)
    }

    /// The filter family.
    pub fn kind(&self) -> FilterKind {
        self.kind
    }

    /// The radii [pixels].
    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    /// ∫f over the support (a non-negative filter's weights all equal it).
    pub fn integral(&self) -> f32 {
        if self.kind == FilterKind::Box {
            return 1.0;
        }
        self.x.integral * self.y.integral
    }

    /// ∫f₁ along x over the support.
    pub fn integral_1d(&self) -> f32 {
        self.x.integral
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn weights_average_to_the_filter_integral() {
        // E[f/pdf] = ∫f over the 2D support: check it for each filter with a fixed seed.
        let stretched = Filter::with_radii(FilterKind::Gaussian { sigma: 0.8 }, Vec2::new(2.5, 1.0));
        let filters = ["box", "gaussian", "mitchell", "sinc", "triangle"].map(|n| (n, Filter::by_name(n).unwrap()));
        for (name, f) in filters.into_iter().chain([("stretched gaussian", stretched)]) {
            let mut rng = Rng::new(5, 0);
            let n = 200_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let (p, w) = f.sample(Vec2::new(rng.uniform(), rng.uniform()));
                assert!(p.x.abs() <= f.radius.x + 1e-5 && p.y.abs() <= f.radius.y + 1e-5);
                s += w as f64;
                s2 += (w * w) as f64;
            }
            let mean = s / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            let expected = f64::from(f.integral());
            assert!((mean - expected).abs() <= 4.0 * se + 1e-6, "{name}: {mean} vs {expected} ± {se}");
        }
    }

    #[test]
    fn the_guide_table_finds_the_segment_a_binary_search_finds() {
        let mut rng = Rng::new(9, 0);
        for name in ["gaussian", "mitchell", "sinc", "triangle"] {
            let p = &Filter::by_name(name).unwrap().x;
            let n = p.table.len();
            let probes = (0..=4 * n).map(|k| k as f32 / (4 * n) as f32).chain(p.cdf.iter().copied());
            for u in probes.chain((0..20_000).map(|_| rng.uniform())).filter(|&u| u < 1.0) {
                let i = p.cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
                assert_eq!(p.segment(u), i, "{name} u = {u}");
            }
        }
    }

    #[test]
    fn profiles_by_hand() {
        // Triangle radius 2: f₁(0.5) = 1.5, ∫ = r² = 4.
        let t = Filter::by_name("triangle").unwrap();
        assert_eq!(t.eval_1d(0.5), 1.5);
        assert!((t.integral_1d() - 4.0).abs() < 1e-3, "{}", t.integral_1d());
        // Lanczos: 1 at 0, zero at the integers, negative on (1, 2).
        let l = Filter::by_name("sinc").unwrap();
        assert!((l.eval_1d(0.0) - 1.0).abs() < 1e-6);
        assert!(l.eval_1d(1.0).abs() < 1e-6 && l.eval_1d(2.0).abs() < 1e-6 && l.eval_1d(1.5) < 0.0);
        assert_eq!(l.eval_1d(4.5), 0.0);
        // Separate radii: a Gaussian 2.5 wide in x and 1 in y vanishes at y = 1.2 but not at x = 1.2.
        let g = Filter::with_radii(FilterKind::Gaussian { sigma: 0.8 }, Vec2::new(2.5, 1.0));
        assert!(g.eval(Vec2::new(1.2, 0.0)) > 0.0 && g.eval(Vec2::new(0.0, 1.2)) == 0.0);
    }

    #[test]
    fn mitchell_has_negative_lobes_and_unit_dc() {
        let f = Filter::by_name("mitchell").unwrap();
        assert!(f.eval_1d(1.5) < 0.0);
        // Mitchell with 2B+... is normalised: ∫ over [-2,2] in its own units = 1 → here r/2.
        assert!((f.integral_1d() - 1.0).abs() < 1e-3, "{}", f.integral_1d());
    }
}

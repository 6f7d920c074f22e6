//! `Spectrum`: a spectral power distribution (or reflectance) as a function of wavelength.
//! A closed set, so an enum: evaluation is a `match`
//! and tables sit behind `Arc`, making `clone` cheap.

use super::blackbody::{blackbody_normalised, blackbody_peak_radiance};
use super::cie::{xyz_of, CIE_LAMBDA_MAX, CIE_LAMBDA_MIN};
use super::sampled::{SampledSpectrum, SampledWavelengths};
use super::sigmoid::{normalised_wavelengths, SigmoidPolynomial};
use glam::{DVec3, Vec3, Vec4};
use std::sync::Arc;

/// Samples (λᵢ [nm], vᵢ) of a piecewise-linear function, zero outside [λ₀, λₙ₋₁]
/// (pbrt-v4 `PiecewiseLinearSpectrum`). Wavelengths strictly increasing.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear {
    lambda: Vec<f64>,
    value: Vec<f64>,
    /// Segment lookup in O(1): the range is cut into equal cells and each cell stores the
    /// segment that holds its left edge, so a lookup starts at most a knot or two before the
    /// answer instead of binary-searching the whole table (this runs per wavelength per hit).
    cell_segment: Vec<u32>,
    /// Cells per nm.
    cells_per_nm: f64,
    /// When every knot lies on a whole nm, the function at every whole nm from λ₀ to λₙ₋₁:
    /// interpolating these is the same function (each 1-nm step lies within one segment), found
    /// with no search at all. Measured data comes on such grids.
    per_nm: Option<Vec<f64>>,
    /// `per_nm` in single precision, for [`Self::sample4`].
    per_nm_f32: Option<Vec<f32>>,
}

impl PiecewiseLinear {
    /// From strictly increasing wavelengths [nm] and values; `None` if the lengths differ,
    /// there are fewer than two samples, a value is not finite or the wavelengths do not
    /// increase.
    pub fn new(lambda: Vec<f64>, value: Vec<f64>) -> Option<Self> {
        let ok = lambda.len() == value.len()
            && lambda.len() >= 2
            && lambda.iter().chain(&value).all(|v| v.is_finite())
            && lambda.windows(2).all(|w| w[0] < w[1]);
        if !ok {
            return None;
        }
        // About two cells per knot: with evenly spaced knots each cell holds at most one.
        let n = lambda.len();
        let span = lambda[n - 1] - lambda[0];
        let cells = (2 * n).clamp(64, 1 << 16);
        let cells_per_nm = cells as f64 / span;
        let mut cell_segment = Vec::with_capacity(cells);
        let mut i = 0;
        for c in 0..cells {
            let edge = lambda[0] + c as f64 / cells_per_nm;
            while i + 2 < n && lambda[i + 1] <= edge {
                i += 1;
            }
            cell_segment.push(i as u32);
        }
        let mut p = Self { lambda, value, cell_segment, cells_per_nm, per_nm: None, per_nm_f32: None };
        if p.lambda.iter().all(|l| l.fract() == 0.0) && span <= 10_000.0 {
            let v: Vec<f64> = (0..=span as usize).map(|i| p.eval(p.lambda[0] + i as f64)).collect();
            p.per_nm_f32 = Some(v.iter().map(|&x| x as f32).collect());
            p.per_nm = Some(v);
        }
        Some(p)
    }
    /// Wavelengths [nm].
    pub fn lambdas(&self) -> &[f64] {
        &self.lambda
    }
    /// Values at [`Self::lambdas`].
    pub fn values(&self) -> &[f64] {
        &self.value
    }
    /// Linear interpolation, 0 outside the sampled range.
    #[inline]
    pub fn eval(&self, l: f64) -> f64 {
        let n = self.lambda.len();
        if !(l >= self.lambda[0] && l <= self.lambda[n - 1]) {
            return 0.0;
        }
        if let Some(v) = &self.per_nm {
            let x = l - self.lambda[0];
            let i = (x as usize).min(v.len() - 2);
            return v[i] + (x - i as f64) * (v[i + 1] - v[i]);
        }
        // The last segment whose left knot is ≤ l (the binary search's answer, found from the
        // cell's first segment by a short forward walk).
        let cell = (((l - self.lambda[0]) * self.cells_per_nm) as usize).min(self.cell_segment.len() - 1);
        let mut i = self.cell_segment[cell] as usize;
        // (Rounding can put l a hair left of its cell's edge, and of a knot on that edge.)
        while i > 0 && self.lambda[i] > l {
            i -= 1;
        }
        while i + 2 < n && self.lambda[i + 1] <= l {
            i += 1;
        }
        let (l0, l1) = (self.lambda[i], self.lambda[i + 1]);
        let t = (l - l0) / (l1 - l0);
        self.value[i] + t * (self.value[i + 1] - self.value[i])
    }
    /// The function at four wavelengths [nm], in single precision: on a whole-nm grid one
    /// table step per wavelength (this runs for every light and metal spectrum at every hit),
    /// otherwise [`Self::eval`].
    #[inline]
    pub fn sample4(&self, lambda: [f32; 4]) -> Vec4 {
        let Some(v) = &self.per_nm_f32 else {
            return Vec4::from_array(lambda.map(|l| self.eval(l as f64) as f32));
        };
        // The four table positions at once: the segment is ⌊x⌋ (the last one at the end).
        let last = Vec4::splat((v.len() - 1) as f32);
        let x = Vec4::from_array(lambda) - Vec4::splat(self.lambda[0] as f32);
        let inside = x.cmpge(Vec4::ZERO) & x.cmple(last);
        let x = x.clamp(Vec4::ZERO, last);
        let left = x.floor().min(last - 1.0);
        let (i, t) = (left.as_uvec4().to_array(), x - left);
        let ends = |k: usize| (v[i[k] as usize], v[i[k] as usize + 1]);
        let [(a0, b0), (a1, b1), (a2, b2), (a3, b3)] = [ends(0), ends(1), ends(2), ends(3)];
        let (a, b) = (Vec4::new(a0, a1, a2, a3), Vec4::new(b0, b1, b2, b3));
        Vec4::select(inside, a + t * (b - a), Vec4::ZERO)
    }
    fn scale(&mut self, s: f64) {
        self.value.iter_mut().chain(self.per_nm.iter_mut().flatten()).for_each(|v| *v *= s);
        self.per_nm_f32 = self.per_nm.as_ref().map(|v| v.iter().map(|&x| x as f32).collect());
    }
}

/// A piecewise-constant function: value `vᵢ` on [eᵢ, eᵢ₊₁), 0 outside [e₀, eₙ] (edges [nm]).
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant {
    edges: Vec<f64>,
    value: Vec<f64>,
}

impl PiecewiseConstant {
    /// From n+1 strictly increasing edges [nm] and n values; `None` if malformed.
    pub fn new(edges: Vec<f64>, value: Vec<f64>) -> Option<Self> {
        let ok = edges.len() == value.len() + 1
            && !value.is_empty()
            && edges.iter().chain(&value).all(|v| v.is_finite())
            && edges.windows(2).all(|w| w[0] < w[1]);
        ok.then_some(Self { edges, value })
    }
    /// Bin edges [nm].
    pub fn edges(&self) -> &[f64] {
        &self.edges
    }
    /// Value per bin.
    pub fn values(&self) -> &[f64] {
        &self.value
    }
    /// The bin's value, 0 outside the edges (the last edge belongs to the last bin).
    pub fn eval(&self, l: f64) -> f64 {
        let n = self.edges.len();
        if !(l >= self.edges[0] && l <= self.edges[n - 1]) {
            return 0.0;
        }
        let i = self.edges.partition_point(|&x| x <= l).clamp(1, n - 1) - 1;
        self.value[i]
    }
}

/// How an RGB triplet is turned into a spectrum (pbrt-v4's three RGB spectrum classes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RgbKind {
    /// A reflectance in [0, 1]: the sigmoid spectrum itself.
    Albedo,
    /// Any non-negative quantity: 2·max(rgb) times the sigmoid fitted to rgb / (2·max).
    Unbounded,
    /// Emission: the unbounded spectrum times the colour space's white illuminant.
    Illuminant,
}

/// A spectral distribution over wavelength [nm]. Values are in whatever unit the user gives
/// (radiance, reflectance, ...); see each constructor.
#[derive(Clone, Debug)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// Tabulated, linear between samples, 0 outside.
    PiecewiseLinear(Arc<PiecewiseLinear>),
    /// Tabulated bins, 0 outside.
    PiecewiseConstant(Arc<PiecewiseConstant>),
    /// Planck's law at `kelvin`, divided by its value at the Wien peak (max = 1).
    Blackbody {
        /// Temperature [K].
        kelvin: f32,
        /// 1 / B(λ_peak, T) [1 / (W sr⁻¹ m⁻² nm⁻¹)], times any factor applied by `scaled`.
        inv_peak: f64,
    },
    /// `scale` · sigmoid(polynomial(λ)) (Jakob & Hanika 2019).
    Sigmoid {
        /// The sigmoid polynomial.
        poly: SigmoidPolynomial,
        /// Multiplier (1 for albedo, 2·max(rgb) for unbounded/illuminant).
        scale: f32,
    },
    /// The product of two spectra (e.g. an RGB-derived shape times a white illuminant).
    Product(Arc<(Spectrum, Spectrum)>),
}

impl Spectrum {
    /// `v` at every wavelength.
    pub fn constant(v: f32) -> Self {
        Spectrum::Constant(v)
    }

    /// Blackbody emission at `kelvin`, normalised so that its maximum over λ is 1
    /// (pbrt-v4 `BlackbodySpectrum`). Non-positive or non-finite temperatures give 0.
    pub fn blackbody(kelvin: f32) -> Self {
        if !(kelvin > 0.0 && kelvin.is_finite()) {
            return Spectrum::Constant(0.0);
        }
        Spectrum::Blackbody { kelvin, inv_peak: 1.0 / blackbody_peak_radiance(kelvin as f64) }
    }

    /// The piecewise-linear function through (`lambdas[i]` [nm], `values[i]`), zero outside.
    /// `None` for fewer than two samples, mismatched lengths, non-finite values or wavelengths
    /// that do not strictly increase.
    pub fn piecewise_linear(lambdas: &[f32], values: &[f32]) -> Option<Self> {
        let l = lambdas.iter().map(|&x| x as f64).collect();
        let v = values.iter().map(|&x| x as f64).collect();
        PiecewiseLinear::new(l, v).map(|p| Spectrum::PiecewiseLinear(Arc::new(p)))
    }

    /// Piecewise-linear from double-precision samples (see [`Self::piecewise_linear`]).
    pub fn piecewise_linear_f64(lambdas: Vec<f64>, values: Vec<f64>) -> Option<Self> {
        PiecewiseLinear::new(lambdas, values).map(|p| Spectrum::PiecewiseLinear(Arc::new(p)))
    }

    /// Piecewise-constant: `values[i]` on [`edges[i]`, `edges[i+1]`) [nm], zero outside.
    pub fn piecewise_constant(edges: Vec<f64>, values: Vec<f64>) -> Option<Self> {
        PiecewiseConstant::new(edges, values).map(|p| Spectrum::PiecewiseConstant(Arc::new(p)))
    }

    /// The value at `lambda` [nm].
    pub fn eval(&self, lambda: f32) -> f32 {
        self.eval_f64(lambda as f64) as f32
    }

    /// The value at `lambda` [nm], in double precision (used by the exact integrals).
    pub fn eval_f64(&self, l: f64) -> f64 {
        match self {
            Spectrum::Constant(v) => *v as f64,
            Spectrum::PiecewiseLinear(p) => p.eval(l),
            Spectrum::PiecewiseConstant(p) => p.eval(l),
            Spectrum::Blackbody { kelvin, inv_peak } => blackbody_normalised(l, *kelvin as f64, *inv_peak),
            Spectrum::Sigmoid { poly, scale } => *scale as f64 * poly.eval_f64(l),
            Spectrum::Product(p) => p.0.eval_f64(l) * p.1.eval_f64(l),
        }
    }

    /// pbrt-v4's `DenselySampledSpectrum` for what is evaluated at every light sample: the
    /// values at each whole nm of 360–830 nm, linear in between, so a blackbody's exponential or
    /// a product of spectra costs a table lookup. The relative error is at most
    /// (1 nm)² · max |S''/S| / 8: below 1e-4 for blackbodies from 2700 K up (largest at 360 nm,
    /// where |B''/B| ≈ 5.5e-4 nm⁻² at 2700 K). Constants and tables are returned as they are.
    pub fn densely_sampled(&self) -> Spectrum {
        match self {
            Spectrum::Constant(_) | Spectrum::PiecewiseLinear(_) | Spectrum::PiecewiseConstant(_) => self.clone(),
            _ => {
                let lambdas: Vec<f64> = (CIE_LAMBDA_MIN as u32..=CIE_LAMBDA_MAX as u32).map(f64::from).collect();
                let values = lambdas.iter().map(|&l| self.eval_f64(l)).collect();
                Spectrum::piecewise_linear_f64(lambdas, values).unwrap_or_else(|| self.clone())
            }
        }
    }

    /// The values at the four wavelengths of `w`.
    #[inline]
    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        // The common cases dispatch once for all four wavelengths.
        match self {
            Spectrum::Constant(v) => SampledSpectrum::splat(*v),
            Spectrum::PiecewiseLinear(p) => SampledSpectrum(p.sample4(w.lambda)),
            Spectrum::Sigmoid { poly, scale } => {
                SampledSpectrum(poly.sample(normalised_wavelengths(w.lambda)) * *scale)
            }
            _ => SampledSpectrum::new(w.lambda.map(|l| self.eval(l))),
        }
    }

    /// Wavelengths [nm] where the spectrum has a kink or a jump (for exact integration).
    pub fn knots(&self) -> Vec<f64> {
        match self {
            Spectrum::PiecewiseLinear(p) => p.lambdas().to_vec(),
            Spectrum::PiecewiseConstant(p) => p.edges().to_vec(),
            Spectrum::Product(p) => {
                let mut k = p.0.knots();
                k.extend(p.1.knots());
                k
            }
            _ => Vec::new(),
        }
    }

    /// XYZ in the ∫ȳ normalisation of `spectrum::cie`, X = ∫ S x̄ dλ / ∫ ȳ dλ (Y, Z alike),
    /// integrated exactly over the 1 nm CMF table and the spectrum's own knots, in double precision.
    pub fn to_xyz_f64(&self) -> DVec3 {
        xyz_of(|l| self.eval_f64(l), &self.knots())
    }

    /// [`Self::to_xyz_f64`] in single precision.
    pub fn to_xyz(&self) -> Vec3 {
        self.to_xyz_f64().as_vec3()
    }

    /// Luminance Y = ∫ S ȳ / ∫ ȳ.
    pub fn y(&self) -> f32 {
        self.to_xyz_f64().y as f32
    }

    /// `self` times `other`, pointwise.
    pub fn product(self, other: Spectrum) -> Spectrum {
        match (&self, &other) {
            (Spectrum::Constant(a), Spectrum::Constant(b)) => Spectrum::Constant(a * b),
            _ => Spectrum::Product(Arc::new((self, other))),
        }
    }

    /// `self` scaled by `s` (tables are rescaled in place; others become a product).
    pub fn scaled(self, s: f64) -> Spectrum {
        match self {
            Spectrum::Constant(v) => Spectrum::Constant((v as f64 * s) as f32),
            // Fold into the f64 normalisation: a cold blackbody's unit-luminance factor (1e30
            // and beyond) overflows an f32 Constant and would turn 0 · ∞ into NaN.
            Spectrum::Blackbody { kelvin, inv_peak } => Spectrum::Blackbody { kelvin, inv_peak: inv_peak * s },
            Spectrum::PiecewiseLinear(p) => {
                let mut q = (*p).clone();
                q.scale(s);
                Spectrum::PiecewiseLinear(Arc::new(q))
            }
            other => other.product(Spectrum::Constant(s as f32)),
        }
    }

    /// Largest value over 360–830 nm (see [`Spectrum::max_value_over`]).
    pub fn max_value(&self) -> f64 {
        self.max_value_over(360.0, 830.0)
    }

    /// Largest value over [lo, hi] nm: exact for constants and sigmoid spectra (σ increases,
    /// so its maximum is at the polynomial's largest value: an end or the vertex), otherwise
    /// estimated on the ends, the knots and a 1 nm grid.
    pub fn max_value_over(&self, lo: f64, hi: f64) -> f64 {
        match self {
            Spectrum::Constant(v) => f64::from(*v),
            Spectrum::Sigmoid { poly, scale } => {
                let ends = [poly.eval_f64(lo), poly.eval_f64(hi)];
                let vertex = poly.vertex_lambda().filter(|l| (lo..=hi).contains(l)).map(|l| poly.eval_f64(l));
                let values = ends.into_iter().chain(vertex);
                let pick = if *scale >= 0.0 { f64::max } else { f64::min };
                f64::from(*scale) * values.reduce(pick).expect("two ends")
            }
            _ => {
                let grid = (lo.ceil() as i64..=hi.floor() as i64).map(|l| l as f64);
                let mut m = f64::NEG_INFINITY;
                for l in grid.chain([lo, hi]).chain(self.knots()) {
                    if (lo..=hi).contains(&l) {
                        m = m.max(self.eval_f64(l));
                    }
                }
                m
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sigmoid_spectrums_maximum_over_a_band_is_the_largest_of_a_fine_scan() {
        // Polynomials with the vertex inside, left of and right of the band, opening up or down;
        // the scan (0.001 nm) never exceeds the exact value and comes within its step's change.
        let polys = [[-40.0, 30.0, -4.0], [25.0, -20.0, 3.0], [0.0, 3.0, -1.0], [-8.0, 1.0, 0.5], [6.0, 2.0, -2.0]];
        for c in polys {
            let s = Spectrum::Sigmoid { poly: SigmoidPolynomial { c }, scale: 1.7 };
            for (lo, hi) in [(360.0, 830.0), (418.75, 477.5), (536.25, 595.0), (771.25, 830.0)] {
                let steps = ((hi - lo) / 1e-3) as usize;
                let scan =
                    (0..=steps).map(|i| s.eval_f64(lo + (hi - lo) * i as f64 / steps as f64)).fold(0.0, f64::max);
                let exact = s.max_value_over(lo, hi);
                assert!(exact >= scan - 1e-12 && exact - scan < 1e-6, "{c:?} on [{lo}, {hi}]: {exact} vs scan {scan}");
            }
        }
    }

    #[test]
    fn dense_sampling_of_a_blackbody_and_a_product_is_within_1e_4_of_the_formula() {
        let bb = Spectrum::blackbody(2700.0);
        let sigmoid = Spectrum::Sigmoid { poly: SigmoidPolynomial { c: [3.0, -2.0, 0.5] }, scale: 2.0 };
        let product = Spectrum::Product(Arc::new((bb.clone(), sigmoid.clone())));
        for s in [bb, sigmoid, product] {
            let dense = s.densely_sampled();
            assert!(matches!(dense, Spectrum::PiecewiseLinear(_)));
            for i in 0..4700 {
                let l = 360.0 + 0.1 * i as f64 + 0.037;
                let (exact, table) = (s.eval_f64(l), dense.eval_f64(l));
                assert!((table - exact).abs() <= 1e-4 * exact.abs().max(1e-3), "{l} nm: {table} vs {exact}");
            }
        }
        let table = Spectrum::piecewise_linear(&[400.0, 700.0], &[0.2, 0.8]).unwrap();
        assert!(matches!(table.densely_sampled(), Spectrum::PiecewiseLinear(p) if p.lambdas() == [400.0, 700.0]));
    }

    #[test]
    fn piecewise_linear_interpolates_and_is_zero_outside() {
        let s = Spectrum::piecewise_linear(&[400.0, 500.0, 600.0], &[1.0, 3.0, 2.0]).unwrap();
        assert_eq!(s.eval(400.0), 1.0);
        assert_eq!(s.eval(450.0), 2.0);
        assert_eq!(s.eval(550.0), 2.5);
        assert_eq!(s.eval(600.0), 2.0);
        assert_eq!(s.eval(399.9), 0.0);
        assert_eq!(s.eval(600.1), 0.0);
        assert_eq!(s.eval(f32::NAN), 0.0);
    }

    #[test]
    fn cell_lookup_finds_the_binary_search_segment() {
        // Irregular knots (clusters, long gaps, knots on cell edges) against the plain
        // binary-search definition, at random points and exactly at every knot.
        let mut rng = crate::sampling::Rng::new(3, 9);
        for table in 0..50 {
            let n = 2 + table * 7;
            let mut l = vec![360.0 + rng.uniform() as f64];
            for k in 1..n {
                let gap = if k % 5 == 0 { 40.0 * rng.uniform() as f64 } else { 0.01 + rng.uniform() as f64 };
                l.push(l[k - 1] + gap);
            }
            let v: Vec<f64> = (0..n).map(|_| rng.uniform() as f64).collect();
            let p = PiecewiseLinear::new(l.clone(), v.clone()).unwrap();
            let reference = |x: f64| {
                let i = l.partition_point(|&k| k <= x).clamp(1, n - 1) - 1;
                v[i] + (x - l[i]) / (l[i + 1] - l[i]) * (v[i + 1] - v[i])
            };
            let xs = (0..200).map(|_| l[0] + (l[n - 1] - l[0]) * rng.uniform() as f64).chain(l.iter().copied());
            for x in xs {
                assert_eq!(p.eval(x), reference(x), "table {table}, λ = {x}");
            }
        }
    }

    #[test]
    fn whole_nm_tables_interpolate_the_same_function() {
        // Integer knots with gaps of 1–12 nm: the per-nm path against the binary-search
        // definition, to rounding, at random points, at every knot and at the ends.
        let mut rng = crate::sampling::Rng::new(5, 2);
        for table in 0..20 {
            let n = 2 + table * 5;
            let mut l = vec![360.0];
            for k in 1..n {
                l.push(l[k - 1] + 1.0 + (rng.uniform() * 12.0).floor() as f64);
            }
            let v: Vec<f64> = (0..n).map(|_| rng.uniform() as f64).collect();
            let p = PiecewiseLinear::new(l.clone(), v.clone()).unwrap();
            assert!(p.per_nm.is_some());
            let reference = |x: f64| {
                let i = l.partition_point(|&k| k <= x).clamp(1, n - 1) - 1;
                v[i] + (x - l[i]) / (l[i + 1] - l[i]) * (v[i + 1] - v[i])
            };
            let xs = (0..200).map(|_| l[0] + (l[n - 1] - l[0]) * rng.uniform() as f64).chain(l.iter().copied());
            for x in xs {
                assert!((p.eval(x) - reference(x)).abs() <= 1e-14, "table {table}, λ = {x}");
            }
            assert_eq!((p.eval(l[0] - 1e-9), p.eval(l[n - 1] + 1e-9)), (0.0, 0.0));
            // Four at a time in single precision: the same function to f32 rounding, zero
            // outside the range.
            for _ in 0..100 {
                let x = [0.0f32; 4].map(|_| (l[0] - 5.0 + (l[n - 1] - l[0] + 10.0) * rng.uniform() as f64) as f32);
                let got = p.sample4(x);
                for k in 0..4 {
                    let want = if (l[0]..=l[n - 1]).contains(&(x[k] as f64)) { reference(x[k] as f64) } else { 0.0 };
                    assert!((got[k] as f64 - want).abs() <= 1e-6, "table {table}, λ = {}: {} vs {want}", x[k], got[k]);
                }
            }
            assert_eq!(p.sample4([l[0] as f32 - 1e-3, l[n - 1] as f32 + 1e-3, l[0] as f32, l[n - 1] as f32])[0], 0.0);
        }
    }

    #[test]
    fn malformed_tables_are_rejected() {
        assert!(Spectrum::piecewise_linear(&[400.0], &[1.0]).is_none());
        assert!(Spectrum::piecewise_linear(&[400.0, 400.0], &[1.0, 1.0]).is_none());
        assert!(Spectrum::piecewise_linear(&[500.0, 400.0], &[1.0, 1.0]).is_none());
        assert!(Spectrum::piecewise_linear(&[400.0, 500.0], &[1.0, f32::NAN]).is_none());
        assert!(Spectrum::piecewise_linear(&[400.0, 500.0], &[1.0]).is_none());
        assert!(Spectrum::piecewise_constant(vec![400.0, 500.0], vec![]).is_none());
    }

    #[test]
    fn piecewise_constant_bins() {
        let s = Spectrum::piecewise_constant(vec![400.0, 500.0, 600.0], vec![1.0, 2.0]).unwrap();
        assert_eq!(s.eval(450.0), 1.0);
        assert_eq!(s.eval(500.0), 2.0);
        assert_eq!(s.eval(600.0), 2.0);
        assert_eq!(s.eval(600.5), 0.0);
    }

    #[test]
    fn constant_one_has_unit_luminance_and_equal_energy_white() {
        let xyz = Spectrum::constant(1.0).to_xyz_f64();
        assert!((xyz.y - 1.0).abs() < 1e-12);
        // Equal-energy white E: ∫x̄/∫ȳ and ∫z̄/∫ȳ from the table's trapezoid sums.
        assert!((xyz.x - 106.865_403_914 / 106.856_914_916_767).abs() < 1e-9);
        assert!((xyz.z - 106.891_948_229 / 106.856_914_916_767).abs() < 1e-9);
    }

    #[test]
    fn xyz_integration_is_exact_for_a_narrow_triangle() {
        // A triangle of height 1 and base 2 nm centred on 555 nm: ∫ S ȳ is computable by hand
        // from the three table values around it (product of two linears on each half).
        let s = Spectrum::piecewise_linear(&[554.0, 555.0, 556.0], &[0.0, 1.0, 0.0]).unwrap();
        let y = s.to_xyz_f64().y * crate::spectrum::cie::CIE_Y_INTEGRAL_F64;
        let t = |i: usize| crate::spectrum::cie::xyz_bar_sample(i).unwrap()[1];
        let (a, b, c) = (t(194), t(195), t(196));
        // ∫₀¹ t (a + (b − a) t) dt = a/2 + (b − a)/3, and symmetrically on the right.
        let want = (a / 2.0 + (b - a) / 3.0) + (c / 2.0 + (b - c) / 3.0);
        assert!((y - want).abs() < 1e-12, "{y} {want}");
    }
}

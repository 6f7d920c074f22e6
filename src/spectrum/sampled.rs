//! Spectral quantities carried along a path: four wavelengths (hero + 3 rotated) and the
//! values of a spectral quantity at them.

use super::cie::{xyz_bar, CIE_Y_INTEGRAL};
use glam::{Vec3, Vec4};
use std::ops::{Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Sub};

/// Number of wavelengths a path carries (hero wavelength sampling).
pub const N_SPECTRUM_SAMPLES: usize = 4;
/// Lower end of the sampled range [nm].
pub const LAMBDA_MIN: f32 = 360.0;
/// Upper end of the sampled range [nm].
pub const LAMBDA_MAX: f32 = 830.0;

/// Values of a spectral quantity (radiance, reflectance, throughput, ...) at the four
/// wavelengths of a [`SampledWavelengths`]. SIMD storage in a `glam::Vec4`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SampledSpectrum(pub Vec4);

impl SampledSpectrum {
    /// The same value at every wavelength.
    #[inline]
    pub fn splat(v: f32) -> Self {
        Self(Vec4::splat(v))
    }
    /// Zero at every wavelength.
    #[inline]
    pub fn zero() -> Self {
        Self(Vec4::ZERO)
    }
    /// One at every wavelength.
    #[inline]
    pub fn one() -> Self {
        Self(Vec4::ONE)
    }
    /// From four values.
    #[inline]
    pub fn new(v: [f32; 4]) -> Self {
        Self(Vec4::from_array(v))
    }
    /// True when every value is exactly zero.
    #[inline]
    pub fn is_black(&self) -> bool {
        self.0 == Vec4::ZERO
    }
    /// True when every value is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.0.is_finite()
    }
    /// Largest value.
    #[inline]
    pub fn max_value(&self) -> f32 {
        self.0.max_element()
    }
    /// Smallest value.
    #[inline]
    pub fn min_value(&self) -> f32 {
        self.0.min_element()
    }
    /// Mean over the four wavelengths.
    #[inline]
    pub fn average(&self) -> f32 {
        self.0.element_sum() * 0.25
    }
    /// Division that maps x/0 to 0 (pdf-weighted quantities where a pdf vanishes).
    #[inline]
    pub fn safe_div(self, d: SampledSpectrum) -> Self {
        let mut out = [0.0; 4];
        for (i, o) in out.iter_mut().enumerate() {
            if d.0[i] != 0.0 {
                *o = self.0[i] / d.0[i];
            }
        }
        Self::new(out)
    }
    /// Element-wise map.
    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self(Vec4::new(f(self.0.x), f(self.0.y), f(self.0.z), f(self.0.w)))
    }
    /// Element-wise exponential (Beer–Lambert transmittance), four lanes at once
    /// ([`exp4`]).
    #[inline]
    pub fn exp(self) -> Self {
        Self(Vec4::from_array(exp4(self.0.to_array())))
    }
    /// Element-wise square root.
    #[inline]
    pub fn sqrt(self) -> Self {
        self.map(|x| x.max(0.0).sqrt())
    }
    /// The values as an array.
    #[inline]
    pub fn to_array(self) -> [f32; 4] {
        self.0.to_array()
    }

    /// Monte Carlo estimate of XYZ in the ∫ȳ normalisation, X = ∫ S x̄ dλ / ∫ ȳ dλ (Y, Z alike), from the
    /// values at `w`: (1/4) Σᵢ x̄ȳz̄(λᵢ) sᵢ / pdfᵢ / ∫ȳ, skipping wavelengths whose pdf is 0.
    /// A spectrum equal to 1 everywhere has E[Y] = 1.
    pub fn to_xyz(&self, w: &SampledWavelengths) -> Vec3 {
        let mut acc = Vec3::ZERO;
        for i in 0..N_SPECTRUM_SAMPLES {
            if w.pdf[i] != 0.0 {
                acc += xyz_bar(w.lambda[i]) * (self.0[i] / w.pdf[i]);
            }
        }
        acc / (N_SPECTRUM_SAMPLES as f32 * CIE_Y_INTEGRAL)
    }

    /// Monte Carlo estimate of the luminance Y (the second component of [`Self::to_xyz`]).
    pub fn y(&self, w: &SampledWavelengths) -> f32 {
        let mut acc = 0.0;
        for i in 0..N_SPECTRUM_SAMPLES {
            if w.pdf[i] != 0.0 {
                acc += xyz_bar(w.lambda[i]).y * self.0[i] / w.pdf[i];
            }
        }
        acc / (N_SPECTRUM_SAMPLES as f32 * CIE_Y_INTEGRAL)
    }
}

/// eˣ of four values in single precision without a library call per lane, as a loop the
/// compiler vectorises: x = k ln 2 + r with k = ⌊x log₂e + ½⌋ and |r| ≤ ½ ln 2 (ln 2 split in
/// two parts so that r is exact), eʳ by Cephes' degree-7 minimax polynomial for `expf` (Moshier
/// 1989, *Methods and Programs for Mathematical Functions*), times 2ᵏ built in the exponent
/// bits. Relative error below 3·10⁻⁷; 0 below ln 2⁻¹²⁵ ≈ −86.64 (where the true value is under
/// 2.4·10⁻³⁸), +∞ above 88.72, NaN for NaN.
#[inline]
pub fn exp4(x: [f32; 4]) -> [f32; 4] {
    const LO: f32 = -86.643_4;
    const HI: f32 = 88.722_83;
    let x = Vec4::from_array(x);
    let c = x.clamp(Vec4::splat(LO), Vec4::splat(HI));
    let k = (c * std::f32::consts::LOG2_E + Vec4::splat(0.5)).floor();
    let r = c - k * 0.693_359_4 - k * -2.121_944_4e-4;
    let p = ((((Vec4::splat(1.987_569_1e-4) * r + Vec4::splat(1.398_199_9e-3)) * r + Vec4::splat(8.333_452e-3)) * r
        + Vec4::splat(4.166_579_6e-2))
        * r
        + Vec4::splat(0.166_666_65))
        * r
        + Vec4::splat(0.5);
    let e = p * r * r + r + Vec4::ONE;
    // Times 2ᵏ⁻¹ (biased exponent k + 126, in 1..=254 for k in −125..=128), then 2.
    let half_two_k = k.to_array().map(|k| f32::from_bits(((k as i32 + 126) as u32) << 23));
    let e = e * Vec4::from_array(half_two_k) * 2.0;
    let e = Vec4::select(x.cmplt(Vec4::splat(LO)), Vec4::ZERO, e);
    let e = Vec4::select(x.cmpgt(Vec4::splat(HI)), Vec4::splat(f32::INFINITY), e);
    Vec4::select(x.cmpeq(x), e, x).to_array()
}

impl Index<usize> for SampledSpectrum {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        &self.0[i]
    }
}
impl IndexMut<usize> for SampledSpectrum {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0[i]
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
        impl $tr for SampledSpectrum {
            type Output = Self;
            #[inline]
            fn $f(self, o: Self) -> Self { Self(self.0 $op o.0) }
        }
        impl $tr<f32> for SampledSpectrum {
            type Output = Self;
            #[inline]
            fn $f(self, o: f32) -> Self { Self(self.0 $op o) }
        }
        impl $tra for SampledSpectrum {
            #[inline]
            fn $fa(&mut self, o: Self) { self.0 = self.0 $op o.0; }
        }
        impl $tra<f32> for SampledSpectrum {
            #[inline]
            fn $fa(&mut self, o: f32) { self.0 = self.0 $op o; }
        }
    };
}
binop!(Add, add, AddAssign, add_assign, +);
binop!(Mul, mul, MulAssign, mul_assign, *);
binop!(Div, div, DivAssign, div_assign, /);

impl Sub for SampledSpectrum {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self(self.0 - o.0)
    }
}
impl Mul<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    #[inline]
    fn mul(self, s: SampledSpectrum) -> SampledSpectrum {
        SampledSpectrum(s.0 * self)
    }
}

/// Four wavelengths [nm] carried by one path, with the probability density [1/nm] of each.
/// The first is the hero wavelength; the others are rotated by multiples of a quarter of the
/// range, so the four are stratified over [LAMBDA_MIN, LAMBDA_MAX].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    /// Wavelengths [nm].
    pub lambda: [f32; N_SPECTRUM_SAMPLES],
    /// Density of each wavelength [1/nm]; 0 for a terminated secondary wavelength.
    pub pdf: [f32; N_SPECTRUM_SAMPLES],
}

impl SampledWavelengths {
    /// Uniform hero sampling over [lmin, lmax] from `u` in [0,1).
    pub fn sample_uniform(u: f32) -> Self {
        Self::sample_uniform_range(u, LAMBDA_MIN, LAMBDA_MAX)
    }

    /// Uniform hero sampling over [lmin, lmax].
    pub fn sample_uniform_range(u: f32, lmin: f32, lmax: f32) -> Self {
        let range = lmax - lmin;
        let lambda = stratified_quantiles(u).map(|up| (lmin + up * range).min(lmax));
        Self { lambda, pdf: [1.0 / range; N_SPECTRUM_SAMPLES] }
    }

    /// Hero sampling with density ∝ 1/cosh²(0.0072 (λ − 538 nm)) on [360, 830] nm, which
    /// roughly follows the luminous efficiency ȳ and cuts colour noise (pbrt-v4,
    /// `SampleVisibleWavelengths`). The four are one per quarter of the CDF, see
    /// [`stratified_quantiles`].
    pub fn sample_visible(u: f32) -> Self {
        let mut lambda = [0.0; N_SPECTRUM_SAMPLES];
        let mut pdf = [0.0; N_SPECTRUM_SAMPLES];
        // The same formulas as sample_visible_wavelength / visible_wavelength_pdf, with the tanh
        // bounds computed once per process (this runs once per camera sample). The density
        // needs no cosh: at λ = μ + atanh(t)/a, sech²(a(λ − μ)) = 1 − tanh² = 1 − t².
        // In single precision: atanh(t) = ½ ln((1 + t)/(1 − t)) with |t| ≤ 0.97 puts λ within
        // ~1e-4 nm of the double-precision inverse, far below any spectral feature.
        let (lo, hi) = *VISIBLE_TANH_BOUNDS;
        let norm = (VISIBLE_A / (hi - lo)) as f32;
        let (lo, width) = (lo as f32, (hi - lo) as f32);
        for (i, up) in stratified_quantiles(u).into_iter().enumerate() {
            let t = lo + up * width;
            let atanh = 0.5 * ((1.0 + t) / (1.0 - t)).ln();
            lambda[i] = (VISIBLE_MU as f32 + atanh / VISIBLE_A as f32).clamp(LAMBDA_MIN, LAMBDA_MAX);
            pdf[i] = norm * (1.0 - t * t);
        }
        Self { lambda, pdf }
    }

    /// Density of the secondary wavelengths as a spectrum (for dividing estimates).
    #[inline]
    pub fn pdf(&self) -> SampledSpectrum {
        SampledSpectrum::new(self.pdf)
    }

    /// True once the secondary wavelengths have been terminated (dispersion).
    #[inline]
    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1..].iter().all(|&p| p == 0.0)
    }

    /// Keeps only the hero wavelength: called at a dispersive interface, where the four
    /// wavelengths would follow different directions. The hero's pdf is divided by N so the
    /// estimator stays unbiased (pbrt-v4 `TerminateSecondary`).
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for p in self.pdf[1..].iter_mut() {
            *p = 0.0;
        }
        self.pdf[0] /= N_SPECTRUM_SAMPLES as f32;
    }
}

/// The CDF values of the four wavelengths drawn from one uniform `u`: one in each quarter of
/// [0, 1), at the same place r within its quarter, the hero (index 0) in quarter q:
/// vᵢ = (r + (q + i) mod 4) / 4.
///
/// pbrt-v4 rotates `u` itself by quarters (vᵢ = frac(u + i/4)), which makes r = frac(4u): the
/// coarse strata of a low-discrepancy `u` fold onto each other (the 16 strata of 16 Sobol points
/// give r only 4), so the four wavelengths lose most of the sampler's stratification. Here r
/// takes the leading 21 of `u`'s first 23 bits, so N stratified values of `u` put the 4N
/// wavelengths one per 1/4N of the CDF, and q takes the last two, which any stratification of up
/// to 2²¹ points leaves uniform. (q, r) is a bijection of those 23 bits, so a uniform `u` gives a
/// uniform hero, whose density a dispersive interface relies on
/// ([`SampledWavelengths::terminate_secondary`]). 23, not 24: Sobol values carry 23 bits.
#[inline]
fn stratified_quantiles(u: f32) -> [f32; N_SPECTRUM_SAMPLES] {
    const _: () = assert!(N_SPECTRUM_SAMPLES == 4, "q is two bits");
    const BITS: u32 = 23;
    let x = ((u.clamp(0.0, 1.0) * (1u32 << BITS) as f32) as u32).min((1 << BITS) - 1);
    let (r, q) = ((x >> 2) as f32 * (1.0 / (1u32 << (BITS - 2)) as f32), x & 3);
    std::array::from_fn(|i| (r + ((q + i as u32) % 4) as f32) * 0.25)
}

/// Slope a [1/nm] and centre μ [nm] of the visible-wavelength density sech²(a(λ − μ)).
const VISIBLE_A: f64 = 0.0072;
const VISIBLE_MU: f64 = 538.0;

/// [`visible_tanh_bounds`], computed once.
static VISIBLE_TANH_BOUNDS: std::sync::LazyLock<(f64, f64)> = std::sync::LazyLock::new(visible_tanh_bounds);

/// tanh(a(λ − μ)) at the ends of the range: the CDF of sech² is tanh, up to an affine map.
fn visible_tanh_bounds() -> (f64, f64) {
    let lo = (VISIBLE_A * (LAMBDA_MIN as f64 - VISIBLE_MU)).tanh();
    let hi = (VISIBLE_A * (LAMBDA_MAX as f64 - VISIBLE_MU)).tanh();
    (lo, hi)
}

/// Density [1/nm] of [`sample_visible_wavelength`]: a / (tanh(a(830−μ)) − tanh(a(360−μ)))
/// · sech²(a(λ − μ)) inside [360, 830] nm, 0 outside.
pub fn visible_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let (lo, hi) = visible_tanh_bounds();
    let c = (VISIBLE_A * (lambda as f64 - VISIBLE_MU)).cosh();
    (VISIBLE_A / (hi - lo) / (c * c)) as f32
}

/// Inverts the CDF of [`visible_wavelength_pdf`]: λ = μ + atanh(lo + u (hi − lo)) / a [nm].
pub fn sample_visible_wavelength(u: f32) -> f32 {
    let (lo, hi) = visible_tanh_bounds();
    let t = lo + (u.clamp(0.0, 1.0) as f64) * (hi - lo);
    let l = VISIBLE_MU + t.atanh() / VISIBLE_A;
    (l as f32).clamp(LAMBDA_MIN, LAMBDA_MAX)
}

/// Density [1/nm] of uniform wavelength sampling over [360, 830] nm.
pub fn uniform_wavelength_pdf(lambda: f32) -> f32 {
    if (LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        1.0 / (LAMBDA_MAX - LAMBDA_MIN)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn exp4_agrees_with_the_exponential() {
        let mut worst = 0.0f64;
        let n = 200_000;
        for i in 0..=n {
            let x = -86.6 + (88.7 + 86.6) * i as f32 / n as f32;
            let got = super::exp4([x, -x.min(86.6), x * 0.01, 0.0]);
            for (g, v) in got.iter().zip([x, -x.min(86.6), x * 0.01, 0.0]) {
                let want = (v as f64).exp();
                worst = worst.max(((*g as f64) - want).abs() / want);
            }
        }
        assert!(worst < 3e-7, "relative error {worst}");
        let [a, b, c, d] = super::exp4([-1e30, f32::NEG_INFINITY, f32::INFINITY, f32::NAN]);
        assert!(a == 0.0 && b == 0.0 && c == f32::INFINITY && d.is_nan());
        assert_eq!(super::exp4([0.0, -100.0, 100.0, -f32::MAX]), [1.0, 0.0, f32::INFINITY, 0.0]);
    }

    use super::*;

    #[test]
    fn uniform_wavelengths_are_stratified_and_in_range() {
        for k in 0..100 {
            let u = k as f32 / 100.0;
            let w = SampledWavelengths::sample_uniform(u);
            let mut l = w.lambda;
            l.sort_by(f32::total_cmp);
            for x in l {
                assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(&x));
            }
            for i in 1..4 {
                let gap = l[i] - l[i - 1];
                assert!((gap - (LAMBDA_MAX - LAMBDA_MIN) / 4.0).abs() < 1e-3, "{l:?}");
            }
        }
    }

    #[test]
    fn terminate_secondary_keeps_estimator_unbiased() {
        // The film's estimate is mean_i f(λ_i)/pdf_i with 0/0 := 0. For f = 1 it is the range
        // length before and after termination.
        let estimate = |w: &SampledWavelengths| SampledSpectrum::one().safe_div(w.pdf()).average();
        let mut w = SampledWavelengths::sample_uniform(0.3);
        let before = estimate(&w);
        w.terminate_secondary();
        assert!(w.secondary_terminated());
        let after = estimate(&w);
        assert!((before - (LAMBDA_MAX - LAMBDA_MIN)).abs() < 1e-3);
        assert!((after - before).abs() < 1e-3, "{before} vs {after}");
    }

    #[test]
    fn visible_pdf_integrates_to_one_and_matches_pbrt() {
        let n = 47_000;
        let h = (LAMBDA_MAX - LAMBDA_MIN) as f64 / n as f64;
        let mut s = 0.0;
        for i in 0..n {
            s += visible_wavelength_pdf(LAMBDA_MIN + (i as f64 + 0.5) as f32 * h as f32) as f64 * h;
        }
        assert!((s - 1.0).abs() < 1e-5, "{s}");
        // pbrt-v4's rounded constants: 0.0039398042 / cosh²(0.0072 (λ − 538)).
        let p = visible_wavelength_pdf(538.0);
        assert!((p - 0.003_939_804).abs() < 2e-6 * 0.0039, "{p}");
        assert_eq!(visible_wavelength_pdf(359.0), 0.0);
        // pbrt: 538 − 138.888889 atanh(0.85691062 − 1.82750197 u).
        for u in [0.1f32, 0.5, 0.9] {
            let want = 538.0 - 138.888_89 * (0.856_910_6f64 - 1.827_502 * u as f64).atanh();
            assert!((sample_visible_wavelength(u) as f64 - want).abs() < 0.05);
        }
    }

    /// Pearson χ² of `n` draws of `sample(u)` against `pdf` over `bins` equal bins of
    /// [360, 830]; returns (statistic, degrees of freedom).
    fn chi2(mut sample: impl FnMut(f32) -> f32, pdf: impl Fn(f32) -> f32, bins: usize, n: usize) -> (f64, usize) {
        let mut rng = crate::sampling::Rng::new(7, 3);
        let mut counts = vec![0u64; bins];
        let w = (LAMBDA_MAX - LAMBDA_MIN) as f64 / bins as f64;
        for _ in 0..n {
            let l = sample(rng.uniform()) as f64;
            let b = (((l - LAMBDA_MIN as f64) / w) as usize).min(bins - 1);
            counts[b] += 1;
        }
        let mut stat = 0.0;
        for (b, &c) in counts.iter().enumerate() {
            // Expected count: ∫ pdf over the bin by a fine midpoint rule.
            let lo = LAMBDA_MIN as f64 + b as f64 * w;
            let m = 64;
            let p: f64 =
                (0..m).map(|k| pdf((lo + (k as f64 + 0.5) * w / m as f64) as f32) as f64).sum::<f64>() * w / m as f64;
            let e = p * n as f64;
            stat += (c as f64 - e).powi(2) / e;
        }
        (stat, bins - 1)
    }

    #[test]
    fn visible_sample_pdfs_are_the_density_at_the_sampled_wavelengths() {
        // The single-precision fast path against the double-precision inverse CDF and density.
        for k in 0..1000 {
            let u = (k as f32 + 0.5) / 1000.0;
            let w = SampledWavelengths::sample_visible(u);
            let hero = sample_visible_wavelength(stratified_quantiles(u)[0]);
            assert!((w.lambda[0] - hero).abs() < 1e-3, "u = {u}: {:?}", w.lambda);
            for (&l, &p) in w.lambda.iter().zip(&w.pdf) {
                let want = visible_wavelength_pdf(l);
                assert!((p - want).abs() <= 1e-5 * want, "λ = {l}: {p} vs {want}");
            }
        }
    }

    #[test]
    fn visible_sampling_passes_chi2() {
        // α = 0.01 critical value of χ²(79) is 111.1 (Wilson–Hilferty: k(1 − 2/9k + z√(2/9k))³
        // with z = 2.326 gives 111.2).
        let (stat, dof) = chi2(sample_visible_wavelength, visible_wavelength_pdf, 80, 1_000_000);
        assert_eq!(dof, 79);
        assert!(stat < 111.1, "χ² = {stat}");
        // The test has power: uniform samples against the visible pdf fail it badly.
        let (bad, _) = chi2(|u| LAMBDA_MIN + u * (LAMBDA_MAX - LAMBDA_MIN), visible_wavelength_pdf, 80, 100_000);
        assert!(bad > 1000.0, "{bad}");
    }

    #[test]
    fn the_hero_and_every_secondary_wavelength_have_the_visible_density() {
        // The hero's density matters on its own once a dispersive interface drops the others.
        for i in 0..N_SPECTRUM_SAMPLES {
            let (stat, _) =
                chi2(|u| SampledWavelengths::sample_visible(u).lambda[i], visible_wavelength_pdf, 80, 400_000);
            assert!(stat < 111.1, "wavelength {i}: χ² = {stat}");
        }
        // Also with the u that renders draw: Sobol values (23 bits), 64 samples in each pixel.
        // The hero's quarter comes from u's lowest bits, so this fails if those are not uniform.
        let mut s = crate::sampling::Sampler::sobol();
        let (mut k, mut quarters) = (0u32, [0u32; 4]);
        let (stat, _) = chi2(
            |_| {
                s.start_pixel_sample((k / 64, 0), (k % 64) as u64, 1);
                k += 1;
                let u = s.get_1d();
                quarters[(stratified_quantiles(u)[0] * 4.0) as usize] += 1;
                SampledWavelengths::sample_visible(u).lambda[0]
            },
            visible_wavelength_pdf,
            80,
            400_000,
        );
        assert!(stat < 111.1, "hero from Sobol: χ² = {stat}");
        // Each quarter 1/4 of the time: binomial σ = √(n·¼·¾) ≈ 274.
        assert!(quarters.iter().all(|&c| (c as f64 - 100_000.0).abs() < 4.0 * 274.0), "{quarters:?}");
    }

    #[test]
    fn stratified_uniforms_put_one_wavelength_in_each_stratum_of_the_cdf() {
        // N Owen-scrambled Sobol values of u (one per 1/N) must give 4N quantiles, one per 1/4N.
        // The quarter rotation frac(u + i/4) fails this from N = 8: its strata fold onto each other.
        let strata_hit = |n: u64, pixel: u32, quantiles: &dyn Fn(f32) -> [f32; 4]| {
            let mut s = crate::sampling::Sampler::sobol();
            let mut counts = vec![0u32; 4 * n as usize];
            for i in 0..n {
                s.start_pixel_sample((pixel, 3), i, 17);
                for v in quantiles(s.get_1d()) {
                    counts[(v * 4.0 * n as f32) as usize] += 1;
                }
            }
            counts.iter().all(|&c| c == 1)
        };
        let rotation = |u: f32| std::array::from_fn(|i| (u + i as f32 / 4.0).fract());
        for n in [1, 4, 16, 64, 256, 4096] {
            for pixel in 0..8 {
                assert!(strata_hit(n, pixel, &stratified_quantiles), "{n} samples, pixel {pixel}");
                if n >= 8 {
                    assert!(!strata_hit(n, pixel, &rotation), "{n} samples, pixel {pixel}");
                }
            }
        }
    }

    #[test]
    fn sampled_xyz_is_unbiased() {
        // E[to_xyz] = exact XYZ for D65 with both samplers; 4σ from the sample variance.
        let d65 = crate::spectrum::Spectrum::named("stdillum-D65").unwrap();
        let exact = d65.to_xyz_f64();
        for visible in [false, true] {
            let mut rng = crate::sampling::Rng::new(11, visible as u64);
            let n = 200_000;
            let (mut sum, mut sq) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
            for _ in 0..n {
                let u = rng.uniform();
                let w =
                    if visible { SampledWavelengths::sample_visible(u) } else { SampledWavelengths::sample_uniform(u) };
                let v = d65.sample(&w).to_xyz(&w).as_dvec3();
                assert!((d65.sample(&w).y(&w) as f64 - v.y).abs() < 1e-6);
                sum += v;
                sq += v * v;
            }
            let mean = sum / n as f64;
            let se = ((sq / n as f64 - mean * mean) / n as f64).powf(0.5);
            let z = (mean - exact).abs() / se;
            assert!(z.max_element() < 4.0, "visible={visible} mean {mean} exact {exact} se {se}");
            assert!(se.y < 2e-3);
        }
    }

    #[test]
    fn constant_one_has_unit_luminance_in_expectation() {
        let mut rng = crate::sampling::Rng::new(5, 0);
        let n = 100_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let w = SampledWavelengths::sample_visible(rng.uniform());
            let y = SampledSpectrum::one().y(&w) as f64;
            s += y;
            s2 += y * y;
        }
        let mean = s / n as f64;
        let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!((mean - 1.0).abs() < 4.0 * se, "{mean} ± {se}");
        // Terminated secondaries are skipped, not divided by zero.
        let mut w = SampledWavelengths::sample_visible(0.3);
        w.terminate_secondary();
        assert!(SampledSpectrum::one().to_xyz(&w).is_finite());
    }
}

//! Spectral quantities carried along a path: four wavelengths (hero + 3 rotated) and the
//! values of a spectral quantity at them.

use glam::Vec4;
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
    /// Element-wise exponential (Beer–Lambert transmittance).
    #[inline]
    pub fn exp(self) -> Self {
        self.map(f32::exp)
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
        let hero = lmin + u * range;
        let delta = range / N_SPECTRUM_SAMPLES as f32;
        let mut lambda = [0.0; N_SPECTRUM_SAMPLES];
        for (i, l) in lambda.iter_mut().enumerate() {
            let mut x = hero + delta * i as f32;
            if x > lmax {
                x = lmin + (x - lmax);
            }
            *l = x;
        }
        Self {
            lambda,
            pdf: [1.0 / range; N_SPECTRUM_SAMPLES],
        }
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

#[cfg(test)]
mod tests {
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
}

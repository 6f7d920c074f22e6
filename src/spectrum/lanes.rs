//! A sampled spectrum per lane: the values at a path's four wavelengths, for every path of the
//! lanes (the lane-generic form of [`crate::spectrum::SampledSpectrum`]).

use super::SampledSpectrum;
use crate::simd::Real;
use std::ops::{Add, AddAssign, Mul, MulAssign};

/// Values at the four wavelengths of each lane's path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct S4<R>(pub [R; 4]);

impl<R: Real> S4<R> {
    /// Every value `v`.
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        S4([R::splat(v); 4])
    }
    /// Every wavelength scaled by the lane's `s`.
    #[inline(always)]
    pub fn scale(self, s: R) -> Self {
        S4(self.0.map(|c| c * s))
    }
    /// Lane `i`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> SampledSpectrum {
        SampledSpectrum::new(self.0.map(|c| c.lane(i)))
    }
    /// Sets lane `i`.
    #[inline(always)]
    pub fn set_lane(&mut self, i: usize, s: SampledSpectrum) {
        for (c, v) in self.0.iter_mut().zip(s.to_array()) {
            c.set_lane(i, v);
        }
    }
    /// Lanes where every wavelength's value is 0.
    #[inline(always)]
    pub fn is_black(&self) -> R::Mask {
        let z = R::splat(0.0);
        self.0[0].eq(z) & self.0[1].eq(z) & self.0[2].eq(z) & self.0[3].eq(z)
    }
    /// The largest of the four values per lane.
    #[inline(always)]
    pub fn max_value(&self) -> R {
        self.0[0].max(self.0[1]).max(self.0[2].max(self.0[3]))
    }
    /// `a` where `m` is set, else `b`.
    #[inline(always)]
    pub fn select(m: R::Mask, a: Self, b: Self) -> Self {
        S4([0, 1, 2, 3].map(|k| R::select(m, a.0[k], b.0[k])))
    }
}

impl<R: Real> Add for S4<R> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        S4([0, 1, 2, 3].map(|k| self.0[k] + o.0[k]))
    }
}

impl<R: Real> AddAssign for S4<R> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<R: Real> Mul for S4<R> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        S4([0, 1, 2, 3].map(|k| self.0[k] * o.0[k]))
    }
}

impl<R: Real> MulAssign for S4<R> {
    #[inline(always)]
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl From<SampledSpectrum> for S4<f32> {
    #[inline(always)]
    fn from(s: SampledSpectrum) -> Self {
        S4(s.to_array())
    }
}

impl From<S4<f32>> for SampledSpectrum {
    #[inline(always)]
    fn from(s: S4<f32>) -> Self {
        SampledSpectrum::new(s.0)
    }
}

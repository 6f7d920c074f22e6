//! Structure-of-arrays columns of a queue, read and written sixteen entries at a time as
//! [`Lanes`] (one AVX-512 register of `f32`).

use crate::simd::{Lanes, LanesMask, V3};
use crate::spectrum::{SampledSpectrum, S4};
use glam::Vec3;

/// Entries per vector.
pub(super) const W: usize = 16;
/// Sixteen floats.
pub(super) type L = Lanes<W>;

/// Entries `i..i + W` of `v`.
#[inline(always)]
pub(super) fn load(v: &[f32], i: usize) -> L {
    Lanes(v[i..i + W].try_into().expect("W entries"))
}

/// Entries `i..i + W` of `v` as a mask.
#[inline(always)]
pub(super) fn load_mask(v: &[bool], i: usize) -> LanesMask<W> {
    LanesMask(v[i..i + W].try_into().expect("W entries"))
}

/// Writes entries `i..i + W`.
#[inline(always)]
pub(super) fn store(v: &mut [f32], i: usize, x: L) {
    v[i..i + W].copy_from_slice(&x.0);
}

/// Writes mask entries `i..i + W`.
#[inline(always)]
pub(super) fn store_mask(v: &mut [bool], i: usize, m: LanesMask<W>) {
    v[i..i + W].copy_from_slice(&m.0);
}

/// A column of vectors.
#[derive(Default)]
pub(super) struct Col3 {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
}

impl Col3 {
    pub fn push(&mut self, v: Vec3) {
        self.x.push(v.x);
        self.y.push(v.y);
        self.z.push(v.z);
    }
    pub fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }
    #[inline(always)]
    pub fn load(&self, i: usize) -> V3<L> {
        V3::new(load(&self.x, i), load(&self.y, i), load(&self.z, i))
    }
    #[inline(always)]
    pub fn store(&mut self, i: usize, v: V3<L>) {
        store(&mut self.x, i, v.x);
        store(&mut self.y, i, v.y);
        store(&mut self.z, i, v.z);
    }
    /// `n` entries, every one zero.
    pub fn reset(&mut self, n: usize) {
        for c in [&mut self.x, &mut self.y, &mut self.z] {
            c.clear();
            c.resize(n, 0.0);
        }
    }
    /// Pads with zeros to `n` entries.
    pub fn pad(&mut self, n: usize) {
        for c in [&mut self.x, &mut self.y, &mut self.z] {
            c.resize(n, 0.0);
        }
    }
    pub fn clear(&mut self) {
        self.reset(0);
    }
}

/// A column of sampled spectra (four wavelengths).
#[derive(Default)]
pub(super) struct Col4(pub [Vec<f32>; 4]);

impl Col4 {
    pub fn push(&mut self, s: SampledSpectrum) {
        for (c, v) in self.0.iter_mut().zip(s.to_array()) {
            c.push(v);
        }
    }
    pub fn get(&self, i: usize) -> SampledSpectrum {
        SampledSpectrum::new([0, 1, 2, 3].map(|k| self.0[k][i]))
    }
    #[inline(always)]
    pub fn load(&self, i: usize) -> S4<L> {
        S4([0, 1, 2, 3].map(|k| load(&self.0[k], i)))
    }
    #[inline(always)]
    pub fn store(&mut self, i: usize, s: S4<L>) {
        for (c, v) in self.0.iter_mut().zip(s.0) {
            store(c, i, v);
        }
    }
    pub fn reset(&mut self, n: usize) {
        for c in &mut self.0 {
            c.clear();
            c.resize(n, 0.0);
        }
    }
    pub fn pad(&mut self, n: usize) {
        for c in &mut self.0 {
            c.resize(n, 0.0);
        }
    }
    pub fn clear(&mut self) {
        self.reset(0);
    }
}

//! The sigmoid polynomial spectra of Jakob & Hanika (2019): S(λ) = σ(c₀x² + c₁x + c₂) with
//! σ(t) = ½ + t / (2√(1 + t²)) and x = (λ − 360 nm) / 470 nm; fitted in [`super::jakob_hanika`].

use super::cie::{CIE_LAMBDA_MAX, CIE_LAMBDA_MIN};
use glam::Vec4;

/// The span of the normalised wavelength x [nm].
pub(super) const X_SPAN: f64 = CIE_LAMBDA_MAX - CIE_LAMBDA_MIN;

/// σ(t) = ½ + t / (2√(1 + t²)), with the limits 0 and 1 at ∓∞.
#[inline]
pub(super) fn sigmoid(t: f64) -> f64 {
    if t.is_infinite() {
        return if t > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + t / (2.0 * (1.0 + t * t).sqrt())
}

/// x = (λ − 360 nm) / 470 nm of four wavelengths λ [nm].
#[inline]
pub fn normalised_wavelengths(lambda: [f32; 4]) -> Vec4 {
    (Vec4::from_array(lambda) - Vec4::splat(CIE_LAMBDA_MIN as f32)) * (1.0 / X_SPAN as f32)
}

/// σ(c₀x² + c₁x + c₂) at four normalised wavelengths x in single precision. t is clamped to
/// ±10¹⁸ (where σ rounds to 0 or 1) so that t² stays finite and ±∞ give the limits.
#[inline]
pub fn sigmoid4(c: [f32; 3], x: Vec4) -> Vec4 {
    let t = (Vec4::splat(c[0]) * x + Vec4::splat(c[1])) * x + Vec4::splat(c[2]);
    let t = t.clamp(Vec4::splat(-1e18), Vec4::splat(1e18));
    Vec4::splat(0.5) + Vec4::splat(0.5) * t / (Vec4::ONE + t * t).sqrt()
}

/// `scale · σ(c₀x² + c₁x + c₂)` with single-precision coefficients, evaluated at four
/// normalised wavelengths at a time ([`normalised_wavelengths`]): the compact form of a sigmoid
/// spectrum kept per voxel or texel. A zero scale gives 0 without evaluating σ (a sparse grid's
/// empty voxels, a black texel).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ScaledSigmoid {
    /// Polynomial coefficients in the normalised wavelength (highest degree first).
    pub c: [f32; 3],
    /// Multiplier.
    pub scale: f32,
}

impl ScaledSigmoid {
    /// The values at the normalised wavelengths `x`.
    #[inline]
    pub fn sample(&self, x: Vec4) -> Vec4 {
        if self.scale == 0.0 {
            Vec4::ZERO
        } else {
            self.scale * sigmoid4(self.c, x)
        }
    }
}

/// dσ/dt = ½ (1 + t²)^(−3/2).
#[inline]
pub(super) fn sigmoid_derivative(t: f64) -> f64 {
    let s = 1.0 / (1.0 + t * t);
    0.5 * s * s.sqrt()
}

/// A spectrum σ(c₀x² + c₁x + c₂) with x = (λ − 360 nm) / 470 nm; values in (0, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidPolynomial {
    /// Polynomial coefficients in the normalised wavelength x (highest degree first).
    pub c: [f64; 3],
}

impl SigmoidPolynomial {
    /// The value at `lambda` [nm].
    #[inline]
    pub fn eval_f64(&self, lambda: f64) -> f64 {
        let x = (lambda - CIE_LAMBDA_MIN) / X_SPAN;
        sigmoid((self.c[0] * x + self.c[1]) * x + self.c[2])
    }

    /// The values at four wavelengths whose normalised x are `x`
    /// ([`normalised_wavelengths`]), in single precision, as pbrt-v4 evaluates its sigmoid
    /// polynomials.
    #[inline]
    pub fn sample(&self, x: Vec4) -> Vec4 {
        sigmoid4(self.c.map(|c| c as f32), x)
    }

    /// The wavelength [nm] of the polynomial's vertex (its extremum), if it is not linear.
    pub fn vertex_lambda(&self) -> Option<f64> {
        (self.c[0] != 0.0).then(|| CIE_LAMBDA_MIN - self.c[1] / (2.0 * self.c[0]) * X_SPAN)
    }

    /// The same polynomial in λ [nm] (c₀λ² + c₁λ + c₂), the form pbrt-v4 and colour-science
    /// store.
    pub fn coefficients_nm(&self) -> [f64; 3] {
        let (a, b, c) = (self.c[0], self.c[1], self.c[2]);
        let (s, o) = (1.0 / X_SPAN, -CIE_LAMBDA_MIN / X_SPAN);
        // x = sλ + o.
        [a * s * s, 2.0 * a * s * o + b * s, a * o * o + b * o + c]
    }

    /// The constant σ⁻¹(v) polynomial (flat spectrum of value `v` in (0, 1)).
    pub fn flat(v: f64) -> Self {
        let v = v.clamp(1e-9, 1.0 - 1e-9);
        Self { c: [0.0, 0.0, (v - 0.5) / (v * (1.0 - v)).sqrt()] }
    }
}

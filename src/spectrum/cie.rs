//! CIE 1931 2° colour matching functions x̄, ȳ, z̄ (360–830 nm at 1 nm) and the exact
//! integrals that turn a spectrum into XYZ (CIE 015:2004, *Colorimetry*), and the luminous
//! efficacy K_m.
//!
//! The table is taken to mean the piecewise-linear function through its samples, zero
//! outside 360–830 nm. Integrals against it are computed exactly for piecewise-linear
//! integrands (3-point Gauss–Legendre on every interval between merged knots is exact for
//! the quadratic product of two linear pieces), not by a Riemann sum.

use super::data::CIE_1931_XYZ;
use glam::{DVec3, Vec3, Vec4};

/// First wavelength of the table [nm].
pub const CIE_LAMBDA_MIN: f64 = 360.0;
/// Last wavelength of the table [nm].
pub const CIE_LAMBDA_MAX: f64 = 830.0;
/// Number of 1 nm samples in the table.
pub const CIE_SAMPLES: usize = 471;

/// ∫ȳ(λ) dλ over the table [nm] (the trapezoid sum, which is the exact integral of the
/// piecewise-linear ȳ). Dividing by it gives the ∫ȳ normalisation used throughout prism:
/// X = ∫ S x̄ dλ / ∫ ȳ dλ (Y, Z alike), so a spectrum that is 1 everywhere has Y = 1, and so does
/// RGB white (1, 1, 1) in every [`super::ColorSpace`].
pub const CIE_Y_INTEGRAL: f32 = 106.856_91;
/// [`CIE_Y_INTEGRAL`] in double precision.
pub const CIE_Y_INTEGRAL_F64: f64 = 106.856_914_916_767;

/// Maximum luminous efficacy of radiation K_m [lm/W]: 683 lm/W at 555 nm, where ȳ = 1 (the SI
/// definition of the candela). Photometric quantities are K_m ∫ X_e(λ) ȳ(λ) dλ.
pub const K_M: f64 = 683.0;

/// The tabulated (x̄, ȳ, z̄) at `360 + i` nm, exactly as published.
pub fn xyz_bar_sample(i: usize) -> Option<[f64; 3]> {
    CIE_1931_XYZ.get(i).copied()
}

/// (x̄, ȳ, z̄)(λ) in double precision: linear interpolation of the 1 nm table, 0 outside.
pub fn xyz_bar_f64(lambda_nm: f64) -> DVec3 {
    if !(CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX).contains(&lambda_nm) {
        return DVec3::ZERO;
    }
    let t = lambda_nm - CIE_LAMBDA_MIN;
    let i = (t as usize).min(CIE_SAMPLES - 2);
    let f = t - i as f64;
    let a = DVec3::from_array(CIE_1931_XYZ[i]);
    let b = DVec3::from_array(CIE_1931_XYZ[i + 1]);
    a + (b - a) * f
}

/// The table in single precision, padded to four lanes, for [`xyz_bar`] (evaluated for every
/// camera sample's four wavelengths).
static CIE_1931_XYZ_F32: [Vec4; CIE_SAMPLES] = {
    let mut t = [Vec4::ZERO; CIE_SAMPLES];
    let mut i = 0;
    while i < CIE_SAMPLES {
        let [x, y, z] = CIE_1931_XYZ[i];
        t[i] = Vec4::new(x as f32, y as f32, z as f32, 0.0);
        i += 1;
    }
    t
};

/// (x̄, ȳ, z̄)(λ): linear interpolation of the 1 nm table, 0 outside 360–830 nm, in single
/// precision.
#[inline]
pub fn xyz_bar(lambda_nm: f32) -> Vec3 {
    if !(CIE_LAMBDA_MIN as f32..=CIE_LAMBDA_MAX as f32).contains(&lambda_nm) {
        return Vec3::ZERO;
    }
    let t = lambda_nm - CIE_LAMBDA_MIN as f32;
    let i = (t as usize).min(CIE_SAMPLES - 2);
    let (a, b) = (CIE_1931_XYZ_F32[i], CIE_1931_XYZ_F32[i + 1]);
    (a + (b - a) * (t - i as f32)).truncate()
}

/// Nodes and weights of 3-point Gauss–Legendre quadrature on [0, 1] (exact to degree 5).
const GAUSS3: [(f64, f64); 3] =
    [(0.112_701_665_379_258_3, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.887_298_334_620_741_7, 5.0 / 18.0)];

/// Calls `visit(λ, w)` with the quadrature nodes and weights for ∫ over [`a`, `b`] split at
/// every 1 nm table knot and at every `extra_knots` entry (the integrand's own breakpoints).
/// Exact for any integrand that is a polynomial of degree ≤ 5 between merged knots.
pub fn for_each_node(a: f64, b: f64, extra_knots: &[f64], mut visit: impl FnMut(f64, f64)) {
    if b <= a {
        return;
    }
    let mut knots: Vec<f64> = Vec::with_capacity(CIE_SAMPLES + extra_knots.len() + 2);
    knots.push(a);
    knots.push(b);
    let first = a.ceil() as i64;
    let last = b.floor() as i64;
    knots.extend((first..=last).map(|k| k as f64));
    knots.extend(extra_knots.iter().copied().filter(|k| *k > a && *k < b));
    knots.sort_by(f64::total_cmp);
    knots.dedup();
    for w in knots.windows(2) {
        let (l, h) = (w[0], w[1]);
        let len = h - l;
        if len <= 0.0 {
            continue;
        }
        for (x, wt) in GAUSS3 {
            visit(l + x * len, wt * len);
        }
    }
}

/// (∫ f x̄ dλ, ∫ f ȳ dλ, ∫ f z̄ dλ) over 360–830 nm, unnormalised [units of f · nm].
/// `knots` lists f's breakpoints so that piecewise-linear f is integrated exactly.
pub fn integrate_xyz(f: impl Fn(f64) -> f64, knots: &[f64]) -> DVec3 {
    let mut acc = DVec3::ZERO;
    for_each_node(CIE_LAMBDA_MIN, CIE_LAMBDA_MAX, knots, |l, w| {
        acc += xyz_bar_f64(l) * (f(l) * w);
    });
    acc
}

/// XYZ of the spectrum f in the ∫ȳ normalisation: X = ∫ f x̄ / ∫ ȳ (Y, Z alike).
pub fn xyz_of(f: impl Fn(f64) -> f64, knots: &[f64]) -> DVec3 {
    integrate_xyz(f, knots) / CIE_Y_INTEGRAL_F64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_integral_matches_the_table() {
        let y = integrate_xyz(|_| 1.0, &[]).y;
        assert!((y - CIE_Y_INTEGRAL_F64).abs() < 1e-9, "{y}");
        assert!((CIE_Y_INTEGRAL as f64 - y).abs() < 1e-5);
    }

    #[test]
    fn interpolation_hits_samples_and_vanishes_outside() {
        for i in [0usize, 40, 195, 470] {
            let s = xyz_bar_sample(i).unwrap();
            let v = xyz_bar_f64(360.0 + i as f64);
            assert_eq!(v.to_array(), s);
        }
        let mid = xyz_bar_f64(555.5);
        let expect = (DVec3::from_array(CIE_1931_XYZ[195]) + DVec3::from_array(CIE_1931_XYZ[196])) / 2.0;
        assert!((mid - expect).abs().max_element() < 1e-15);
        assert_eq!(xyz_bar(359.9), Vec3::ZERO);
        assert_eq!(xyz_bar(830.1), Vec3::ZERO);
        assert_eq!(xyz_bar(f32::NAN), Vec3::ZERO);
    }

    #[test]
    fn quadrature_is_exact_for_piecewise_quadratics() {
        // ∫ x̄ · (λ-500) over 360–830 equals the trapezoid-exact sum computed per interval.
        let got = integrate_xyz(|l| l - 500.0, &[]).x;
        let mut want = 0.0;
        for i in 0..CIE_SAMPLES - 1 {
            // ∫_0^1 (a + (b-a)t)(c + t) dt with c = λ_i - 500.
            let a = CIE_1931_XYZ[i][0];
            let b = CIE_1931_XYZ[i + 1][0];
            let c = 360.0 + i as f64 - 500.0;
            want += a * c + (b - a) * c / 2.0 + a / 2.0 + (b - a) / 3.0;
        }
        assert!((got - want).abs() < 1e-9 * want.abs(), "{got} {want}");
    }
}

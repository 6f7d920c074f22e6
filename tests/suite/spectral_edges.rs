//! Spectral edge cases: wavelengths at and just outside 360/830 nm, saturated and
//! out-of-gamut RGB through Jakob–Hanika and Smits upsampling, and very hot and very cold
//! blackbodies. Everything must stay finite and physically ranged.

use glam::DVec3;
use prism::spectrum::smits::{smits_spectrum, SmitsKind};
use prism::spectrum::{
    normalise_luminance, sample_visible_wavelength, visible_wavelength_pdf, xyz_bar, ColorSpace, RgbKind,
    SampledWavelengths, Spectrum, LAMBDA_MAX, LAMBDA_MIN,
};

fn next_up(v: f32) -> f32 {
    f32::from_bits(v.to_bits() + 1)
}
fn next_down(v: f32) -> f32 {
    f32::from_bits(v.to_bits() - 1)
}

/// Wavelengths a spectrum may be asked about: the ends, one ulp either side, far outside, NaN.
fn probe_wavelengths() -> Vec<f32> {
    let mut l = vec![
        LAMBDA_MIN,
        next_up(LAMBDA_MIN),
        next_down(LAMBDA_MIN),
        LAMBDA_MAX,
        next_up(LAMBDA_MAX),
        next_down(LAMBDA_MAX),
        359.0,
        831.0,
        0.0,
        -1.0,
        1e6,
        f32::INFINITY,
    ];
    l.extend((360..=830).step_by(10).map(|x| x as f32));
    l
}

#[test]
fn sampled_wavelengths_stay_inside_360_830_for_extreme_uniforms() {
    let us = [0.0f32, f32::MIN_POSITIVE, 1e-7, 0.5, next_down(1.0), 1.0];
    for &u in &us {
        for w in [SampledWavelengths::sample_uniform(u), SampledWavelengths::sample_visible(u)] {
            for (l, p) in w.lambda.iter().zip(w.pdf().to_array()) {
                assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(l), "u={u}: λ = {l}");
                assert!(p.is_finite() && p > 0.0, "u={u}: pdf({l}) = {p}");
            }
        }
        let l = sample_visible_wavelength(u);
        assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(&l), "visible sample at u={u}: {l}");
    }
    // The density is exactly 0 outside the range and positive at its ends.
    assert_eq!(visible_wavelength_pdf(next_down(LAMBDA_MIN)), 0.0);
    assert_eq!(visible_wavelength_pdf(next_up(LAMBDA_MAX)), 0.0);
    assert!(visible_wavelength_pdf(LAMBDA_MIN) > 0.0 && visible_wavelength_pdf(LAMBDA_MAX) > 0.0);
}

#[test]
fn spectra_and_matching_functions_are_finite_at_and_beyond_the_ends() {
    let space = ColorSpace::srgb();
    let spectra = [
        ("constant", Spectrum::constant(0.7)),
        ("blackbody", Spectrum::blackbody(3000.0)),
        ("D65", Spectrum::named("stdillum-D65").unwrap()),
        ("albedo rgb", Spectrum::from_rgb([0.9, 0.1, 0.05], RgbKind::Albedo, space)),
        ("illuminant rgb", Spectrum::from_rgb([0.2, 0.4, 3.0], RgbKind::Illuminant, space)),
        ("samples", Spectrum::piecewise_linear(&[360.0, 500.0, 830.0], &[0.1, 0.9, 0.3]).unwrap()),
    ];
    for l in probe_wavelengths() {
        let cmf = xyz_bar(l);
        // The tabulated z̄ carries rounding residue of −2e-21 beyond 650 nm; anything visible
        // would be a sign error.
        assert!(cmf.is_finite() && cmf.min_element() >= -1e-18, "x̄ȳz̄({l}) = {cmf}");
        if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&l) {
            assert_eq!(cmf, glam::Vec3::ZERO, "matching functions outside the table at {l}");
        }
        for (name, s) in &spectra {
            let v = s.eval(l);
            assert!(v.is_finite() && v >= 0.0, "{name}({l}) = {v}");
        }
    }
    // NaN wavelengths must not poison anything either.
    for (name, s) in &spectra {
        let v = s.eval(f32::NAN);
        assert!(v.is_nan() || (v.is_finite() && v >= 0.0), "{name}(NaN) = {v}");
    }
}

/// Saturated colours on the sRGB gamut boundary, and colours outside it (negative, > 1, huge,
/// non-finite).
fn hard_rgbs() -> Vec<[f32; 3]> {
    vec![
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1e-7, 0.0],
        [0.0, 0.0, 1e-7],
        [1.0, 1.0, 1.0],
        [-0.5, 0.3, 0.8],
        [1.5, 0.2, -0.1],
        [2.0, 2.0, 2.0],
        [1e6, 1.0, 0.0],
        [1e30, 1e30, 1e-30],
        [f32::INFINITY, 0.5, 0.1],
        [f32::NAN, 0.5, 0.1],
        [-1.0, -1.0, -1.0],
    ]
}

fn check(name: &str, rgb: [f32; 3], s: &Spectrum, max: Option<f64>) {
    for l in (360..=830).map(|l| l as f64) {
        let v = s.eval_f64(l);
        assert!(v.is_finite() && v >= 0.0, "{name} {rgb:?} at {l} nm: {v}");
        if let Some(m) = max {
            assert!(v <= m + 1e-9, "{name} {rgb:?} at {l} nm: reflectance {v} > {m}");
        }
    }
    let xyz = s.to_xyz_f64();
    assert!(xyz.is_finite() && xyz.min_element() >= 0.0, "{name} {rgb:?}: XYZ {xyz}");
}

#[test]
fn jakob_hanika_upsampling_is_finite_and_reflectances_stay_in_0_1() {
    for space in ["srgb", "rec2020", "aces2065-1"].map(|n| ColorSpace::by_name(n).unwrap()) {
        for rgb in hard_rgbs() {
            check("albedo", rgb, &Spectrum::from_rgb(rgb, RgbKind::Albedo, space), Some(1.0));
            check("unbounded", rgb, &Spectrum::from_rgb(rgb, RgbKind::Unbounded, space), None);
            check("illuminant", rgb, &Spectrum::from_rgb(rgb, RgbKind::Illuminant, space), None);
        }
    }
}

#[test]
fn jakob_hanika_reflectance_reproduces_in_gamut_boundary_colours() {
    // Colours on the gamut boundary are reachable only in the sigmoid's limit; the fit must still
    // come close (≤ 0.02 per channel), not collapse to grey.
    let space = ColorSpace::srgb();
    for rgb in [[1.0f32, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 0.0], [0.0, 1.0, 1.0]] {
        let s = Spectrum::from_rgb(rgb, RgbKind::Albedo, space);
        let back = prism::spectrum::roundtrip::reflectance_rgb(&s, space);
        let err = (back - DVec3::from(rgb.map(|v| v as f64))).abs().max_element();
        assert!(err < 0.02, "{rgb:?} → {back}");
    }
}

#[test]
fn smits_upsampling_is_finite_and_reflectances_stay_in_0_1() {
    for space in ["srgb", "rec2020"].map(|n| ColorSpace::by_name(n).unwrap()) {
        for rgb in hard_rgbs() {
            let rgb64 = rgb.map(|v| v as f64);
            // Smits' reflectance basis is built for [0, 1]; clamp before, as the renderer does.
            let clamped = rgb64.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 });
            check("smits reflectance", rgb, &smits_spectrum(clamped, SmitsKind::Reflectance, space), Some(1.0));
            // The illuminant form is unbounded but must be finite and non-negative for any input.
            check("smits illuminant", rgb, &smits_spectrum(rgb64, SmitsKind::Illumination, space), None);
        }
    }
}

#[test]
fn very_hot_blackbodies_are_finite_and_approach_the_planckian_limit() {
    // As T → ∞ the visible spectrum tends to Rayleigh–Jeans, B ∝ λ⁻⁴, whose chromaticity is
    // (x, y) ≈ (0.2399, 0.2342) (the end of the Planckian locus).
    let rj = Spectrum::piecewise_linear_f64(
        (360..=830).map(|l| l as f64).collect(),
        (360..=830).map(|l| (l as f64 / 560.0).powi(-4)).collect(),
    )
    .unwrap()
    .to_xyz_f64();
    let rj_xy = (rj.x / rj.element_sum(), rj.y / rj.element_sum());
    for t in [1e5f32, 1e6, 1e7, 1e8, 1e9] {
        let s = Spectrum::blackbody(t);
        for l in probe_wavelengths() {
            let v = s.eval(l);
            assert!(v.is_finite() && (0.0..=1.0).contains(&v), "{t} K at {l}: {v}");
        }
        let xyz = s.to_xyz_f64();
        assert!(xyz.is_finite() && xyz.y > 0.0, "{t} K: {xyz}");
        let xy = (xyz.x / xyz.element_sum(), xyz.y / xyz.element_sum());
        if t >= 1e7 {
            assert!((xy.0 - rj_xy.0).abs() < 1e-3 && (xy.1 - rj_xy.1).abs() < 1e-3, "{t} K: xy {xy:?} vs {rj_xy:?}");
        }
        let n = normalise_luminance(s);
        let y = n.to_xyz_f64().y;
        assert!((y - 1.0).abs() < 1e-4, "{t} K normalised: Y = {y}");
    }
}

#[test]
fn very_cold_blackbodies_are_finite_and_normalise_or_vanish() {
    // Below ~300 K almost nothing is visible: Planck's exponential underflows f32 (and, at a few
    // kelvin, f64). The normalised spectrum must then be either Y = 1 and finite, or all zero —
    // never ∞ or NaN from dividing by an underflowed luminance.
    for t in [1.0f32, 5.0, 20.0, 50.0, 80.0, 100.0, 120.0, 150.0, 200.0, 250.0, 300.0] {
        let s = Spectrum::blackbody(t);
        for l in probe_wavelengths() {
            let v = s.eval(l);
            assert!(v.is_finite() && (0.0..=1.0).contains(&v), "{t} K at {l}: {v}");
        }
        let n = normalise_luminance(s);
        let mut all_zero = true;
        // A unit-luminance 50 K body is astronomically bright in the infrared (∞ in f32 at 1 mm);
        // only wavelengths the renderer can sample matter.
        for l in probe_wavelengths().into_iter().filter(|&l| l <= 831.0) {
            let v = n.eval(l);
            assert!(v.is_finite() && v >= 0.0, "{t} K normalised at {l}: {v}");
            all_zero &= v == 0.0 || !(LAMBDA_MIN..=LAMBDA_MAX).contains(&l);
        }
        let y = n.to_xyz_f64().y;
        assert!(y.is_finite(), "{t} K normalised: Y = {y}");
        assert!(all_zero || (y - 1.0).abs() < 1e-3, "{t} K normalised: Y = {y}");
    }
    // Warmer is redder: x grows as T falls toward the infrared.
    let x = |t: f32| {
        let c = Spectrum::blackbody(t).to_xyz_f64();
        c.x / c.element_sum()
    };
    assert!(x(300.0) > x(1000.0) && x(1000.0) > x(3000.0), "{} {} {}", x(300.0), x(1000.0), x(3000.0));
}

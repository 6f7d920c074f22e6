//! Reproduces every value in tests/data/colour_truth.json (colour-science 0.4.7, copied from
//! the project's shared data) within the tolerances the file states.

use super::blackbody::blackbody_radiance;
use super::cie::{xyz_bar_sample, CIE_Y_INTEGRAL_F64};
use super::{fit_albedo, ColorSpace, RgbKind, Spectrum};
use glam::{DMat3, DVec3};
use serde_json::Value;

fn truth() -> Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/colour_truth.json");
    serde_json::from_str(&std::fs::read_to_string(path).expect("truth file")).expect("json")
}

fn vec3(v: &Value) -> DVec3 {
    DVec3::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap())
}

/// The file's linear-sRGB convention: colour-science's 4-decimal matrix (row-major).
fn colour_xyz_to_srgb(t: &Value) -> DMat3 {
    let m = &t["conventions"]["M_XYZ_to_linear_sRGB"];
    DMat3::from_cols(vec3(&m[0]), vec3(&m[1]), vec3(&m[2])).transpose()
}

#[test]
fn cmf_table_values_exact() {
    let t = truth();
    let vals = t["a_cmf_cie1931_2deg"]["values"].as_object().unwrap();
    assert!(vals.len() >= 8);
    for (wl, v) in vals {
        let i = wl.parse::<usize>().unwrap() - 360;
        let got = xyz_bar_sample(i).unwrap();
        for k in 0..3 {
            assert!((got[k] - v[k].as_f64().unwrap()).abs() <= 1e-9, "{wl} {k}");
        }
    }
}

#[test]
fn d65_xyz_xy_and_srgb() {
    let t = truth();
    let b = &t["b_D65"];
    let xyz = Spectrum::named("stdillum-D65").unwrap().to_xyz_f64();
    let xyz = xyz / xyz.y;
    // "1e-4 absolute (integration of the 1 nm tables)": the 1 nm alternate. The headline
    // value uses colour's 5 nm ASTM E308 tables cut at 780 nm and differs from both by
    // 1.5e-4 in Z (reported in docs/colour.md).
    let one_nm = &b["alternates_XYZ_Y1"]["sd_to_XYZ_integration, D65 Sprague-aligned to 360-830/1nm"];
    assert!((xyz - vec3(one_nm)).abs().max_element() < 1e-4, "{xyz}");
    let s = xyz.element_sum();
    assert!((xyz.x / s - b["xy"][0].as_f64().unwrap()).abs() < 1e-4);
    assert!((xyz.y / s - b["xy"][1].as_f64().unwrap()).abs() < 1e-4);
    // Linear sRGB: against colour's matrix applied to the same 1 nm XYZ.
    let m = colour_xyz_to_srgb(&t);
    let rgb = m * xyz;
    assert!((rgb - m * vec3(one_nm)).abs().max_element() < 1e-4, "{rgb}");
    // The headline 5 nm value is within 2e-4 (its Z differs by 1.5e-4, see above).
    assert!((rgb - vec3(&b["linear_sRGB"])).abs().max_element() < 2e-4, "{rgb}");
}

#[test]
fn blackbody_xyz_xy_and_srgb() {
    let t = truth();
    let m = colour_xyz_to_srgb(&t);
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    for (temp, v) in t["c_blackbody"]["values"].as_object().unwrap() {
        let kelvin: f64 = temp.parse().unwrap();
        // The normalised quantities: our SI-2019 Planck through the exact integral.
        let xyz = Spectrum::blackbody(kelvin as f32).to_xyz_f64();
        let y1 = xyz / xyz.y;
        let want = vec3(&v["XYZ_Y1"]);
        for k in 0..3 {
            assert!(rel(y1[k], want[k]) < 1e-4, "{temp} XYZ_Y1[{k}] {} {}", y1[k], want[k]);
        }
        let s = y1.element_sum();
        assert!(rel(y1.x / s, v["xy"][0].as_f64().unwrap()) < 1e-4);
        assert!(rel(y1.y / s, v["xy"][1].as_f64().unwrap()) < 1e-4);
        let rgb = m * y1;
        let want = vec3(&v["linear_sRGB_of_XYZ_Y1"]);
        for k in 0..3 {
            assert!(rel(rgb[k], want[k]) < 1e-4, "{temp} rgb[{k}]");
        }
        // Absolute: colour-science's constants (c₁ = 3.741771e-16 W m², c₂ = 0.014388 m K,
        // /π, per nm) differ from SI 2019 by ~1.5e-4 relative in the exponent, so use
        // theirs here; our SI Planck is checked against Stefan–Boltzmann in blackbody.rs.
        let planck = |l: f64| {
            let lm = l * 1e-9;
            3.741771e-16 / std::f64::consts::PI / lm.powi(5) / ((0.014388 / (lm * kelvin)).exp() - 1.0) * 1e-9
        };
        let abs = super::cie::integrate_xyz(planck, &[]) / CIE_Y_INTEGRAL_F64;
        let want = vec3(&v["XYZ_Enorm_absolute"]);
        for k in 0..3 {
            assert!(rel(abs[k], want[k]) < 1e-4, "{temp} abs[{k}] {} {}", abs[k], want[k]);
        }
        // And ours agrees with theirs to the constants' difference.
        let ours = super::cie::integrate_xyz(|l| blackbody_radiance(l, kelvin), &[]) / CIE_Y_INTEGRAL_F64;
        assert!(rel(ours.y, want.y) < 5e-4);
    }
}

/// Linear sRGB (derived matrix) of a reflectance lit by the space's illuminant.
pub(crate) fn albedo_roundtrip(s: &Spectrum, cs: &ColorSpace) -> DVec3 {
    let lit = s.clone().product(cs.illuminant.clone());
    cs.xyz_to_rgb_f64 * lit.to_xyz_f64()
}

#[test]
fn jakob_hanika_roundtrip_on_truth_triplets() {
    let t = truth();
    let cs = ColorSpace::srgb();
    for row in t["d_rgb_upsampling_roundtrip"]["rows"].as_array().unwrap() {
        let rgb = vec3(&row["rgb_in_linear"]);
        let s = Spectrum::from_rgb(rgb.as_vec3().to_array(), RgbKind::Albedo, cs);
        let err = (albedo_roundtrip(&s, cs) - rgb).abs().max_element();
        let theirs = row["jakob2019_D65"]["max_abs_err"].as_f64().unwrap();
        assert!(err < 1e-3, "{rgb}: {err} (colour-science {theirs})");
    }
}

#[test]
fn jakob_hanika_matches_colour_science_reflectance() {
    // For (0.6, 0.2, 0.5) colour-science's fit (D65, 5 nm CMFs) has R at 400/500/600/700 nm;
    // ours differs only by the integration grid, so the curves agree closely.
    let t = truth();
    let row = &t["d_rgb_upsampling_roundtrip"]["rows"][0];
    let fit = fit_albedo([0.6, 0.2, 0.5], ColorSpace::srgb());
    let want = &row["jakob2019_D65"]["R_at_[400,500,600,700]"];
    for (k, l) in [400.0, 500.0, 600.0, 700.0].iter().enumerate() {
        let got = fit.poly.eval_f64(*l);
        assert!((got - want[k].as_f64().unwrap()).abs() < 5e-3, "{l}: {got}");
    }
}

#[test]
fn white_upsamples_to_flat() {
    for n in ColorSpace::names() {
        let cs = ColorSpace::by_name(n).unwrap();
        let s = Spectrum::from_rgb([1.0, 1.0, 1.0], RgbKind::Albedo, cs);
        for l in (360..=830).step_by(5) {
            assert_eq!(s.eval(l as f32), 1.0, "{n} {l}");
        }
        // Flat 1 reflects the illuminant itself, so the round trip is exactly the RGB of the
        // illuminant SPD, off (1,1,1) only by the SPD-vs-published-white-xy mismatch.
        let rt = albedo_roundtrip(&s, cs);
        let white = cs.xyz_to_rgb_f64 * cs.illuminant.to_xyz_f64();
        assert!((rt - white).abs().max_element() < 1e-12, "{n} {rt}");
        assert!((rt - DVec3::ONE).abs().max_element() < 1e-3, "{n} {rt}");
    }
}

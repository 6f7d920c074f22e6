//! The probabilities with which the power and BVH light samplers choose lights, against those
//! pbrt-v4's samplers give, derived here from pbrt-v4's definitions (`src/pbrt/lights.cpp`,
//! `lightsamplers.cpp`, `util/spectrum.h`): a 2700 K and a 6500 K blackbody sphere light of the
//! same luminance, an RGB-coloured area light (a quad of two triangles) and an RGB point light.
//!
//! pbrt-v4 divides a light's spectrum S by ∫ S ȳ (a sum over whole nm of 360–830 nm; for an RGB
//! illuminant, by that of its colour space's illuminant alone) and keeps it as a table at each
//! whole nm of 360–830 nm (`DenselySampledSpectrum`), so:
//! - `PowerLightSampler` weighs a light by the mean over λᵢ of `SampleVisible(0.5)` of
//!   Φ(λᵢ)/p(λᵢ), Φ(λ) = π A S(λ) for an area light, 4π S(λ) × scale for a point light;
//! - `BVHLightSampler` weighs a node by Φ cos θ' / d² with Φ = π A MaxValue(S) for an area light
//!   and 4π MaxValue(S) × scale for a point light, MaxValue the largest value of the table.
//!
//! Far above the lights (in a medium, so no cosine at the point), every node's cos θ' is 1 and
//! its d² the same to 10⁻⁶: the BVH then chooses each light in proportion to its Φ.

use crate::common::pbrt_scene;
use glam::{Vec2, Vec3};
use prism::accel::AccelKind;
use prism::light::{Light, LightSampleContext};
use prism::spectrum::cie::xyz_bar_sample;
use prism::spectrum::{ColorSpace, RgbKind, Spectrum};
use std::f64::consts::PI;

const SPHERE_RADIUS: f64 = 0.05;
const QUAD_SIDE: f64 = 0.2;
const QUAD_RGB: [f32; 3] = [4.0, 1.0, 0.25];
const POINT_RGB: [f32; 3] = [0.2, 0.5, 1.0];
const POINT_SCALE: f64 = 0.01;

fn scene(kind: &str) -> String {
    let h = QUAD_SIDE / 2.0;
    let [r, g, b] = QUAD_RGB;
    let [pr, pg, pb] = POINT_RGB;
    format!(
        "Integrator \"path\" \"string lightsampler\" \"{kind}\"\nCamera \"perspective\"\nWorldBegin\n\
         AttributeBegin Translate -1 0 0 AreaLightSource \"diffuse\" \"blackbody L\" [2700]\n\
           Shape \"sphere\" \"float radius\" {SPHERE_RADIUS} AttributeEnd\n\
         AttributeBegin Translate -0.5 0 0 AreaLightSource \"diffuse\" \"blackbody L\" [6500]\n\
           Shape \"sphere\" \"float radius\" {SPHERE_RADIUS} AttributeEnd\n\
         AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [{r} {g} {b}]\n\
           Shape \"trianglemesh\" \"point3 P\" [0.4 {m} 0  0.6 {m} 0  0.6 {h} 0  0.4 {h} 0]\n\
           \"integer indices\" [0 1 2 0 2 3] AttributeEnd\n\
         LightSource \"point\" \"point3 from\" [1 0 0] \"rgb I\" [{pr} {pg} {pb}] \"float scale\" {POINT_SCALE}\n",
        m = -h,
    )
}

/// Which of the four sources a light of the scene belongs to.
fn source(l: &Light) -> usize {
    match l {
        Light::Sphere(s) if s.center.x < -0.75 => 0,
        Light::Sphere(_) => 1,
        Light::Point(_) => 3,
        _ => 2,
    }
}

/// Each source's probability of being chosen at `ctx`: the sum over its lights of the pmf
/// [`prism::scene::Scene::sample_light`] reports, found by sweeping u over [0, 1).
fn chosen(kind: &str, ctx: &LightSampleContext) -> [f64; 4] {
    let scene = pbrt_scene(&scene(kind), AccelKind::Obvhs);
    let mut pmf = vec![0.0f64; scene.lights().len()];
    let n = 100_000;
    for k in 0..n {
        let u = Vec2::new((k as f32 + 0.5) / n as f32, 0.5);
        let (id, _, p, _) = scene.sample_light(ctx, u).expect("a light");
        pmf[id as usize] = p as f64;
    }
    let mut by_source = [0.0; 4];
    for (l, p) in scene.lights().iter().zip(pmf) {
        by_source[source(l)] += p;
    }
    by_source
}

/// Planck's law [W/(sr·m²·m)] at `nm` and temperature `kelvin`.
fn planck(nm: f64, kelvin: f64) -> f64 {
    let (h, c, k) = (6.62606957e-34, 299792458.0, 1.3806488e-23);
    let l = nm * 1e-9;
    2.0 * h * c * c / (l.powi(5) * ((h * c / (l * k * kelvin)).exp() - 1.0))
}

/// ȳ at each whole nm of 360–830 nm (the CIE 1931 table, as pbrt-v4's).
fn y_bar(nm: u32) -> f64 {
    xyz_bar_sample((nm - 360) as usize).unwrap()[1]
}

/// A spectrum as pbrt-v4 keeps a light's: divided by ∫ ȳ `normaliser` over whole nm, at whole nm.
fn pbrt_table(s: impl Fn(f64) -> f64, normaliser: impl Fn(f64) -> f64) -> Vec<f64> {
    let y: f64 = (360..=830).map(|l| y_bar(l) * normaliser(l as f64)).sum();
    (360..=830).map(|l| s(l as f64) / y).collect()
}

/// pbrt-v4's `SampledWavelengths::SampleVisible(0.5)`: λᵢ and p(λᵢ) for uᵢ = 0.5, 0.75, 1, 0.25.
fn visible_wavelengths() -> [(f64, f64); 4] {
    [0.5, 0.75, 1.0, 0.25].map(|u: f64| {
        let l = 538.0 - 138.888889 * (0.85691062 - 1.82750197 * u).atanh();
        (l, 0.0039398042 / (0.0072 * (l - 538.0)).cosh().powi(2))
    })
}

/// The power sampler's weight of a table (Φ(λ)/p(λ) averaged, without the geometric factor).
fn visible_mean(table: &[f64]) -> f64 {
    visible_wavelengths().iter().map(|&(l, p)| table[(l.round() as usize).clamp(360, 830) - 360] / p).sum::<f64>() / 4.0
}

fn max_value(table: &[f64]) -> f64 {
    table.iter().copied().fold(0.0, f64::max)
}

/// The four sources' spectra as pbrt-v4 tables, and their geometric factors π A or 4π scale.
fn sources() -> [(Vec<f64>, f64); 4] {
    let space = ColorSpace::srgb();
    let white = Spectrum::from_rgb([1.0; 3], RgbKind::Illuminant, space);
    let rgb = |c: [f32; 3]| {
        let s = Spectrum::from_rgb(c, RgbKind::Illuminant, space);
        pbrt_table(|l| s.eval_f64(l), |l| white.eval_f64(l))
    };
    let sphere_area = 4.0 * PI * SPHERE_RADIUS * SPHERE_RADIUS;
    [
        (pbrt_table(|l| planck(l, 2700.0), |l| planck(l, 2700.0)), PI * sphere_area),
        (pbrt_table(|l| planck(l, 6500.0), |l| planck(l, 6500.0)), PI * sphere_area),
        (rgb(QUAD_RGB), PI * QUAD_SIDE * QUAD_SIDE),
        (rgb(POINT_RGB), 4.0 * PI * POINT_SCALE),
    ]
}

fn normalised(w: [f64; 4]) -> [f64; 4] {
    let sum: f64 = w.iter().sum();
    w.map(|x| x / sum)
}

fn assert_close(what: &str, got: [f64; 4], want: [f64; 4]) {
    for i in 0..4 {
        assert!((got[i] - want[i]).abs() < 2e-3 * want[i], "{what}: source {i}: {got:?} vs pbrt-v4's {want:?}");
    }
}

#[test]
fn the_power_sampler_chooses_lights_as_pbrt_v4s() {
    let want = normalised(sources().map(|(table, k)| k * visible_mean(&table)));
    let got = chosen("power", &LightSampleContext::medium(Vec3::new(0.0, 0.0, 1000.0)));
    assert_close("power", got, want);
}

#[test]
fn the_bvh_sampler_chooses_lights_as_pbrt_v4s() {
    let want = normalised(sources().map(|(table, k)| k * max_value(&table)));
    let got = chosen("bvh", &LightSampleContext::medium(Vec3::new(0.0, 0.0, 1000.0)));
    assert_close("bvh", got, want);
    // The blackbodies of equal luminance differ in max/∫ȳ: 2700 K peaks beyond 830 nm.
    assert!(want[0] > 1.2 * want[1], "{want:?}");
}

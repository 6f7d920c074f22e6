//! An image infinite light whose transform is not a rotation (pbrt-v4's `sssdragon` scenes give
//! theirs a projective row): pbrt-v4 turns sampled map directions into rendering space by the
//! transform's upper 3 × 3, unnormalised, and looks escaped rays up through its inverse's; with
//! a projective row and its default rendering space (world space moved to the camera) the two
//! disagree. prism reproduces the estimate pbrt-v4's path tracer then makes, derived here from
//! its definition: the NEE sample's BSDF cosine and density scale with the length of the
//! unnormalised direction, the light's density does not.

use crate::common::tmpdir;
use crate::equal_area_envmap::equal_area_map;
use glam::Vec3;
use prism::accel::AccelKind;
use prism::integrator::Integrator;
use prism::light::photometry::lumens_per_unit_y;
use prism::measure::irradiance;
use prism::pbrt::parse_str;
use std::f64::consts::PI;
use std::path::Path;

/// Irradiance [film Y] on a patch at the origin facing +z, under a constant equal-area map of
/// radiance Y = 1 whose transform has the projective row (0, 0, k), the camera at (0, 0, 2),
/// `options` first in the file; its standard error, and the warnings.
fn upward_irradiance(dir: &Path, k: f32, options: &str) -> (f64, f64, Vec<String>) {
    let text = format!(
        "{options}\nLookAt 0 0 2  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nAttributeBegin\n\
         ConcatTransform [1 0 0 0  0 1 0 0  0 0 1 {k}  0 0 0 1]\n\
         LightSource \"infinite\" \"string filename\" \"white.exr\"\nAttributeEnd\n"
    );
    let opts = prism::pbrt::ParseOptions { base_dir: Some(dir.to_path_buf()), ..Default::default() };
    let (desc, mut warnings) = parse_str(&text, &opts).unwrap();
    let (b, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    let scene = b.build(AccelKind::Obvhs).unwrap();
    let integ = Integrator { max_depth: 1, ..Default::default() };
    let e = irradiance(&scene, &integ, Vec3::ZERO, Vec3::Z, 40_000, 5).illuminance;
    let k = lumens_per_unit_y() as f64;
    (e.mean / k, e.std_err / k, warnings.into_iter().map(|w| w.message).collect())
}

/// pbrt-v4's expected irradiance ÷ π on that patch (radiance 1 everywhere) when sampled map
/// directions ω = (x, y, z) become v = (x, y, s z): NEE draws ω uniformly (density P = 1/4π),
/// shades along v/|v| with cosine c and BSDF density b = c/π both times |v|; BSDF sampling draws
/// cosine-weighted directions and weighs them against P. Power heuristic, midpoint quadrature
/// over z (both integrands depend on z alone).
fn pbrt_v4_expectation(s: f64) -> f64 {
    let p = 1.0 / (4.0 * PI);
    let power = |a: f64, b: f64| a * a / (a * a + b * b);
    let n = 100_000;
    let mid = |i: usize, lo: f64, hi: f64| lo + (hi - lo) * (i as f64 + 0.5) / n as f64;
    // NEE, over ω uniform on the sphere: z uniform on [−1, 1]. The estimate, divided by π:
    // w(P, |v| b) · (1/π) · |v| c / P = w(P/|v|, b) · c / (π P/|v|).
    let nee: f64 = (0..n)
        .map(|i| {
            let z = mid(i, -1.0, 1.0);
            let len = (1.0 - z * z + s * s * z * z).sqrt();
            let c = s * z / len;
            if c <= 0.0 {
                return 0.0;
            }
            let (pl, b) = (p / len, c / PI);
            power(pl, b) * c / (PI * pl)
        })
        .sum::<f64>()
        / n as f64;
    // BSDF sampling: ∫ w(b, P) (1/π) c dω over the hemisphere = 2 ∫₀¹ w(μ/π, P) μ dμ.
    let bsdf: f64 = (0..n).map(|i| mid(i, 0.0, 1.0)).map(|mu| power(mu / PI, p) * mu).sum::<f64>() * 2.0 / n as f64;
    nee + bsdf
}

#[test]
fn a_projective_light_transform_renders_pbrt_v4s_estimate() {
    let d = tmpdir("envmap-transform");
    prism::image::write(&d.join("white.exr"), &equal_area_map(16, |_, _, _| [1.0, 1.0, 1.0])).unwrap();
    assert!((pbrt_v4_expectation(1.0) - 1.0).abs() < 1e-6, "a rotation gives the true irradiance");
    // The camera at z = 2 and k = 0.45 make the sampled directions (x, y, 0.1 z).
    let expected = pbrt_v4_expectation(1.0 - 2.0 * 0.45);
    assert!((expected - 0.9157).abs() < 1e-3, "the estimate differs measurably from the truth: {expected}");
    let (e, se, warnings) = upward_irradiance(&d, 0.45, "");
    assert!(se < 0.01 * e, "noise {se} of {e}");
    assert!((e / PI - expected).abs() < 4.0 * se / PI, "E/π = {} ± {} against pbrt-v4's {expected}", e / PI, se / PI);
    assert!(warnings.iter().any(|w| w.contains("not a rotation")), "{warnings:?}");
    // In pbrt-v4's "world" rendering space the two maps agree: the true irradiance π.
    let (e, se, _) = upward_irradiance(&d, 0.45, "Option \"string rendercoordsys\" \"world\"");
    assert!((e - PI).abs() < 4.0 * se, "world space: E = {e} ± {se}, not π");
    // A rotation (k = 0) is read as before, without a warning.
    let (e, se, warnings) = upward_irradiance(&d, 0.0, "");
    assert!((e - PI).abs() < 4.0 * se, "rotation: E = {e} ± {se}, not π");
    assert!(warnings.is_empty(), "{warnings:?}");
}

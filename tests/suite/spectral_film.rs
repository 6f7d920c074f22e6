//! pbrt-v4's `spectral` film: the buckets of a white Lambertian plane under a blackbody equal
//! the blackbody's bucket means (Planck's law and colour-science's luminance of it), the buckets
//! integrated against the CIE 1931 curves give the image's R, G, B, and parts merge to the
//! single render. Files are read with the `exr` crate, not prism's reader.

use crate::common::{prism, render_halves_and_merge, stderr, tmpdir};
use std::collections::HashMap;
use std::path::Path;

/// Image size [pixels].
const N: usize = 24;
/// The blackbody's temperature [K] and the light's scale.
const T: f64 = 5000.0;
const SCALE: f64 = 3.0;

/// An OpenEXR file's channels by name and its header's text attributes.
fn read_exr(path: &Path) -> (HashMap<String, Vec<f32>>, HashMap<String, String>) {
    use exr::meta::attribute::AttributeValue;
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .unwrap();
    let texts = image
        .attributes
        .other
        .iter()
        .chain(&image.layer_data.attributes.other)
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((k.to_string(), t.to_string())),
            _ => None,
        })
        .collect();
    let list = image.layer_data.channel_data.list;
    (list.into_iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect(), texts)
}

/// A camera looking along +z at a white Lambertian plane at z = 5 (reflectance 1 at every
/// wavelength) lit head-on by a distant blackbody light of irradiance `SCALE` (its spectrum
/// normalised to luminance 1, as pbrt-v4's), one bounce: every visible point has radiance
/// L(λ) = SCALE · B(λ, T) / (π Y_B).
fn scene(film: &str) -> String {
    format!(
        "LookAt 0 0 0  0 0 1  0 1 0\n\
         Camera \"perspective\" \"float fov\" 30\n\
         Sampler \"independent\" \"integer pixelsamples\" 64\n\
         PixelFilter \"box\"\n\
         Film \"spectral\" \"integer xresolution\" {N} \"integer yresolution\" {N} \"bool savefp16\" false {film}\n\
         Integrator \"path\" \"integer maxdepth\" 1\n\
         WorldBegin\n\
         LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 1] \"blackbody L\" {T} \"float scale\" {SCALE}\n\
         Material \"diffuse\" \"spectrum reflectance\" [300 1 900 1]\n\
         Shape \"trianglemesh\" \"point3 P\" [-4 -4 5  4 -4 5  4 4 5  -4 4 5] \"integer indices\" [0 2 1 0 3 2]\n"
    )
}

/// Renders `text` to `name.exr` in `dir` with extra arguments.
fn render(dir: &Path, name: &str, text: &str, args: &[&str]) -> (HashMap<String, Vec<f32>>, HashMap<String, String>) {
    let file = dir.join(format!("{name}.pbrt"));
    std::fs::write(&file, text).unwrap();
    let out = dir.join(format!("{name}.exr"));
    let o = prism().arg("render").arg(&file).arg("-o").arg(&out).args(args).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    read_exr(&out)
}

/// colour-science's values for the blackbody at `T` (tests/data/colour_truth.json): Y of
/// B/π·10⁻⁹ (Planck's law with c₁ = 3.741771e-16 W·m², c₂ = 0.014388 m·K) in the ∫ȳ
/// normalisation, and the linear sRGB of the blackbody scaled to Y = 1; and its XYZ-to-sRGB
/// matrix (rows).
fn colour_truth() -> (f64, [f64; 3], [[f64; 3]; 3]) {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/colour_truth.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let bb = &v["c_blackbody"]["values"][format!("{T}")];
    let f = |x: &serde_json::Value| x.as_f64().unwrap();
    let rgb = &bb["linear_sRGB_of_XYZ_Y1"];
    let m = &v["conventions"]["M_XYZ_to_linear_sRGB"];
    (
        f(&bb["XYZ_Enorm_absolute"][1]),
        [f(&rgb[0]), f(&rgb[1]), f(&rgb[2])],
        std::array::from_fn(|r| std::array::from_fn(|c| f(&m[r][c]))),
    )
}

/// Planck's law as colour-science evaluates it for its table: B(λ, T)/π·10⁻⁹ [W·sr⁻¹·m⁻²·nm⁻¹].
fn planck(lambda_nm: f64) -> f64 {
    let l = lambda_nm * 1e-9;
    3.741771e-16 / (l.powi(5) * ((0.014388 / (l * T)).exp() - 1.0)) / std::f64::consts::PI * 1e-9
}

/// The mean of L(λ) = SCALE · B(λ)/(π Y_B) over [a, b] [nm] (midpoint rule, 0.01 nm steps).
fn radiance_mean(a: f64, b: f64, y_b: f64) -> f64 {
    let steps = ((b - a) * 100.0).round() as usize;
    let h = (b - a) / steps as f64;
    let sum: f64 = (0..steps).map(|k| planck(a + (k as f64 + 0.5) * h)).sum();
    SCALE / std::f64::consts::PI * sum / steps as f64 / y_b
}

/// Mean and standard error of the mean of pixel values.
fn mean_se(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let v: Vec<f64> = v.collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The bucket channels' names in wavelength order with their intervals, as the test expects
/// pbrt-v4 to name them.
fn buckets(n: usize, lo: f64, hi: f64) -> Vec<(String, f64, f64)> {
    let w = (hi - lo) / n as f64;
    (0..n)
        .map(|i| {
            let centre = format!("{:.3}", lo + w * (i as f64 + 0.5)).replace('.', ",");
            (format!("S0.{centre}nm"), lo + w * i as f64, lo + w * (i + 1) as f64)
        })
        .collect()
}

#[test]
fn buckets_are_the_blackbodys_bucket_means() {
    let dir = tmpdir("spectral-closed-form");
    let (y_b, rgb_truth, _) = colour_truth();
    for (name, film, n, lo, hi) in [
        ("default", "", 16, 360.0, 830.0),
        ("narrow", "\"integer nbuckets\" 3 \"float lambdamin\" 450 \"float lambdamax\" 650", 3, 450.0, 650.0),
    ] {
        let (c, attrs) = render(&dir, name, &scene(film), &[]);
        assert_eq!(c.len(), 3 + n, "{name}: channels {:?}", c.keys().collect::<Vec<_>>());
        assert_eq!(attrs.get("spectralLayoutVersion").map(String::as_str), Some("1.0"));
        assert_eq!(attrs.get("emissiveUnits").map(String::as_str), Some("W.m^-2.sr^-1"));
        for (channel, a, b) in buckets(n, lo, hi) {
            let values = c.get(&channel).unwrap_or_else(|| panic!("{name}: no channel {channel}"));
            let (mean, se) = mean_se(values.iter().map(|&v| v as f64));
            let expected = radiance_mean(a, b, y_b);
            // Planck's constants and the luminance normalisation agree with prism's to ~1e-4.
            let tol = 4.0 * se + 2e-4 * expected;
            assert!((mean - expected).abs() < tol, "{name} {channel}: {mean} ± {se}, expected {expected}");
        }
        if name == "default" {
            // The full range: R, G, B are the blackbody's colour (uniform wavelengths, same sums).
            for (k, ch) in ["R", "G", "B"].iter().enumerate() {
                let (mean, se) = mean_se(c[*ch].iter().map(|&v| v as f64));
                let expected = SCALE / std::f64::consts::PI * rgb_truth[k];
                assert!((mean - expected).abs() < 4.0 * se + 1e-3 * expected, "{ch}: {mean} ± {se} vs {expected}");
            }
        }
    }
}

#[test]
fn buckets_integrated_against_cie_1931_give_the_rgb_channels() {
    let dir = tmpdir("spectral-energy");
    let (_, _, m) = colour_truth();
    // 10 nm buckets: the radiance is nearly constant within each; 256 samples leave no bucket
    // of a pixel without a wavelength (each bucket gets one with probability 0.085 per sample).
    let (c, _) = render(&dir, "energy", &scene("\"integer nbuckets\" 47"), &["--spp", "256"]);
    let bins = buckets(47, 360.0, 830.0);
    // ∫ x̄ȳz̄ over each bucket (1 nm midpoint rule on the CIE table), over ∫ ȳ.
    let bar = |l: f64| prism::spectrum::xyz_bar(l as f32).as_dvec3();
    let y_integral: f64 = (0..470).map(|k| bar(360.5 + k as f64).y).sum();
    let weights: Vec<glam::DVec3> = bins
        .iter()
        .map(|(_, a, b)| {
            (0..(b - a).round() as usize).map(|k| bar(a + k as f64 + 0.5)).sum::<glam::DVec3>() / y_integral
        })
        .collect();
    // The discretisation: what the buckets' exact means give against the exact integral.
    let (y_b, _, _) = colour_truth();
    let bucketed: glam::DVec3 = bins.iter().zip(&weights).map(|((_, a, b), w)| *w * radiance_mean(*a, *b, y_b)).sum();
    let fine: glam::DVec3 = (0..4700)
        .map(|k| {
            let l = 360.0 + 0.1 * k as f64;
            bar(l + 0.05) * radiance_mean(l, l + 0.1, y_b) * 0.1
        })
        .sum::<glam::DVec3>()
        / y_integral;
    let rgb =
        |xyz: glam::DVec3| -> [f64; 3] { std::array::from_fn(|r| m[r][0] * xyz.x + m[r][1] * xyz.y + m[r][2] * xyz.z) };
    let bias = {
        let (a, b) = (rgb(bucketed), rgb(fine));
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    };
    for (k, ch) in ["R", "G", "B"].iter().enumerate() {
        // Per pixel: the buckets' RGB minus the channel's; pixels are independent.
        let diffs = (0..N * N).map(|p| {
            let xyz: glam::DVec3 = bins.iter().zip(&weights).map(|((name, _, _), w)| *w * c[name][p] as f64).sum();
            rgb(xyz)[k] - c[*ch][p] as f64
        });
        let (d, se) = mean_se(diffs);
        let scale = c[*ch].iter().map(|&v| v as f64).sum::<f64>() / (N * N) as f64;
        assert!(
            (d - bias[k]).abs() < 4.0 * se + 1e-3 * scale,
            "{ch}: buckets − channel = {d} ± {se} (discretisation {}), channel mean {scale}",
            bias[k]
        );
    }
}

#[test]
fn buckets_pbrt_v4_cannot_render_are_errors_at_their_parameter() {
    let dir = tmpdir("spectral-errors");
    for (film, param) in [
        ("\"integer nbuckets\" 0", "nbuckets"),
        ("\"float lambdamin\" 300", "lambdamin"),
        ("\"float lambdamax\" 900", "lambdamax"),
        ("\"float lambdamin\" 600 \"float lambdamax\" 500", "lambdamin"),
    ] {
        let file = dir.join("bad.pbrt");
        std::fs::write(&file, scene(film)).unwrap();
        let o = prism().arg("render").arg(&file).arg("-o").arg(dir.join("bad.exr")).output().unwrap();
        let e = stderr(&o);
        assert!(!o.status.success() && e.contains(param) && e.contains("bad.pbrt:5:"), "{film}: {e}");
        assert!(!dir.join("bad.exr").exists());
    }
    // More buckets than memory holds: one line saying so, no panic, no file.
    std::fs::write(dir.join("huge.pbrt"), scene("\"integer nbuckets\" 2147483647")).unwrap();
    let o = prism().arg("render").arg(dir.join("huge.pbrt")).arg("-o").arg(dir.join("huge.exr")).output().unwrap();
    let e = stderr(&o);
    assert!(!o.status.success() && e.contains("GiB") && !e.contains("panicked"), "{e}");
    assert!(!dir.join("huge.exr").exists());
}

#[test]
fn a_spectral_film_to_png_writes_rgb_with_a_warning_and_parts_merge_to_the_whole() {
    let dir = tmpdir("spectral-parts");
    let file = dir.join("s.pbrt");
    std::fs::write(&file, scene("\"integer nbuckets\" 8")).unwrap();
    let png = dir.join("s.png");
    let o = prism().arg("render").arg(&file).arg("-o").arg(&png).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("Film \"spectral\""), "{}", stderr(&o));

    let whole = dir.join("whole.exr");
    let o = prism().arg("render").arg(&file).arg("-o").arg(&whole).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let merged = render_halves_and_merge(&dir, &file);
    let ((a, _), (b, attrs)) = (read_exr(&whole), read_exr(&merged));
    assert_eq!(a.len(), 3 + 8);
    assert_eq!(attrs.get("spectralLayoutVersion").map(String::as_str), Some("1.0"));
    for (name, values) in &a {
        for (k, (x, y)) in values.iter().zip(&b[name]).enumerate() {
            assert!((x - y).abs() <= 1e-6 * x.abs().max(1e-3), "{name}[{k}]: {x} vs {y}");
        }
    }
}
